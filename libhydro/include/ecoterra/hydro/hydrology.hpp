#pragma once
// The daily soil-water, runoff, catchment and evapotranspiration model (paper 002 s4), with a
// water budget that must close.
//
// State: volumetric soil water theta per cell over a root zone of depth d (m), above the wilting
// point and at most the porosity (field capacity under paper 002's `drainage = none`); the
// surface layer's depletion De (FAO-56); standing water in catchments; optionally a water table.
// One day (HydrologyModel::step), composed of the process kernels of kernels.hpp in this order:
//  1. lake losses: standing water (as yesterday's equilibrium left it) evaporates at the open-water
//     rate (Penman E0 over its wet cells) and infiltrates into the soil under it;
//  2. rain on standing water joins it;
//  3. interception (`gash`): the canopy of each dry cell holds and evaporates part of the rain;
//  4. the rest splits into runoff and infiltration (runoff coefficients or SCS curve number);
//     water above the soil's ceiling runs off (or, under paper 002 with groundwater, percolates);
//  5. run-on, highest cells first (D8 or MFD), then the standing water comes to equilibrium
//     (catchments grow, shrink, spill, merge, split);
//  6. evapotranspiration: FAO-56 two-stage soil evaporation plus transpiration, each limited
//     (`fao56`), or the larger of the surface's Penman demand and the plants' request
//     (`paper002`); never below the wilting point;
//  7. drainage below the root zone at K(theta) (`gravity`), to the water table or out;
//  8. groundwater (optional, groundwater.hpp), seepage joining the standing water;
//  9. the budget closes.
// Budget (m3, whole domain): rain = evaporation + transpiration + interception + runoff out +
// drainage out + groundwater out + d(soil) + d(surface) + d(groundwater) + residual.
// docs/hydrology.md s4 gives the equations and their sources.
#include "ecoterra/catalog.hpp"
#include "ecoterra/hydro/catchments.hpp"
#include "ecoterra/hydro/groundwater.hpp"
#include "ecoterra/hydro/penman.hpp"
#include "ecoterra/hydro/runoff.hpp"
#include "ecoterra/hydro/soil.hpp"
#include "ecoterra/hydro/weather.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

