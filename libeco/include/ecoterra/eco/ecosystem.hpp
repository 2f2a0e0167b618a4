#pragma once
// The coupled engine (paper 002 s3-4): terrain, soil, weather, hydrology and plants stepped day by
// day. The state is the plant population (population.hpp), its canopy, the ground layer and the
// hydrology; the processes are the kernels of processes.hpp, which step_day() and the year end
// compose in this order:
//   day (coupled)    plant_water_demand, ground_water_request -> HydrologyModel::step ->
//                    supply_fractions -> carbon_balance -> the ground layer's day; every
//                    canopy_interval_days refresh_structure and Canopy::refresh
//   year end         coupled: ageing_and_mortality, seed_dispersal, background_arrivals, then the
//                    dead removed, the recruits added and the canopy refreshed; light-only (Deussen
//                    et al. 1998 / MAVS, docs/ecosystem.md s7): light_only_growth,
//                    light_only_arrivals, overlap_thinning; both: the dead trees into dead wood
//                    (deadwood.hpp; the starved also at each canopy refresh), the dead wood's
//                    year, the vegetation density for the hydrology, close_carbon_budget, the
//                    yearly row
// The year ends on day 365, or on 31 December with observed weather.
#include "ecoterra/archive.hpp"
#include "ecoterra/eco/deadwood.hpp"
#include "ecoterra/eco/diagnosis.hpp"
#include "ecoterra/eco/ground_layer.hpp"
#include "ecoterra/eco/growth.hpp"
#include "ecoterra/eco/outputs.hpp"
#include "ecoterra/eco/plant.hpp"
#include "ecoterra/eco/processes.hpp"
#include "ecoterra/eco/roots.hpp"
#include "ecoterra/eco/scene_config.hpp"
#include "ecoterra/eco/stand_metrics.hpp"
#include "ecoterra/hydro/hydrology.hpp"
#include "ecoterra/hydro/weather.hpp"
#include "ecoterra/random.hpp"

#include <functional>
#include <memory>
#include <optional>

namespace ecoterra::eco {

class Ecosystem {
public:
    explicit Ecosystem(const EcoScene& scene);
    ~Ecosystem();

    /// Steps one day; returns true when the day closed a year.
    bool step_day();
    /// Steps to the end of the current year.
    void run_year();
    /// Cuts the plants with these ids now, as a thinning cuts them at a year end: each leaves its
    /// stump and slash to the dead wood and counts in the year's harvest; the canopy is refreshed.
    /// InputError (naming the id) for an id that is not a living plant, with nothing removed.
    /// Returns the number of plants removed.
    std::size_t remove_plants(const std::vector<std::int64_t>& ids);
    /// Replaces the rain of the next day stepped, mm, once: a coupled model's rain (the BMI's
    /// precipitation input). The day's weather is drawn as always and only its rain replaced, so
    /// the other variables and the later days are unchanged. Not part of the checkpoint.
    /// InputError for a negative or non-finite amount.
    void set_next_rain_mm(double rain_mm);

    int years_done() const { return m_years_done; }
    int days_done() const { return m_days_done; }
    const hydro::DayWeather& last_weather() const { return m_weather; }
    const Population& plants() const { return m_pop; }
    /// Snags and logs (empty with vegetation.deadwood.enabled false).
    const DeadWood& dead_wood() const { return m_dead; }
    const EcoScene& scene() const { return m_scene; }
    const hydro::HydrologyModel& hydrology() const { return *m_hydro; }
    const GridSpec& plant_grid() const { return m_canopy.plant_grid; }
    /// Ground shade on the plant grid (see canopy.hpp).
    const RasterD& ground_shade() const { return m_canopy.ground_shade; }
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

    /// Where a checkpoint keeps the daily and yearly series: in itself, or in the run file beside
    /// it (its /series, written from the same tables), the checkpoint then holding each column's
    /// name, row count and a hash of its values to check them by on a resume. A run file rewritten
    /// at every snapshot so no longer compresses the series twice.
    enum class SeriesIn { checkpoint, run_file };
    /// One column of the run file's series, by table ("daily" or "yearly") and column name, its
    /// integers as doubles: what a checkpoint saved with SeriesIn::run_file resumes from.
    using SeriesSource =
        std::function<std::vector<double>(const std::string& table, const std::string& column)>;

    /// The checkpoint: a magic tag, the container version and one section per part of the state
    /// (see docs/formats.md). With SeriesIn::run_file the series stay in the checkpoint all the
    /// same when a column would not read back exactly from the run file (an integer column with a
    /// value that is not a whole number, NaN included).
    void save_state(ArchiveWriter& a, SeriesIn series = SeriesIn::checkpoint) const;
    /// Reads a checkpoint save_state() wrote, or one of format version 6 (before sections). A
    /// checkpoint whose series are in its run file needs `series`; CheckpointError without it, or
    /// when a column is missing or differs from the one saved with the checkpoint.
    void load_state(ArchiveReader& a, const SeriesSource& series = {});

