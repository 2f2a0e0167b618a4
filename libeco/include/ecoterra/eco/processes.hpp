#pragma once
// The plant processes as kernels over the population (population.hpp): each a function over
// explicit inputs that adds its fluxes and counts to a PlantSums passed in, so that a test can
// drive it alone and the sums are taken in one fixed order (plant order) whatever the thread
// count. Ecosystem::step_day and the year end compose them (ecosystem.hpp), as
// hydro::HydrologyModel::step composes the water kernels (hydro/kernels.hpp).
//
// Daily, coupled mode:
//   plant_water_demand      demand = transpiration per leaf area x leaf area x phen x ET0, m3
//   ground_water_request    the ground layer's demand, at most the water above its roots, m3
//   (hydrology)             supplies each cell's request without drawing below the wilting point
//   supply_fractions        the share of each plant's demand its root cells supplied
//   carbon_balance          production, respiration, allocation (growth.hpp); starvation
//   ground_environment      the ground layer's light, water and ponding per cell
// Every canopy interval (and at each year end):
//   refresh_structure       wood -> diameter -> height, crown and leaf area (allometry)
//   Canopy::refresh         crowns, roots, shading, the crowns' shade per hydrology cell
// Year end, coupled mode:
//   ageing_and_mortality    age, growth efficiency, death by age, background, suppression
//   seed_dispersal          seeds of mature plants, dispersed and established (Seedbed)
//   background_arrivals     arrivals from outside at each species' rate, established
// Year end, light-only mode (Deussen et al. 1998, MAVS):
//   light_only_growth, light_only_arrivals, overlap_thinning
// Both modes: vegetation_density for the hydrology; close_carbon_budget.
#include "ecoterra/eco/canopy.hpp"
#include "ecoterra/eco/deadwood.hpp"
#include "ecoterra/eco/diagnosis.hpp"
#include "ecoterra/eco/ground_layer.hpp"
#include "ecoterra/eco/population.hpp"
#include "ecoterra/eco/roots.hpp"
#include "ecoterra/eco/scene_config.hpp"
#include "ecoterra/hydro/catchments.hpp"
#include "ecoterra/hydro/soil.hpp"
#include "ecoterra/random.hpp"

#include <optional>
#include <vector>