namespace ecoterra::hydro {

struct SoilColumns;
enum class RunoffMethod { coefficients, curve_number };
/// How the soil loses water to the air: paper 002 (the larger of the surface's Penman demand and
/// the plants' request) or FAO-56's dual coefficients (two-stage soil evaporation plus
/// transpiration, each limited).
enum class EvapotranspirationMethod { paper002, fao56 };
/// The surface layer's total evaporable water TEW: FAO-56 eq. 73 alone (`eq73`), or eq. 73 scaled
/// by min(1, sqrt(ET0 / 5 mm/day)) on each day (`sqrt_et0`): less of the layer dries under a low
/// evaporative demand, as FAO-56's initial-stage procedure has it (ch. 6, Figs. 29-30: TEW =
/// min(28 mm, 13 sqrt(ET0)) on medium and fine soils, min(15 mm, 7 sqrt(ET0)) on coarse ones).
enum class EvaporableWater { eq73, sqrt_et0 };
/// Water below the root zone: none (paper 002: the root zone holds at most field capacity, the
/// excess runs off) or gravity drainage at K(theta).
enum class DrainageMethod { none, gravity };
enum class InterceptionMethod { none, gash };

struct HydrologyOptions {
    double root_zone_depth_m = 1.0;
    double initial_saturation = 1.0; ///< theta0 = WP + s (FC - WP), s in [0, 1]
    Routing routing = Routing::d8;
    RunoffMethod runoff = RunoffMethod::coefficients;
    double flat_slope = 0.005;            ///< rise/run below which a cell is flat
    double grass_density_threshold = 0.3; ///< vegetation density at which the surface is grass
    et::WindFunction wind = et::WindFunction::penman1948;
    bool groundwater = false;
    double specific_yield = 0.2;       ///< m3/m3
    double aquifer_thickness_m = 20.0; ///< from the impermeable base to the surface
    double initial_water_table_depth_m = 5.0;
    GroundwaterSolver groundwater_solver = GroundwaterSolver::implicit;
    int groundwater_steps_per_day = 2;          ///< TR-BDF2 steps a day (implicit solver)
    double groundwater_head_tolerance_m = 1e-5; ///< of a stage's solve (implicit solver)
    int aquifer_cell_factor = 1; ///< terrain cells to an aquifer cell's side (groundwater.hpp)
    EvapotranspirationMethod evapotranspiration = EvapotranspirationMethod::fao56;
    DrainageMethod drainage = DrainageMethod::gravity;
    InterceptionMethod interception = InterceptionMethod::gash;
    double surface_layer_depth_m = 0.10; ///< Ze, FAO-56 eq. 73 (0.10-0.15 m)
    EvaporableWater evaporable_water = EvaporableWater::sqrt_et0;
    /// The top of the root zone whose water sets the soil's strength for vehicles (the critical
    /// layer: 6-12 in, Priddy & Willoughby 2004; 0-6 in for light vehicles); 0: none (the soil's
    /// strength reads the root zone's water, and the hydrology skips the layer's update).
    double critical_layer_depth_m = 0.30;
    double kc_max = 1.2;             ///< FAO-56 eq. 72 at the standard climate
    double depletion_fraction = 0.5; ///< p, FAO-56 Table 22 (trees 0.5-0.7)
    double canopy_storage_per_lai_mm = 0.2;
    double wet_canopy_evaporation_ratio = 0.05; ///< Gash E/R, medfate's default
    double canopy_extinction = 0.5; ///< cover = 1 - exp(-k LAI), hydrology without plants
    double budget_tolerance = 1e-9; ///< |cumulative residual| / cumulative throughput
    void validate() const;
};

/// The scene keys of section "hydrology" (every key, unit, default and range).
const ParamCatalog<HydrologyOptions>& hydrology_catalog();

/// One day's water over the domain, m3.
struct DailyFluxes {
    double rain = 0, evaporation = 0, transpiration = 0, infiltration = 0, runoff_out = 0;
    double groundwater_out = 0, recharge = 0;
    double interception = 0, drainage_out = 0;
    double d_soil = 0, d_surface = 0, d_groundwater = 0;
    double residual = 0;
};

/// One row of the daily water-budget series written by every run: the calendar, then the budget
/// terms in mm/day over the whole domain.
struct BudgetRow {
    double day = 0, year = 0, day_of_year = 0;
    double rain_mm = 0, evaporation_mm = 0, transpiration_mm = 0, interception_mm = 0,
           infiltration_mm = 0, runoff_out_mm = 0, drainage_out_mm = 0, groundwater_out_mm = 0,
           recharge_mm = 0, d_soil_storage_mm = 0, d_surface_storage_mm = 0,
           d_groundwater_storage_mm = 0, residual_mm = 0;
};
const std::vector<Column<BudgetRow>>& daily_budget_columns();
BudgetRow daily_budget_row(int day, const DayWeather& w, const DailyFluxes& f, double domain_m2);

/// The ET functions' view of a generated or observed day at the climate's site.
et::DailyWeather et_weather(const DayWeather& w, const Climate& c);

class HydrologyModel {
public:
    HydrologyModel(const RasterD& dem, const SoilMap& soil, const RasterD& vegetation_density,
                   const HydrologyOptions& opt, const Climate& climate);
    ~HydrologyModel();

    /// Advances one day. `transpiration_mm` (per cell, may be null) is the water the plants ask
    /// for; `leaf_area_index` and `cover` (per cell, m2/m2 and 0..1, both or neither) today's
    /// leaves, for interception and the energy split (without them, both follow the vegetation
    /// density). Throws Error if the budget breaks.
    DailyFluxes step(const DayWeather& w, const RasterD* transpiration_mm = nullptr,
                     const RasterD* leaf_area_index = nullptr, const RasterD* cover = nullptr);

    const SoilMap& soil() const { return m_soil; }
    const RasterD& soil_moisture() const { return m_theta; }
    /// Water content of the critical layer (the top critical_layer_depth_m of the root zone),
    /// m3/m3: what the soil's strength for vehicles is read from (the root zone's water with
    /// critical_layer_depth_m = 0).
    const RasterD& critical_layer_moisture() const {
        return has_critical_layer() ? m_top_theta : m_theta;
    }
    bool has_critical_layer() const { return m_opt.critical_layer_depth_m > 0; }
    RasterD surface_water_depth() const { return m_catch.depth_map(); }
    Raster<std::int32_t> catchment_ids() const { return m_catch.id_map(); }
    /// Depth of the water table below the surface, m (NaN without groundwater).
    RasterD water_table_depth() const;
    /// Water removed from each cell's soil by the last step's transpiration, mm.
    const RasterD& transpiration_supplied_mm() const { return m_transp_supplied; }
    const Catchments& catchments() const { return m_catch; }
    double cumulative_residual_m3() const { return m_cum_residual; }
    double cumulative_throughput_m3() const { return m_cum_throughput; }
    double soil_storage_m3() const;
    double groundwater_storage_m3() const;
    int day() const { return m_day; }