    /// Why the stand is what it is, from the run's ledger (diagnosis.hpp).
    Diagnosis diagnosis() const;
    const std::vector<SpeciesLedger>& species_ledger() const { return m_diag; }

private:
    const hydro::DayWeather& next_weather();
    /// Days in the year of `w`: 365, or the calendar year's with observed weather.
    int year_length(const hydro::DayWeather& w) const;
    /// The coupled day: demand -> hydrology -> supply -> carbon -> ground layer -> canopy.
    hydro::DailyFluxes coupled_day(const hydro::DayWeather& w);
    /// The plants' and ground layer's water request of the day (m_request_mm) and their leaves
    /// per hydrology cell (m_lai, m_cover), for either mode.
    void water_request_and_leaves(const hydro::DayWeather& w, const DayClimate& day);
    /// The light-only day: the plants ask for water and shade the ground, but grow on light.
    hydro::DailyFluxes light_only_day(const hydro::DayWeather& w);
    /// The ground layer's day in coupled mode: its environment, water sums and growth.
    void ground_layer_day(const hydro::DayWeather& w, const DayClimate& day);
    /// The trees that died (not alive, or with a cause in `causes`) into the dead wood.
    void take_dead(const std::vector<char>* causes);
    /// Sorts the plants by their stem's cell unless the scene keeps them in birth order.
    void order_plants();
    /// The year's management operations: marks the trees they cut in `dead` (DeathCause::harvest)
    /// and sums them into m_harvest.
    void harvest(std::vector<char>& dead, bool allometric_mass);
    /// Adds the plants cut (dead but not in `before`) to the year's harvest sums.
    void count_harvest(const std::vector<char>& before, const std::vector<char>& dead,
                       bool allometric_mass);
    /// The year's storm: marks the trees it fells in `dead` (windthrow.hpp) into m_storm.
    void storm(std::vector<char>& dead);
    /// Removes the dead, refreshes the structure (coupled) and the canopy.
    void refresh_canopy();
    void year_end_coupled();
    void year_end_light_only();
    /// Both modes: vegetation density for the hydrology, the carbon budget, the yearly row.
    void year_end_common();
    /// Appends the year's row (yearly_columns()) to the yearly series.
    void record_year(const CarbonStocks& c);
    SoilWater soil_water() const { return {m_hydro->soil_moisture(), m_scene.hydro.soil}; }
    Nursery nursery() {
        return {m_scene.ecosystem.species, m_scene.hydro.dem, m_scene.hydro.soil,
                m_scene.competition, m_next_id};
    }
    Seedbed seedbed();
    /// Counts the plants starved since the last count (dead, not yet removed) in the ledger.
    void count_starved();
    /// Counts the year's deaths by cause in the ledger.
    void count_deaths(const std::vector<char>& dead);
    /// Adds the growth factors of the living plants in leaf to the ledger.
    void sample_growth_factors(const DayClimate& day);
    /// A hash of the observed weather series (0 with the generator), checked on resume.
    std::uint64_t observed_weather_hash() const;
    void load_sections(ArchiveReader& a, const SeriesSource& series);
    void load_version6(ArchiveReader& a);

    EcoScene m_scene;
    std::optional<double> m_next_rain_mm; ///< set_next_rain_mm(), for the next day only
    double m_hydro_cell_area = 1;
    std::unique_ptr<hydro::HydrologyModel> m_hydro;
    hydro::WeatherGenerator m_gen;
    hydro::DayWeather m_weather;
    Rng m_rng_seed, m_rng_mort, m_rng_arrival;
    Population m_pop;
    DeadWood m_dead;
    Windthrow m_wind;
    StormResult m_storm; ///< the year's (reset at year end)
    /// The year's harvest (reset at year end, so never in a checkpoint).
    struct HarvestSums {
        double stems = 0, basal_area_m2_per_ha = 0, wood_kg = 0;
    } m_harvest;
    std::int64_t m_next_id = 1;
    Canopy m_canopy;
    GroundLayer m_ground;
    std::vector<GroundCell> m_ground_env;
    // The day's water exchange (kept to avoid allocations in the daily loop): per plant the
    // demand (m3) and the share met; per hydrology cell the request (m3 and mm), the supply ratio
    // and the ground layer's demand and request (m3).
    std::vector<double> m_demand, m_fraction;
    std::vector<double> m_request, m_ratio, m_ground_demand, m_ground_request;
    RasterD m_request_mm;
    // Today's leaves: per plant its leaf area (m2), per hydrology cell the leaf area index and
    // the cover 1 - exp(-k LAI).
    std::vector<double> m_leaf_today, m_leaf_cells;
    RasterD m_lai, m_cover;
    int m_years_done = 0, m_days_done = 0;
    Table m_yearly, m_daily;
    PlantSums m_sum;
    CarbonLedger m_ledger;
    std::vector<SpeciesLedger> m_diag; ///< per species, over the run (in the checkpoint)
};

} // namespace ecoterra::eco