namespace ecoterra::eco {

/// What the plant processes add up over a year: counts, carbon (kg) and water (m3).
struct PlantSums {
    double births = 0, deaths_starvation = 0, deaths_age = 0, deaths_background = 0,
           deaths_suppression = 0, deaths_overlap = 0, seeds = 0, seeds_lost = 0;
    double production = 0, maintenance = 0, growth_resp = 0, recruit_carbon = 0, dead_carbon = 0,
           turnover = 0;
    double demand_m3 = 0, supplied_m3 = 0;
    double ground_demand_m3 = 0, ground_supplied_m3 = 0;
};

/// The soil's suitability for a species at a soil cell: texture factor x pH factor (growth.hpp).
double soil_suitability(const Species& s, const hydro::SoilMap& soil, int i, int j);

/// The root-zone water the plant processes read: relative extractable water and the water above
/// the wilting point.
struct SoilWater {
    const RasterD& theta; ///< volumetric water content, m3/m3
    const hydro::SoilMap& soil;
    /// Relative extractable soil water of a cell, (theta - wp) / (fc - wp).
    double relative(int i, int j) const;
};

// --- daily, coupled ----------------------------------------------------------------------------

/// Each living plant's transpiration demand, m3 per day (`phen` per species, `et0_m` in m); with
/// light_and_turnover in proportion to the light on its crown (1 - shade fraction).
void plant_water_demand(const Population& pop, const std::vector<Species>& species,
                        const std::vector<double>& phen, double et0_m, GrowthModel model,
                        std::vector<double>& demand_m3);

/// The ground layer's demand per hydrology cell (`demand_m3`) and what it asks of the soil
/// (`request_m3`: at most the water above the wilting point within its roots and the root zone),
/// m3; the request is added to `cell_request_m3`. Without a ground layer both are left empty.
void ground_water_request(const GroundLayer& ground, const std::vector<Species>& species,
                          const std::vector<double>& phen, double et0_m, const SoilWater& water,
                          double root_zone_depth_m, double cell_area_m2,
                          std::vector<double>& demand_m3, std::vector<double>& request_m3,
                          std::vector<double>& cell_request_m3);

/// Supply ratio per hydrology cell (supplied / requested, 1 where nothing was asked) and the share
/// of each plant's demand met (the mean ratio over its root cells).
void supply_fractions(const RootCells& roots, const RasterD& request_mm, const RasterD& supplied_mm,
                      std::vector<double>& ratio, std::vector<double>& fraction);

/// The day's temperature and phenology per species.
struct DayClimate {
    std::vector<double> phen;  ///< leaf-on fraction per species
    std::vector<double> ftemp; ///< temperature factor f_T per species
    double q10 = 1;            ///< Q10^((T - 20)/10)
};
DayClimate day_climate(const std::vector<Species>& species, int doy, double tmean_c);

/// The day's carbohydrate balance of every living plant (growth.hpp: carbon_day) with the growth
/// percentage light (or shade, by `model`) x water x soil factors and, by `model`, the tissue cost;
/// the year's growth-percentage sum; the water demand and supply sums; starvation (`alive` cleared,
/// counted). Plants in parallel, sums in plant order.
void carbon_balance(Population& pop, const std::vector<Species>& species, const DayClimate& day,
                    const std::vector<double>& fraction, const std::vector<double>& demand_m3,
                    GrowthModel model, PlantSums& sums);

/// The ground layer's state of each hydrology cell for a step: crown shade, relative water,
/// ponding and, with `ratio` (coupled), the share of its demand supplied.
void ground_environment(const std::vector<double>& cell_shade, const SoilWater& water,
                        const hydro::Catchments& lakes, const std::vector<double>* ratio,
                        const std::vector<double>& demand_m3, const std::vector<double>& request_m3,
                        std::vector<GroundCell>& env);

// --- canopy ------------------------------------------------------------------------------------

/// Coupled mode: each plant's diameter from its wood (the inverse of the stem mass), then its
/// height, crown and leaf area (times crown_leaf_factor of its last shade fraction under
/// light_and_turnover). Objects keep their size.
void refresh_structure(Population& pop, const std::vector<Species>& species,
                       GrowthModel model = GrowthModel::paper002);

/// The crowns on the plant grid and what is derived from them: roots per hydrology cell, each
/// plant's shade fraction, the ground shade and the crowns' shade per hydrology cell.
struct Canopy {
    GridSpec plant_grid;
    CellMap map;
    CrownSet crowns;
    RootCells roots;
    RasterD ground_shade;           ///< on the plant grid, 0..1
    std::vector<double> cell_shade; ///< crown shade per hydrology cell, 0..1

