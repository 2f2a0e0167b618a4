#include "ecoterra/eco/outputs.hpp"

namespace ecoterra::eco {

namespace {
/// The year's water budget columns (over the domain, mm).
std::vector<Column<YearRow>> water_columns() {
    using R = YearRow;
    return {
        column("rain_mm", &R::rain_mm, "mm", "rain over the domain in the year"),
        column("evaporation_mm", &R::evaporation_mm, "mm",
               "soil and open-water evaporation in the year"),
        column("transpiration_mm", &R::transpiration_mm, "mm",
               "transpiration supplied in the year (plants and ground layer)"),
        column("interception_mm", &R::interception_mm, "mm",
               "rain held on the canopy and evaporated in the year"),
        column("runoff_out_mm", &R::runoff_out_mm, "mm",
               "surface water that left through the domain edge in the year"),
        column("drainage_out_mm", &R::drainage_out_mm, "mm",
               "water drained below the root zone out of the domain in the year"),
        column("groundwater_out_mm", &R::groundwater_out_mm, "mm",
               "groundwater that left through fixed-head edges in the year"),
        column("recharge_mm", &R::recharge_mm, "mm", "percolation to the water table in the year")};
}

/// The dead wood's yearly columns (deadwood.hpp).
std::vector<Column<YearRow>> dead_wood_columns() {
    using R = YearRow;
    return {column("snags_per_ha", &R::snags_per_ha, "1/ha",
                   "standing dead trees (DBH >= vegetation.deadwood.min_dbh_m) at year end"),
            column("logs_per_ha", &R::logs_per_ha, "1/ha",
                   "fallen dead stems and the slash of cut trees at year end"),
            column("snag_volume_m3_per_ha", &R::snag_volume_m3_per_ha, "m3/ha",
                   "stem volume of the snags at year end"),
            column("log_volume_m3_per_ha", &R::log_volume_m3_per_ha, "m3/ha",
                   "volume of the logs at year end"),
            column("deadwood_volume_class1_m3_per_ha", &R::deadwood_volume_class1_m3_per_ha,
                   "m3/ha", "snags and logs of decay class 1 (sound; > 90 % of the mass left)"),
            column("deadwood_volume_class2_m3_per_ha", &R::deadwood_volume_class2_m3_per_ha,
                   "m3/ha", "decay class 2 (70-90 % of the mass left)"),
            column("deadwood_volume_class3_m3_per_ha", &R::deadwood_volume_class3_m3_per_ha,
                   "m3/ha", "decay class 3 (40-70 %)"),
            column("deadwood_volume_class4_m3_per_ha", &R::deadwood_volume_class4_m3_per_ha,
                   "m3/ha", "decay class 4 (20-40 %)"),
            column("deadwood_volume_class5_m3_per_ha", &R::deadwood_volume_class5_m3_per_ha,
                   "m3/ha", "decay class 5 (< 20 %)"),
            column("deadwood_stock_kg", &R::deadwood_stock_kg, "kg",
                   "dry mass of the snags and logs at year end"),
            column("deadwood_input_kg", &R::deadwood_input_kg, "kg",
                   "stem mass of the trees that became snags in the year (part of dead_carbon_kg, "
                   "or allometric in light-only runs)"),
            column("deadwood_decay_kg", &R::deadwood_decay_kg, "kg",
                   "mass the snags and logs lost to decay in the year"),
            column("snags_fallen", &R::snags_fallen, "1",
                   "snags that fell and became logs in the year", ColumnType::int64),
            column("stumps_per_ha", &R::stumps_per_ha, "1/ha",
                   "stumps of cut trees at year end (not in snags_per_ha)"),
            column("stump_volume_m3_per_ha", &R::stump_volume_m3_per_ha, "m3/ha",
                   "volume of the stumps at year end (not in snag_volume_m3_per_ha)"),
            column("harvested_stems", &R::harvested_stems, "1",
                   "trees cut by management operations in the year", ColumnType::int64),
            column("harvested_basal_area_m2_per_ha", &R::harvested_basal_area_m2_per_ha, "m2/ha",
                   "basal area of the trees cut in the year"),
            column("harvested_wood_kg", &R::harvested_wood_kg, "kg",
                   "stem dry mass of the cut trees taken out of the stand (their stumps and slash "
                   "stay as dead wood)"),
            column("storm_wind_m_per_s", &R::storm_wind_m_per_s, "m/s",
                   "the year's storm: highest hourly mean wind 10 m above the canopy's zero-plane "
                   "displacement (0: windthrow off)"),
            column("windthrow_uprooted", &R::windthrow_uprooted, "1",
                   "trees the year's storm uprooted", ColumnType::int64),
            column("windthrow_broken", &R::windthrow_broken, "1", "trees the year's storm broke",
                   ColumnType::int64),
            column("windthrow_basal_area_m2_per_ha", &R::windthrow_basal_area_m2_per_ha, "m2/ha",
                   "basal area of the trees the year's storm felled"),
            column("root_plates_per_ha", &R::root_plates_per_ha, "1/ha",
                   "root plates of uprooted trees standing at year end"),
            column("storm_severe", &R::storm_severe, "1",
                   "1 when the year's storm was a drawn severe convective storm (downburst), 0 "
                   "otherwise",
                   ColumnType::int64)};
}
} // namespace

const std::vector<Column<YearRow>>& yearly_columns() {
    using R = YearRow;
    static const std::vector<Column<R>> c = [] {
        std::vector<Column<R>> v = {
            column("year", &R::year, "1", "completed simulation years", ColumnType::int64),
            column("basal_area_m2_per_ha", &R::basal_area_m2_per_ha, "m2/ha",
                   "basal area of stems at breast height"),
            column("stems_per_ha", &R::stems_per_ha, "1/ha",
                   "stems that reached breast height (1.3 m)"),
            column("mean_dbh_m", &R::mean_dbh_m, "m",
                   "arithmetic mean trunk diameter at breast height"),
            column("quadratic_mean_dbh_m", &R::quadratic_mean_dbh_m, "m",
                   "quadratic mean diameter Dq"),
            column("reineke_sdi_per_ha", &R::reineke_sdi_per_ha, "1/ha",
                   "Reineke stand density index N (Dq/25.4 cm)^1.605"),
            column("live_plants", &R::live_plants, "1",
                   "live plants, including those below breast height", ColumnType::int64),
            column("births", &R::births, "1", "recruits established this year", ColumnType::int64),
            column("deaths_starvation", &R::deaths_starvation, "1",
                   "deaths by an exhausted carbohydrate reserve", ColumnType::int64),
            column("deaths_age", &R::deaths_age, "1", "deaths at the species' maximum age",
                   ColumnType::int64),
            column("deaths_background", &R::deaths_background, "1", "deaths by the background rate",
                   ColumnType::int64),
            column("deaths_suppression", &R::deaths_suppression, "1",
                   "deaths by growth suppression (low growth efficiency)", ColumnType::int64),
            column("deaths_overlap", &R::deaths_overlap, "1", "light-only deaths by crown overlap",
                   ColumnType::int64),
            column("seeds_dispersed", &R::seeds_dispersed, "1", "seeds produced and dispersed",
                   ColumnType::int64),
            column("seeds_lost_outside", &R::seeds_lost_outside, "1",
                   "seeds that landed outside the terrain", ColumnType::int64),
            column("production_kg", &R::production_kg, "kg", "carbohydrate produced"),
            column("maintenance_respiration_kg", &R::maintenance_respiration_kg, "kg",
                   "maintenance respiration"),
            column("growth_respiration_kg", &R::growth_respiration_kg, "kg",
                   "growth respiration of new wood"),
            column("recruit_carbon_kg", &R::recruit_carbon_kg, "kg",
                   "carbohydrate of new recruits (from outside the balance)"),
            column("dead_carbon_kg", &R::dead_carbon_kg, "kg",
                   "wood and reserve of plants that died"),
            column("wood_stock_kg", &R::wood_stock_kg, "kg",
                   "stem dry mass of live plants at year end"),
            column("reserve_stock_kg", &R::reserve_stock_kg, "kg",
                   "carbohydrate reserve of live plants at year end"),
            column(
                "carbon_residual_kg", &R::carbon_residual_kg, "kg",
                "stock change (live plants and dead wood) - (production - respiration - turnover + "
                "recruits - dead + dead wood's input - its decay); round-off only"),
            column("transpiration_demand_mm", &R::transpiration_demand_mm, "mm",
                   "plant water demand over the domain"),
            column("transpiration_supplied_mm", &R::transpiration_supplied_mm, "mm",
                   "plant water supplied by the soil"),
            column("turnover_kg", &R::turnover_kg, "kg",
                   "carbohydrate turned over by plants at their maximum stem diameter, and the "
                   "litter of rebuilt leaves and fine roots (vegetation.growth = "
                   "light_and_turnover)"),
            column("shrubs_per_ha", &R::shrubs_per_ha, "1/ha",
                   "live shrubs (not in the tree metrics)"),
            column("ground_cover_fraction", &R::ground_cover_fraction, "1",
                   "mean cover of the ground layer (grasses and herbs) at year end, 0..1"),
            column("ground_transpiration_demand_mm", &R::ground_transpiration_demand_mm, "mm",
                   "the ground layer's water demand over the domain"),
            column("ground_transpiration_supplied_mm", &R::ground_transpiration_supplied_mm, "mm",
                   "the ground layer's water supplied (from above its roots)"),
        };
        for (auto& d : water_columns()) v.push_back(std::move(d));
        for (auto& d : dead_wood_columns()) v.push_back(std::move(d));
        return v;
    }();
    return c;
}

} // namespace ecoterra::eco