    /// Replaces the vegetation-density raster (0..1) and recomputes the runoff coefficients; the
    /// ecosystem calls it as canopies change.
    void set_vegetation_density(const RasterD& density);
    const RasterD& vegetation_density() const { return m_veg; }

    /// Checkpoint of the evolving state (soil water, catchments, groundwater, budget totals).
    /// load_state() expects a model built from the same terrain, soil and options.
    void save_state(ArchiveWriter& a) const;
    /// `version` 1 (before the surface layer) derives the surface layer's depletion from theta;
    /// before version 3 the critical layer starts as wet as the root zone.
    void load_state(ArchiveReader& a, std::uint32_t version = kStateVersion);
    static constexpr std::uint32_t kStateVersion = 3;
    /// Depletion of the evaporating surface layer, mm (FAO-56 De; zero under paper 002).
    const RasterD& surface_depletion_mm() const { return m_de; }

private:
    void update_runoff_coefficients();
    /// The surface layer's limits and the drainage exponent per cell, from the soil.
    void init_soil_layers();
    /// Today's leaf area and cover: the plants' or the vegetation density's.
    void leaves_of_the_day(const RasterD* leaf_area_index, const RasterD* cover);
    /// Steps 6 and 6b (evapotranspiration, drainage) under the chosen methods and, without
    /// groundwater, step 9 and the soil's storage (soil_day_end), a block of cells at a time.
    /// Returns the sum of the water contents at the day's end (NaN with groundwater, whose
    /// exchange comes first: the caller then runs soil_day_end).
    double soil_day(DailyFluxes& f, const SoilColumns& soil, double e0_mm, double et0_mm,
                    const et::DailyWeather& dw, const double* request_mm,
                    const double* intercepted_m, std::vector<double>* recharge);
    /// Step 9 over the cells [begin, end) (critical_layer_range, with a critical layer) and the
    /// sum of their water contents, in cell order, added to `theta_sum`.
    void soil_day_end(std::int64_t begin, std::int64_t end, double& theta_sum);
    /// Step 9 over the cells [begin, end): the critical layer follows the day (m_theta_start: the
    /// root zone's water at the day's start, m_theta_wet: after the rain, m_theta_et: after
    /// evapotranspiration).
    void critical_layer_range(std::int64_t begin, std::int64_t end);
    /// Step 8: storage changes (soil1: the soil's at the day's end), the residual and the
    /// cumulative check.
    void close_budget(DailyFluxes& f, const DayWeather& w, double soil0, double soil1, double surf0,
                      double gw0, double lost0);
    RasterD m_dem;
    SoilMap m_soil;
    RasterD m_veg;
    HydrologyOptions m_opt;
    Climate m_climate;
    Catchments m_catch;
    RunoffTable m_table;
    RasterD m_theta, m_slope, m_coef, m_transp_supplied;
    std::vector<std::int64_t> m_order;        ///< every cell after its higher neighbours
    std::vector<double> m_runoff, m_recharge; ///< per-cell scratch of a step, m3
    RasterD m_de;                             ///< surface-layer depletion, mm
    RasterD m_top_theta;                      ///< the critical layer's water content, m3/m3
    std::vector<double> m_theta_start, m_theta_wet, m_theta_et; ///< the day's stages, m3/m3
    std::vector<float> m_tew, m_rew, m_drain_exponent; ///< per cell: TEW, REW (mm), 3 + 2/lambda
    std::vector<double> m_scratch; ///< 1 per cell: the drainage passes' intermediate contents
    std::vector<double> m_kr, m_lai, m_cover, m_intercepted;
    /// The factor on m_tew on a day of FAO-56 reference ET `et0_mm` (evaporable_water; 1 without
    /// FAO-56).
    double tew_scale(double et0_mm) const;
    bool m_leaves_from_density = false; ///< m_lai and m_cover hold the density's leaves
    const double *m_day_lai = nullptr, *m_day_cover = nullptr; ///< today's leaves, per cell
    std::unique_ptr<Groundwater> m_gw;
    double m_area;
    double m_cum_residual = 0, m_cum_throughput = 0;
    int m_day = 0;
    /// The root zone's storage at the end of the last step (m3), which soil_storage_m3 returns
    /// until theta changes: step() sums the same blocks in the same order, so the same bits
    /// without another pass over the cells. Only step() changes theta (and load_state); NaN while
    /// it is not known.
    double m_soil_storage_end_m3 = std::nan("");
};

} // namespace ecoterra::hydro
