#pragma once
// The coupled engine (paper 002 s3-4): terrain, soil, weather, hydrology and plants stepped day by
// day. Daily: weather, plant water demand -> hydrology -> supply -> carbohydrate balance,
// starvation. Every canopy_interval_days: wood -> diameter -> height, crown, leaf area (allometry),
// crowns and shading. Yearly (day 365, or 31 December with observed weather): ageing,
// mortality (maximum age, background, growth suppression), seed
// production, dispersal and establishment, background arrivals, canopy cover -> the hydrology's
// vegetation density, the yearly series. The light-only mode replaces the plant processes by the
// geometric rule of Deussen et al. 1998 / MAVS (see docs/ecosystem.md s7).
#include "ecoterra/archive.hpp"
#include "ecoterra/eco/ground_layer.hpp"
#include "ecoterra/eco/growth.hpp"
#include "ecoterra/eco/outputs.hpp"
#include "ecoterra/eco/plant.hpp"
#include "ecoterra/eco/roots.hpp"
#include "ecoterra/eco/scene_config.hpp"
#include "ecoterra/eco/stand_metrics.hpp"
#include "ecoterra/hydro/hydrology.hpp"
#include "ecoterra/hydro/weather.hpp"
#include "ecoterra/random.hpp"

#include <memory>

namespace ecoterra::eco {

class Ecosystem {
public:
    explicit Ecosystem(const EcoScene& scene);
    ~Ecosystem();

    /// Steps one day; returns true when the day closed a year.
    bool step_day();
    /// Steps to the end of the current year.
    void run_year();

    int years_done() const { return m_years_done; }
    int days_done() const { return m_days_done; }
    const hydro::DayWeather& last_weather() const { return m_weather; }
    const std::vector<Plant>& plants() const { return m_plants; }
    const EcoScene& scene() const { return m_scene; }
    const hydro::HydrologyModel& hydrology() const { return *m_hydro; }
    const GridSpec& plant_grid() const { return m_pgrid; }
    /// Ground shade on the plant grid (see canopy.hpp).
    const RasterD& ground_shade() const { return m_ground_shade; }
    /// Stand metrics of the trees (basal area is a tree measure).
    StandMetrics stand() const;
    /// Shrubs, objects and the ground layer, reported apart from the trees.
    UndergrowthMetrics undergrowth() const;
    const GroundLayer& ground_layer() const { return m_ground; }
    /// Total ground-layer cover per hydrology cell, 0..1.
    RasterD ground_cover() const;
    /// One grass species' cover per hydrology cell (g indexes ground_layer().species()).
    RasterD ground_cover(std::size_t g) const;
    const Table& yearly() const { return m_yearly; }
    const Table& daily() const { return m_daily; }
    double carbon_residual_relative() const;