    /// Crowns and roots from the population's positions and crown radii.
    void rebuild(const Population& pop);
    /// rebuild(), then shading (canopy.hpp) into pop.shade_fraction and the ground shade, then
    /// the cell shade. Each crown's leaf area index is its species' times crown_leaf_factor of
    /// its last shade fraction under `model`.
    void refresh(Population& pop, const std::vector<Species>& species, ShadingMode mode,
                 double extinction, GrowthModel model = GrowthModel::paper002);
    /// The mean ground shade of each hydrology cell's plant cells.
    void shade_per_cell();
    /// Canopy cover per hydrology cell for the runoff and surface ET: the crowns' cover, and with
    /// a ground layer 1 - (1 - crown)(1 - ground cover).
    RasterD vegetation_density(const GroundLayer& ground, const GridSpec& hydro_grid) const;
};

// --- demography --------------------------------------------------------------------------------

/// Makes new plants: id, position on the terrain, size from the allometry and the soil factor.
struct Nursery {
    const std::vector<Species>& species;
    const RasterD& dem;
    const hydro::SoilMap& soil;
    Competition competition;
    std::int64_t& next_id;
    /// A plant of species `sp` at (x, y) m with diameter `dbh_m` (coupled: its wood and initial
    /// reserve; light-only: a seedling of no diameter and height; objects at full size).
    Plant make(std::uint16_t sp, double x, double y, double dbh_m) const;
};

/// Forestry's top height: the mean height of the 100 tallest trees a hectare (at least one tree;
/// shrubs and objects left out), 0 without trees.
double top_height_m(const Population& pop, const std::vector<Species>& species, double area_ha);

/// The light a seedbed cell receives from the gap it lies in: the mean of 1 - ground shade over
/// a square window of half-width `half_width_m` around it (its part inside the grid). A gap
/// narrower than the canopy is tall lets little light down to the ground, however open its own
/// cell (Canham 1988, the gap light index); the seedbed uses half the top height.
RasterD gap_light(const RasterD& ground_shade, double half_width_m);

/// Where a seed may establish: enough light through the crowns and the ground layer, enough
/// soil water, no standing water, and then a draw against the germination probability x soil
/// suitability.
struct Seedbed {
    const Canopy& canopy;
    const GroundLayer& ground;
    const std::vector<Species>& species;
    double extinction;
    SoilWater water;
    const hydro::Catchments& lakes;
    /// Where each species' seeds and attempts are counted (diagnosis.hpp); none if null.
    std::vector<SpeciesLedger>* ledger = nullptr;
    /// The light of each plant cell (gap_light) under crown_profile shading; if empty, 1 - the
    /// cell's own ground shade (paper 002's blocking and Beer-Lambert shading).
    std::optional<RasterD> cell_light = std::nullopt;
    /// One draw of `rng` always (the stream does not depend on the tests).
    bool establishes(const Species& s, double x, double y, Rng& rng) const;
};

/// Ageing, the growth-efficiency update and death by age, background and suppression (paper 002's
/// growth model only: suppression_mortality) (one draw of
/// `rng` per plant, dead or alive); returns per plant its DeathCause (deadwood.hpp) as a char, 0
/// for the living (starved plants are not counted again).
std::vector<char> ageing_and_mortality(Population& pop, const std::vector<Species>& species,
                                       Rng& rng, PlantSums& sums,
                                       GrowthModel model = GrowthModel::paper002);

/// Seeds of the mature survivors, dispersed (Poisson count, kernel distance, uniform direction)
/// and established; seeds landing outside the plant grid are lost (with one draw, to keep the
/// stream aligned).
std::vector<Plant> seed_dispersal(const Population& pop, const std::vector<char>& dead,
                                  const std::vector<Species>& species, const GridSpec& grid,
                                  const Seedbed& bed, const Nursery& nursery, Rng& rng,
                                  PlantSums& sums);

/// Arrivals from outside at each species' per-area rate (grasses arrive into the ground layer's
/// cover), established by `bed` (objects always).
void background_arrivals(const std::vector<Species>& species, const GridSpec& grid,
                         const Seedbed& bed, const Nursery& nursery, Rng& rng,
                         std::vector<Plant>& recruits);

/// Removes the plants that are not alive, adding their wood and reserve to the dead carbon.
void remove_dead(Population& pop, PlantSums& sums);

/// Orders the plants by the cell of their stem on `grid`, row by row (stable: plants of one cell
/// keep their order). Plants do not move, so after the first call only the year's recruits are
/// out of place. Consecutive plants then touch neighbouring cells, and the per-cell passes (the
/// roots' scatter and gather, the crown-profile shading) read memory in order instead of at
/// random. The order decides which plant takes which of a generator's draws (mortality,
/// seeding), so it is part of a run's state: a run is the same whether resumed or not, since
/// the checkpoint keeps the sorted order.
void sort_by_stem_cell(Population& pop, const GridSpec& grid);

// --- light-only mode ---------------------------------------------------------------------------

/// Ageing and growth on the light-only curve D(t) = D95 (1 - exp(-r t)); death at the maximum age
/// (the returned causes as ageing_and_mortality's).
std::vector<char> light_only_growth(Population& pop, const std::vector<Species>& species,
                                    PlantSums& sums);
/// The light-only curve's diameter at `age_yr`, and the age an initial stem of `dbh_m` gets.
double light_only_dbh_m(const Species& s, double age_yr);
double light_only_age_yr(const Species& s, double dbh_m);

/// Arrivals at each species' per-area rate, placed without an establishment test.
void light_only_arrivals(Population& pop, std::vector<char>& dead,
                         const std::vector<Species>& species, const GridSpec& grid,
                         const Nursery& nursery, Rng& rng, PlantSums& sums);

/// From the largest circle down, a plant overlapping a kept larger one dies (cause overlap).
void overlap_thinning(const Population& pop, std::vector<char>& dead,
                      const std::vector<Species>& species, const GridSpec& grid,
                      LightOnlyRadius rule, PlantSums& sums);

/// MAVS's ecosystem step (Goodin 2018, as MAVS's terrain_generator/ecosystem.cpp does it;
/// reference mavs.md s1.2-1.4), one year:
/// 1. arrivals: per species floor(A g n) plants plus one with probability the remainder (A the
///    plant grid's area, g MAVS's "Plant Density", n "Num New Per Area"), uniform over the grid,
///    each of a height uniform in [0, H(1 yr)];
/// 2. growth, arrivals included: the age is read off the height curve and one year added; the
///    plant's own age counter grows by one and it dies (cause age) once over "Max Age";
/// 3. competition: every pair closer than the sum of their circles (0.5 ratio H) is tested at once,
///    plants dying this year included; the smaller circle dies, equal circles both (cause
///    overlap).
/// The diameter is the height curve's inverse (allometry::dbh_from_height_m). Returns the causes.
std::vector<char> mavs_step(Population& pop, const std::vector<Species>& species,
                            const GridSpec& grid, double plant_density, const Nursery& nursery,
                            Rng& rng, PlantSums& sums);
/// MAVS's height curve H(t) = Hmax (1 - exp(-r t)) and the age it gives a height (capped below
/// Hmax).
double mavs_height_m(const Species& s, double age_yr);
double mavs_age_yr(const Species& s, double height_m);

// --- initial stems -----------------------------------------------------------------------------

/// The initial stems of a scene (vegetation.initial): none, random, or a stem file.
std::vector<Plant> initial_stems(const EcoScene& scene, const GridSpec& plant_grid,
                                 const Nursery& nursery);

// --- the carbon budget -------------------------------------------------------------------------

/// The plants' carbon from year to year: the stock at the last year end and the cumulative
/// residual and throughput of the yearly budget.
struct CarbonLedger {
    double stock_at_year_start_kg = 0;
    double cumulative_residual_kg = 0, cumulative_throughput_kg = 0;
};
struct CarbonStocks {
    double wood_kg = 0, reserve_kg = 0, deadwood_kg = 0, residual_kg = 0;
};
/// The dead wood's part of the budget (deadwood.hpp): its stock at year end and the year's input
/// (the stems of trees that died) and decay, kg.
struct DeadWoodBudget {
    double stock_kg = 0, input_kg = 0, decay_kg = 0;
};
/// The year's carbon budget of the plants and their dead wood: stock = last stock + production -
/// respiration + recruits - dead + dead wood's input - its decay - turnover; throws Error naming
/// `year` when the cumulative residual exceeds its tolerance.
CarbonStocks close_carbon_budget(const Population& pop, const PlantSums& sums,
                                 const DeadWoodBudget& dead_wood, int year, CarbonLedger& ledger);

} // namespace ecoterra::eco
