#pragma once
// The model's yearly report as a catalogue: each column's name, unit, type and description written
// once (docs/parameters.md lists them, `ecoterra describe outputs` prints them). The run file's
// other groups are the run layer's (run/records.hpp).
//
//   /series/yearly/*           yearly_columns(), one row per simulated year (YearRow)
//   /series/daily/*            hydro::daily_budget_columns(), one row per day
#include "ecoterra/catalog.hpp"
#include "ecoterra/eco/plant.hpp"
#include "ecoterra/eco/species.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace ecoterra::eco {

/// One year of the yearly series.
struct YearRow {
    double year = 0, basal_area_m2_per_ha = 0, stems_per_ha = 0, mean_dbh_m = 0,
           quadratic_mean_dbh_m = 0, reineke_sdi_per_ha = 0, live_plants = 0, births = 0,
           deaths_starvation = 0, deaths_age = 0, deaths_background = 0, deaths_suppression = 0,
           deaths_overlap = 0, seeds_dispersed = 0, seeds_lost_outside = 0, production_kg = 0,
           maintenance_respiration_kg = 0, growth_respiration_kg = 0, recruit_carbon_kg = 0,
           dead_carbon_kg = 0, wood_stock_kg = 0, reserve_stock_kg = 0, carbon_residual_kg = 0,
           transpiration_demand_mm = 0, transpiration_supplied_mm = 0, shrubs_per_ha = 0,
           ground_cover_fraction = 0, ground_transpiration_demand_mm = 0,
           ground_transpiration_supplied_mm = 0, turnover_kg = 0;
    // Dead wood at year end, and the year's fluxes (deadwood.hpp).
    double snags_per_ha = 0, logs_per_ha = 0, snag_volume_m3_per_ha = 0, log_volume_m3_per_ha = 0,
           deadwood_volume_class1_m3_per_ha = 0, deadwood_volume_class2_m3_per_ha = 0,
           deadwood_volume_class3_m3_per_ha = 0, deadwood_volume_class4_m3_per_ha = 0,
           deadwood_volume_class5_m3_per_ha = 0, deadwood_stock_kg = 0, deadwood_input_kg = 0,
           deadwood_decay_kg = 0, snags_fallen = 0, stumps_per_ha = 0, stump_volume_m3_per_ha = 0;
    // The year's harvest (management.hpp).
    double harvested_stems = 0, harvested_basal_area_m2_per_ha = 0, harvested_wood_kg = 0;
    // The year's storm (windthrow.hpp) and the root plates at year end.
    double storm_wind_m_per_s = 0, windthrow_uprooted = 0, windthrow_broken = 0,
           windthrow_basal_area_m2_per_ha = 0, root_plates_per_ha = 0, storm_severe = 0;
    // The year's water budget: the daily series summed over the year's days, mm.
    double rain_mm = 0, evaporation_mm = 0, transpiration_mm = 0, interception_mm = 0,
           runoff_out_mm = 0, drainage_out_mm = 0, groundwater_out_mm = 0, recharge_mm = 0;
};
const std::vector<Column<YearRow>>& yearly_columns();

} // namespace ecoterra::eco