    void save_state(ArchiveWriter& a) const;
    void load_state(ArchiveReader& a);

private:
    // The daily processes, in the order step_day() runs them.
    const hydro::DayWeather& next_weather();
    /// Each plant's transpiration demand (leaf area x phenology x reference ET), spread over its
    /// root cells into the hydrology's request (mm per cell).
    void plant_water_demand(double et0_m, const std::vector<double>& phen);
    /// The share of each plant's demand its root cells supplied.
    void water_supply_fractions();
    /// The day's carbohydrate balance of every plant; starvation.
    void carbon_balance(const std::vector<double>& phen, const std::vector<double>& ftemp,
                        double q10);
    /// Days in the year of `w`: 365, or the calendar year's with observed weather.
    int year_length(const hydro::DayWeather& w) const;
    void place_initial_plants();
    Plant new_plant(std::uint16_t species, double x, double y, double dbh_m);
    bool establishes(const Species& s, double x, double y, Rng& rng) const;
    void refresh_canopy();
    void rebuild_crowns();
    void update_vegetation_density();
    /// The crowns' shade of each hydrology cell (mean of the ground shade over its plant cells).
    void crown_shade_per_cell();
    /// The ground layer's state of each cell for a step (water_met from the day's supply).
    void ground_environment(bool coupled);
    /// Relative extractable soil water of a hydrology cell.
    double relative_water(int hi, int hj) const;
    // The year end, coupled mode: year_end_coupled runs these in order, then removes the dead,
    // adds the recruits and refreshes the canopy.
    void year_end_coupled();
    /// Ageing, the growth-efficiency update, and death by age, background and suppression (one
    /// draw of the mortality stream per plant); returns the plants that die.
    std::vector<char> ageing_and_mortality();
    /// Seeds of the mature survivors, dispersed and established (the seeding stream).
    std::vector<Plant> seed_dispersal(const std::vector<char>& dead);
    /// Arrivals from outside at each species' per-area rate, established (the arrival stream).
    void background_arrivals(std::vector<Plant>& recruits);
    // The year end, light-only mode (the MAVS baseline): growth on the saturating curve, arrivals,
    // overlap thinning, then the dead removed and the canopy refreshed.
    void year_end_light_only();
    /// Ageing and growth on the light-only curve; death at the maximum age.
    std::vector<char> light_only_growth();
    /// Arrivals at each species' per-area rate, placed without an establishment test.
    void light_only_arrivals(std::vector<char>& dead);
    /// From the largest circle down, a plant overlapping a kept larger one dies.
    void overlap_thinning(std::vector<char>& dead);
    // Both modes: vegetation density for the hydrology, the carbon budget, the yearly row.
    void year_end_common();
    struct CarbonStocks {
        double wood_kg = 0, reserve_kg = 0, residual_kg = 0;
    };
    /// The year's carbon budget of all plants; throws Error when it does not close.
    CarbonStocks close_carbon_budget();
    /// Appends the year's row (yearly_columns()) to the yearly series.
    void record_year(const CarbonStocks& c);
    void remove_dead();
    /// A hash of the observed weather series (0 with the generator), checked on resume.
    std::uint64_t observed_weather_hash() const;

    EcoScene m_scene;
    GridSpec m_pgrid;
    CellMap m_map{};
    double m_hydro_cell_area = 1;
    std::unique_ptr<hydro::HydrologyModel> m_hydro;
    hydro::WeatherGenerator m_gen;
    hydro::DayWeather m_weather;
    Rng m_rng_seed, m_rng_mort, m_rng_arrival;
    std::vector<Plant> m_plants;
    std::int64_t m_next_id = 1;
    CrownSet m_crowns;
    RootCells m_roots; ///< the crowns' root cells per hydrology cell
    RasterD m_ground_shade;
    GroundLayer m_ground;
    std::vector<char> m_is_object;    ///< per species
    std::vector<double> m_cell_shade; ///< crown shade per hydrology cell
    std::vector<GroundCell> m_ground_env;
    std::vector<double> m_ground_demand, m_ground_request; ///< per hydrology cell, m3 per day
    // Daily scratch (kept to avoid allocations in the daily loop).
    std::vector<double> m_request, m_ratio, m_fraction, m_demand;
    RasterD m_request_mm;
    std::vector<CarbonDay> m_carbon;
    int m_years_done = 0, m_days_done = 0;
    Table m_yearly, m_daily;
    // Year accumulators.
    struct YearSums {
        double births = 0, deaths_starvation = 0, deaths_age = 0, deaths_background = 0,
               deaths_suppression = 0, deaths_overlap = 0, seeds = 0, seeds_lost = 0;
        double production = 0, maintenance = 0, growth_resp = 0, recruit_carbon = 0,
               dead_carbon = 0, turnover = 0;
        double demand_m3 = 0, supplied_m3 = 0;
        double ground_demand_m3 = 0, ground_supplied_m3 = 0;
    } m_sum;
    double m_stock_at_year_start = 0;
    double m_cum_carbon_residual = 0, m_cum_carbon_throughput = 0;
};

} // namespace ecoterra::eco
