#include "ecoterra/eco/ecosystem.hpp"
#include "ecoterra/fastmath.hpp"
#include "ecoterra/hash.hpp"

#include "ecoterra/hydro/penman.hpp"
#include "ecoterra/parallel.hpp"
#include "ecoterra/units.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <numbers>
#include <unordered_map>
#include <utility>

namespace ecoterra::eco {

namespace {
/// Memory per plant-grid cell: the ground shade and the shading pass's work rasters, bytes.
constexpr double kPlantGridBytesPerCell = 24.0;
constexpr std::uint32_t kCheckpointMagic = 0x45434f54; // "ECOT"
// The container: 4 catchments on the depression hierarchy; 5 no padding in plants and the weather
// state, bands sorted once; 6 life forms (the ground layer's cover); 7 sections, each with its own
// version (the section versions are kSection* below). load_state still reads version 6.
constexpr std::uint32_t kCheckpointVersion = 7;
constexpr std::uint32_t kLastUnsectionedVersion = 6;
// Section versions: raise one when its content changes, and teach its reader the older one where
// it can be converted.
constexpr std::uint32_t kSectionClock = 1;  // days, years, weather, the generator
constexpr std::uint32_t kSectionRandom = 1; // the seeding, mortality and arrival streams
constexpr std::uint32_t kSectionPlants = 1; // the population's columns and the next id
constexpr std::uint32_t kSectionCanopy = 1; // the ground shade
constexpr std::uint32_t kSectionGround = 1; // the ground layer's cover
// the hydrology's state and vegetation density (2: with the surface layer's depletion)
constexpr std::uint32_t kSectionHydro = hydro::HydrologyModel::kStateVersion;
// the daily and yearly series, by column name (2: or, for a run file, each column's row count and
// hash, its values in the run file's /series)
constexpr std::uint32_t kSectionSeries = 2;
constexpr std::uint32_t kSectionBudget = 1;    // the year's sums and the carbon ledger
constexpr std::uint32_t kSectionWindthrow = 1; // the storm stream and the last thinning
constexpr std::uint32_t kSectionDiagnosis = 1; // the species ledgers (optional: none before it)
constexpr std::uint32_t kSectionDeadWood = 2;  // snags and logs (optional: none before it);
                                               // 2: stumps and slash

/// The daily columns of the processes that came with hydrology state version 2 (interception,
/// drainage). Runs checkpointed before had neither: their rows hold 0, not "unknown".
bool is_surface_layer_era_column(const std::string& name) {
    return name == "interception_mm" || name == "drainage_out_mm";
}
void zero_surface_layer_era_columns(Table& daily) {
    std::size_t rows = 0;
    for (std::size_t c = 0; c < daily.columns.size(); ++c)
        if (!is_surface_layer_era_column(daily.names[c])) rows = daily.columns[c].size();
    for (std::size_t c = 0; c < daily.columns.size(); ++c)
        if (is_surface_layer_era_column(daily.names[c])) daily.columns[c].assign(rows, 0.0);
}

/// The yearly dead-wood columns (outputs.cpp), absent from format-6 checkpoints.
bool is_dead_wood_column(const std::string& name) {
    return name.starts_with("snag") || name.starts_with("log_") || name.starts_with("logs_") ||
           name.starts_with("deadwood_") || name.starts_with("stump") ||
           name.starts_with("harvested_") || name.starts_with("storm_") ||
           name.starts_with("windthrow_") || name.starts_with("root_plates");
}

/// The yearly water columns, each the sum of a daily budget column.
constexpr std::array<std::pair<const char*, const char*>, 8> kYearlyWater = {{
    {"rain_mm", "rain_mm"},
    {"evaporation_mm", "evaporation_mm"},
    {"transpiration_mm", "transpiration_mm"},
    {"interception_mm", "interception_mm"},
    {"runoff_out_mm", "runoff_out_mm"},
    {"drainage_out_mm", "drainage_out_mm"},
    {"groundwater_out_mm", "groundwater_out_mm"},
    {"recharge_mm", "recharge_mm"},
}};

/// Each year's water sums from the daily series: the k-th run of days with one `year` value is the
/// k-th yearly row. Fills the yearly water columns of rows [first, rows).
void yearly_water_from_daily(const Table& daily, Table& yearly, std::size_t first) {
    const auto& day_year = daily.column("year");
    const std::size_t rows = yearly.rows(), days = day_year.size();
    // The first day of each year from `first` on; the last year alone (every year end) is found
    // from the end, so that a long run does not rescan its whole series each year.
    std::vector<std::size_t> start;
    if (first + 1 == rows && days > 0) {
        std::size_t d = days - 1;
        while (d > 0 && day_year[d - 1] == day_year[days - 1]) --d;
        start = {d, days};
    } else {
        std::size_t year = 0;
        for (std::size_t d = 0; d < days; ++d)
            if (d == 0 || day_year[d] != day_year[d - 1])
                if (year++ >= first) start.push_back(d);
        start.push_back(days);
    }
    for (const auto& [to, from] : kYearlyWater) {
        const auto& src = daily.column(from);
        auto& dst = yearly.columns[static_cast<std::size_t>(
            std::find(yearly.names.begin(), yearly.names.end(), to) - yearly.names.begin())];
        dst.resize(rows, 0.0);
        for (std::size_t k = 0; first + k < rows && k + 1 < start.size(); ++k) {
            double sum = 0;
            for (std::size_t d = start[k]; d < start[k + 1]; ++d) sum += src[d];
            dst[first + k] = sum;
        }
    }
}

} // namespace

Ecosystem::Ecosystem(const EcoScene& scene)
    : m_scene(scene), m_gen(scene.hydro.climate, scene.seed), m_rng_seed(scene.seed, "eco.seeding"),
      m_rng_mort(scene.seed, "eco.mortality"), m_rng_arrival(scene.seed, "eco.arrival"),
      m_dead(scene.deadwood, scene.seed), m_wind(scene.windthrow, scene.seed) {
    const auto& hg = scene.hydro.dem.grid();
    CellMap& map = m_canopy.map;
    map.factor = static_cast<int>(std::lround(hg.cell_size_m / scene.plant_cell_m));
    map.hydro_nx = hg.nx;
    GridSpec& pg = m_canopy.plant_grid;
    pg = hg;
    pg.cell_size_m = hg.cell_size_m / map.factor;
    pg.nx = hg.nx * map.factor;
    pg.ny = hg.ny * map.factor;
    ensure_fits_in_memory(pg.size(), kPlantGridBytesPerCell, "the plant grid");
    m_hydro_cell_area = hg.cell_size_m * hg.cell_size_m;
    m_hydro =
        std::make_unique<hydro::HydrologyModel>(scene.hydro.dem, scene.hydro.soil, RasterD(hg, 0.0),
                                                scene.hydro.options, scene.hydro.climate);
    m_canopy.ground_shade = RasterD(pg, 0.0);
    m_request_mm = RasterD(hg, 0.0);
    m_lai = RasterD(hg, 0.0);
    m_cover = RasterD(hg, 0.0);
    const auto& species = scene.ecosystem.species;
    const auto& soil = scene.hydro.soil;
    m_ground = GroundLayer(species, hg.size(), [&](std::uint16_t k, std::int64_t c) {
        return soil_suitability(species[k], soil, static_cast<int>(c % hg.nx),
                                static_cast<int>(c / hg.nx));
    });
    m_daily = Table::of(hydro::daily_budget_columns());
    m_yearly = Table::of(yearly_columns());
    m_diag.assign(species.size(), SpeciesLedger{});
    for (const Plant& p : initial_stems(m_scene, pg, nursery())) m_pop.push(p);
    order_plants();
    refresh_canopy();
    m_hydro->set_vegetation_density(m_canopy.vegetation_density(m_ground, hg));
    for (std::size_t k = 0; k < m_pop.size(); ++k)
        m_ledger.stock_at_year_start_kg += m_pop.wood_kg[k] + m_pop.reserve_kg[k];
}

Ecosystem::~Ecosystem() = default;

Seedbed Ecosystem::seedbed() {
    std::optional<RasterD> light;
    if (m_scene.shading == ShadingMode::crown_profile) {
        const double area_ha = plant_grid().width_m() * plant_grid().height_m() / 1e4;
        light = gap_light(m_canopy.ground_shade,
                          0.5 * top_height_m(m_pop, m_scene.ecosystem.species, area_ha));
    }
    return {m_canopy,
            m_ground,
            m_scene.ecosystem.species,
            m_scene.extinction,
            soil_water(),
            m_hydro->catchments(),
            &m_diag,
            std::move(light)};
}

void Ecosystem::count_starved() {
    for (std::size_t k = 0; k < m_pop.size(); ++k)
        if (!m_pop.alive[k])
            m_diag[m_pop.species[k]].deaths[static_cast<int>(DeathCause::starvation)] += 1;
}

void Ecosystem::count_deaths(const std::vector<char>& dead) {
    for (std::size_t k = 0; k < m_pop.size(); ++k)
        if (dead[k] > 0 && dead[k] < 9)
            m_diag[m_pop.species[k]].deaths[static_cast<int>(dead[k])] += 1;
}

void Ecosystem::sample_growth_factors(const DayClimate& day) {
    const auto& species = m_scene.ecosystem.species;
    for (std::size_t k = 0; k < m_pop.size(); ++k) {
        const auto sp = m_pop.species[k];
        const Species& s = species[sp];
        if (!m_pop.alive[k] || s.life_form == LifeForm::object || day.phen[sp] <= 0) continue;
        SpeciesLedger& l = m_diag[sp];
        l.samples += 1;
        l.light_sum += light_or_shade_factor(s, m_scene.growth, m_pop.shade_fraction[k]);
        l.water_sum += water_factor(s.water, m_fraction[k]);
        l.soil_sum += m_pop.soil_factor[k];
        l.temperature_sum += day.ftemp[sp];
    }
}

void Ecosystem::order_plants() {
    if (m_scene.plant_order == PlantOrder::stem_cell) sort_by_stem_cell(m_pop, plant_grid());
}

void Ecosystem::refresh_canopy() {
    if (m_scene.competition == Competition::coupled) count_starved();
    take_dead(nullptr);
    remove_dead(m_pop, m_sum);
    // The crowns' leaf plasticity belongs to the coupled light_and_turnover model.
    const GrowthModel growth =
        m_scene.competition == Competition::coupled ? m_scene.growth : GrowthModel::paper002;
    if (m_scene.competition == Competition::coupled)
        refresh_structure(m_pop, m_scene.ecosystem.species, growth);
    m_canopy.refresh(m_pop, m_scene.ecosystem.species, m_scene.shading, m_scene.extinction, growth);
}

const hydro::DayWeather& Ecosystem::next_weather() {
    if (m_scene.hydro.observed) {
        // Observed weather replays its whole calendar years in a cycle.
        const auto& days = m_scene.hydro.observed->days;
        m_weather = days[static_cast<std::size_t>(m_days_done) % days.size()];
    } else {
        m_weather = m_gen.next();
    }
    ++m_days_done;
    if (m_next_rain_mm) {
        m_weather.rain_mm = *m_next_rain_mm;
        m_next_rain_mm.reset();
    }
    return m_weather;
}

int Ecosystem::year_length(const hydro::DayWeather& w) const {
    return m_scene.hydro.observed ? hydro::days_in_calendar_year(w.year) : hydro::kDaysPerYear;
}

bool Ecosystem::step_day() {
    const hydro::DayWeather& w = next_weather();
    const bool coupled = m_scene.competition == Competition::coupled;
    const hydro::DailyFluxes f = coupled ? coupled_day(w) : light_only_day(w);
    const auto& hg = m_scene.hydro.dem.grid();
    m_daily.push(hydro::daily_budget_row(m_days_done, w, f, hg.width_m() * hg.height_m()),
                 hydro::daily_budget_columns());
    if (w.doy < year_length(w)) return false;
    if (coupled)
        year_end_coupled();
    else
        year_end_light_only();
    year_end_common();
    return true;
}

void Ecosystem::run_year() {
    while (!step_day()) {
    }
}

void Ecosystem::water_request_and_leaves(const hydro::DayWeather& w, const DayClimate& day) {
    const auto& species = m_scene.ecosystem.species;
    const auto dw = hydro::et_weather(w, m_scene.hydro.climate);
    const double et0_m = std::max(0.0, hydro::et::fao56_reference_daily(dw)) / kMmPerM;
    // Demand: the plants' through their root cells, then the ground layer's.
    plant_water_demand(m_pop, species, day.phen, et0_m, m_scene.growth, m_demand);
    // Leaves: each plant's today, spread as its roots are (in the same pass), and the ground
    // layer's below.
    m_leaf_today.assign(m_pop.size(), 0.0);
    for (std::size_t k = 0; k < m_pop.size(); ++k)
        if (m_pop.alive[k] && species[m_pop.species[k]].life_form != LifeForm::object)
            m_leaf_today[k] = m_pop.leaf_area_m2[k] * day.phen[m_pop.species[k]];
    // The two per-cell sums are zero between days: the block loop below clears each cell as it
    // reads it (in cache), instead of a pass zeroing both grids here.
    const auto cells = static_cast<std::size_t>(m_request_mm.size());
    if (m_request.size() != cells) m_request.assign(cells, 0.0);
    if (m_leaf_cells.size() != cells) m_leaf_cells.assign(cells, 0.0);
    scatter_pair(m_canopy.roots, m_demand, m_leaf_today, m_request, m_leaf_cells);
    ground_water_request(m_ground, species, day.phen, et0_m, soil_water(),
                         m_scene.hydro.options.root_zone_depth_m, m_hydro_cell_area,
                         m_ground_demand, m_ground_request, m_request);
    const auto n = static_cast<std::int64_t>(cells);
    for_each_block(n, [&](std::int64_t c0, std::int64_t c1) {
        for (std::int64_t c = c0; c < c1; ++c) {
            const auto u = static_cast<std::size_t>(c);
            m_request_mm.data()[c] = m_request[u] / m_hydro_cell_area * kMmPerM;
            double lai = m_leaf_cells[u] / m_hydro_cell_area;
            m_request[u] = 0.0;
            m_leaf_cells[u] = 0.0;
            if (!m_ground.empty()) lai += m_ground.leaf_area_index(species, c, day.phen);
            m_lai.data()[c] = lai;
        }
        // The cover by Beer-Lambert, vectorised (fastmath.hpp).
        fastmath::cover_from_lai(c1 - c0, m_lai.data() + c0, m_scene.extinction,
                                 m_cover.data() + c0);
    });
}

hydro::DailyFluxes Ecosystem::light_only_day(const hydro::DayWeather& w) {
    const DayClimate day =
        day_climate(m_scene.ecosystem.species, w.doy, 0.5 * (w.tmin_c + w.tmax_c));
    water_request_and_leaves(w, day);
    // Paper 002's light-only baseline draws no water for its plants.
    if (m_scene.hydro.options.evapotranspiration == hydro::EvapotranspirationMethod::paper002)
        return m_hydro->step(w, nullptr, &m_lai, &m_cover);
    return m_hydro->step(w, &m_request_mm, &m_lai, &m_cover);
}

hydro::DailyFluxes Ecosystem::coupled_day(const hydro::DayWeather& w) {
    const auto& species = m_scene.ecosystem.species;
    const DayClimate day = day_climate(species, w.doy, 0.5 * (w.tmin_c + w.tmax_c));
    water_request_and_leaves(w, day);
    // The hydrology supplies it; the plants grow on what they got.
    const hydro::DailyFluxes f = m_hydro->step(w, &m_request_mm, &m_lai, &m_cover);
    supply_fractions(m_canopy.roots, m_request_mm, m_hydro->transpiration_supplied_mm(), m_ratio,
                     m_fraction);
    carbon_balance(m_pop, species, day, m_fraction, m_demand, m_scene.growth, m_sum);
    if (!m_ground.empty()) ground_layer_day(w, day);
    // The ground layer steps once a canopy interval and on the year's last day (the year end and
    // its checkpoint see no pending days); the canopy refreshes once an interval.
    const bool refresh = m_days_done % m_scene.canopy_interval_days == 0;
    if (refresh || w.doy >= year_length(w)) m_ground.apply(species);
    if (refresh) {
        sample_growth_factors(day);
        refresh_canopy();
    }
    return f;
}

void Ecosystem::ground_layer_day(const hydro::DayWeather& w, const DayClimate& day) {
    const auto& species = m_scene.ecosystem.species;
    ground_environment(m_canopy.cell_shade, soil_water(), m_hydro->catchments(), &m_ratio,
                       m_ground_demand, m_ground_request, m_ground_env);
    for (std::size_t c = 0; c < m_ground_demand.size(); ++c) {
        m_sum.ground_demand_m3 += m_ground_demand[c];
        m_sum.ground_supplied_m3 += m_ground_demand[c] * m_ground_env[c].water_met;
    }
    // "Growth Rate" is the rate over a growing season: a leaf-on day grows 1/season of it.
    std::vector<double> season_phen(day.phen);
    for (std::size_t k = 0; k < species.size(); ++k)
        if (!species[k].evergreen)
            season_phen[k] *= static_cast<double>(year_length(w)) /
                              std::max(1, species[k].leaf_off_doy - species[k].leaf_on_doy);
    m_ground.accumulate(species, m_ground_env, 1.0 / year_length(w), season_phen, day.ftemp);
}

void Ecosystem::year_end_coupled() {
    const auto& species = m_scene.ecosystem.species;
    count_starved(); // since the last refresh; removed below
    std::vector<char> dead =
        ageing_and_mortality(m_pop, species, m_rng_mort, m_sum, m_scene.growth);
    const Seedbed bed = seedbed();
    const Nursery make = nursery();
    std::vector<Plant> recruits =
        seed_dispersal(m_pop, dead, species, plant_grid(), bed, make, m_rng_seed, m_sum);
    background_arrivals(species, plant_grid(), bed, make, m_rng_arrival, recruits);
    storm(dead);
    harvest(dead, false);
    count_deaths(dead);
    take_dead(&dead);
    for (std::size_t k = 0; k < m_pop.size(); ++k) {
        m_pop.growth_sum[k] = m_pop.growth_days[k] = 0;
        if (dead[k]) m_pop.alive[k] = 0;
    }
    remove_dead(m_pop, m_sum);
    for (const Plant& r : recruits) {
        m_sum.recruit_carbon += r.wood_kg + r.reserve_kg;
        m_pop.push(r);
    }
    m_sum.births += static_cast<double>(recruits.size());
    order_plants();
    refresh_canopy();
}

void Ecosystem::year_end_light_only() {
    const auto& species = m_scene.ecosystem.species;
    if (!m_ground.empty()) {
        // The ground layer in a whole-year step: light under the crowns, no water limit.
        ground_environment(m_canopy.cell_shade, soil_water(), m_hydro->catchments(), nullptr,
                           m_ground_demand, m_ground_request, m_ground_env);
        const std::vector<double> ones(species.size(), 1.0);
        m_ground.step(species, m_ground_env, 1.0, ones, ones);
    }
    std::vector<char> dead;
    if (m_scene.light_only_model == LightOnlyModel::mavs) {
        dead = mavs_step(m_pop, species, plant_grid(), m_scene.mavs_plant_density, nursery(),
                         m_rng_arrival, m_sum);
    } else {
        dead = light_only_growth(m_pop, species, m_sum);
        light_only_arrivals(m_pop, dead, species, plant_grid(), nursery(), m_rng_arrival, m_sum);
        overlap_thinning(m_pop, dead, species, plant_grid(), m_scene.light_only_radius, m_sum);
    }
    storm(dead);
    harvest(dead, true);
    count_deaths(dead);
    take_dead(&dead);
    for (char& d : dead) d = !d;
    m_pop.keep_if(dead);
    order_plants();
    refresh_canopy();
}

void Ecosystem::storm(std::vector<char>& dead) {
    m_storm = m_wind.strike(m_pop, m_scene.ecosystem.species, plant_grid(), m_years_done + 1, dead,
                            static_cast<char>(DeathCause::wind_uprooted),
                            static_cast<char>(DeathCause::wind_broken));
    m_dead.set_storm_azimuth(m_storm.to_azimuth_rad);
}

void Ecosystem::harvest(std::vector<char>& dead, bool allometric_mass) {
    if (m_scene.management.operations.empty()) return; // nothing to cut, nothing to count
    const auto& species = m_scene.ecosystem.species;
    const auto& pg = plant_grid();
    const double area_m2 = pg.width_m() * pg.height_m();
    std::vector<char> before = dead;
    const double spacing =
        exposed_spacing_m(m_pop, species, area_m2, m_scene.windthrow.min_height_m);
    if (mark_harvest(m_scene.management, m_pop, species, area_m2, m_years_done + 1, dead,
                     static_cast<char>(DeathCause::harvest)) > 0)
        m_wind.thinned(spacing, m_years_done + 1);
    count_harvest(before, dead, allometric_mass);
}

void Ecosystem::count_harvest(const std::vector<char>& before, const std::vector<char>& dead,
                              bool allometric_mass) {
    const auto& species = m_scene.ecosystem.species;
    const auto& pg = plant_grid();
    const double area_m2 = pg.width_m() * pg.height_m();
    for (std::size_t k = 0; k < m_pop.size(); ++k) {
        if (dead[k] == before[k]) continue;
        const Species& s = species[m_pop.species[k]];
        const double d = m_pop.dbh_m[k];
        m_harvest.stems += 1;
        m_harvest.basal_area_m2_per_ha += std::numbers::pi * d * d / 4 * 1e4 / area_m2;
        m_harvest.wood_kg += allometric_mass ? allometry::stem_mass_kg(s, d) : m_pop.wood_kg[k];
    }
}

void Ecosystem::set_next_rain_mm(double rain_mm) {
    if (!(rain_mm >= 0) || !std::isfinite(rain_mm))
        throw InputError("rain: the next day's rain must be a finite amount >= 0 mm, got " +
                         std::to_string(rain_mm));
    m_next_rain_mm = rain_mm;
}

std::size_t Ecosystem::remove_plants(const std::vector<std::int64_t>& ids) {
    std::unordered_map<std::int64_t, std::size_t> index;
    for (std::size_t k = 0; k < m_pop.size(); ++k)
        if (m_pop.alive[k]) index.emplace(m_pop.id[k], k);
    const std::vector<char> none(m_pop.size(), 0);
    std::vector<char> dead = none;
    for (const std::int64_t id : ids) {
        const auto it = index.find(id);
        if (it == index.end())
            throw InputError("remove_plants: no living plant has id " + std::to_string(id) +
                             " (nothing was removed)");
        dead[it->second] = static_cast<char>(DeathCause::harvest);
    }
    const bool coupled = m_scene.competition == Competition::coupled;
    if (coupled) count_starved(); // as at a year end: the starved are counted before the cut
    count_harvest(none, dead, !coupled);
    count_deaths(dead);
    take_dead(&dead);
    const auto removed = static_cast<std::size_t>(
        std::count_if(dead.begin(), dead.end(), [](char c) { return c != 0; }));
    if (coupled) { // the carbon of the cut leaves the stand as at a year end
        for (std::size_t k = 0; k < m_pop.size(); ++k)
            if (dead[k]) m_pop.alive[k] = 0;
        remove_dead(m_pop, m_sum);
    } else { // the light-only year end keeps the others, as here
        for (char& d : dead) d = !d;
        m_pop.keep_if(dead);
    }
    refresh_canopy();
    return removed;
}

void Ecosystem::take_dead(const std::vector<char>* causes) {
    m_dead.take_dead(m_pop, m_scene.ecosystem.species, causes,
                     m_scene.competition == Competition::light_only, m_years_done + 1);
}

void Ecosystem::year_end_common() {
    ++m_years_done;
    m_dead.step_year(m_scene.ecosystem.species, m_scene.hydro.dem, m_years_done);
    m_hydro->set_vegetation_density(
        m_canopy.vegetation_density(m_ground, m_scene.hydro.dem.grid()));
    const DeadWoodSums& d = m_dead.sums();
    record_year(close_carbon_budget(m_pop, m_sum, {m_dead.stock_kg(), d.input_kg, d.decay_kg},
                                    m_years_done, m_ledger));
    m_sum = PlantSums{};
    m_harvest = HarvestSums{};
    m_storm = StormResult{};
    m_dead.reset_sums();
}

void Ecosystem::record_year(const CarbonStocks& c) {
    const auto& hg = m_scene.hydro.dem.grid();
    const StandMetrics st = stand();
    const double to_mm = kMmPerM / (hg.width_m() * hg.height_m());
    YearRow row;
    row.year = m_years_done;
    row.basal_area_m2_per_ha = st.basal_area_m2_per_ha;
    row.stems_per_ha = st.stems_per_ha;
    row.mean_dbh_m = st.mean_dbh_m;
    row.quadratic_mean_dbh_m = st.quadratic_mean_dbh_m;
    row.reineke_sdi_per_ha = st.sdi_per_ha;
    row.live_plants = static_cast<double>(m_pop.size());
    row.births = m_sum.births;
    row.deaths_starvation = m_sum.deaths_starvation;
    row.deaths_age = m_sum.deaths_age;
    row.deaths_background = m_sum.deaths_background;
    row.deaths_suppression = m_sum.deaths_suppression;
    row.deaths_overlap = m_sum.deaths_overlap;
    row.seeds_dispersed = m_sum.seeds;
    row.seeds_lost_outside = m_sum.seeds_lost;
    row.production_kg = m_sum.production;
    row.maintenance_respiration_kg = m_sum.maintenance;
    row.growth_respiration_kg = m_sum.growth_resp;
    row.recruit_carbon_kg = m_sum.recruit_carbon;
    row.dead_carbon_kg = m_sum.dead_carbon;
    row.turnover_kg = m_sum.turnover;
    row.wood_stock_kg = c.wood_kg;
    row.reserve_stock_kg = c.reserve_kg;
    row.carbon_residual_kg = c.residual_kg;
    row.transpiration_demand_mm = m_sum.demand_m3 * to_mm;
    row.transpiration_supplied_mm = m_sum.supplied_m3 * to_mm;
    const UndergrowthMetrics u = undergrowth();
    row.shrubs_per_ha = u.shrubs_per_ha;
    row.ground_cover_fraction = u.ground_cover_fraction;
    row.ground_transpiration_demand_mm = m_sum.ground_demand_m3 * to_mm;
    row.ground_transpiration_supplied_mm = m_sum.ground_supplied_m3 * to_mm;
    const DeadWoodMetrics dm =
        deadwood_metrics(m_dead, m_scene.ecosystem.species, hg.width_m() * hg.height_m());
    const DeadWoodSums& ds = m_dead.sums();
    row.snags_per_ha = dm.snags_per_ha;
    row.logs_per_ha = dm.logs_per_ha;
    row.snag_volume_m3_per_ha = dm.snag_volume_m3_per_ha;
    row.log_volume_m3_per_ha = dm.log_volume_m3_per_ha;
    row.deadwood_volume_class1_m3_per_ha = dm.volume_by_class_m3_per_ha[0];
    row.deadwood_volume_class2_m3_per_ha = dm.volume_by_class_m3_per_ha[1];
    row.deadwood_volume_class3_m3_per_ha = dm.volume_by_class_m3_per_ha[2];
    row.deadwood_volume_class4_m3_per_ha = dm.volume_by_class_m3_per_ha[3];
    row.deadwood_volume_class5_m3_per_ha = dm.volume_by_class_m3_per_ha[4];
    row.deadwood_stock_kg = c.deadwood_kg;
    row.deadwood_input_kg = ds.input_kg;
    row.deadwood_decay_kg = ds.decay_kg;
    row.snags_fallen = ds.snags_fallen;
    row.stumps_per_ha = dm.stumps_per_ha;
    row.stump_volume_m3_per_ha = dm.stump_volume_m3_per_ha;
    row.harvested_stems = m_harvest.stems;
    row.harvested_basal_area_m2_per_ha = m_harvest.basal_area_m2_per_ha;
    row.harvested_wood_kg = m_harvest.wood_kg - ds.cut_kept_kg;
    row.storm_wind_m_per_s = m_storm.wind_m_per_s;
    row.windthrow_uprooted = m_storm.uprooted;
    row.windthrow_broken = m_storm.broken;
    row.windthrow_basal_area_m2_per_ha = m_storm.basal_area_m2_per_ha;
    row.root_plates_per_ha = dm.root_plates_per_ha;
    row.storm_severe = m_storm.severe ? 1 : 0;
    m_yearly.push(row, yearly_columns());
    yearly_water_from_daily(m_daily, m_yearly, m_yearly.rows() - 1);
}

Diagnosis Ecosystem::diagnosis() const {
    const auto& species = m_scene.ecosystem.species;
    const auto& hg = m_scene.hydro.dem.grid();
    DiagnosisInput in{
        species, m_diag, std::vector<double>(species.size(), 0.0), {}, 0, {}, 0, false, 1, "", 0};
    for (std::size_t k = 0; k < m_pop.size(); ++k)
        if (m_pop.alive[k]) in.living[m_pop.species[k]] += 1;
    in.stand = stand();
    in.years = m_years_done;
    in.target_basal_area_m2_per_ha = m_scene.target_basal_area_m2_per_ha;
    const auto& ba = m_yearly.column("basal_area_m2_per_ha");
    if (ba.size() >= 2) {
        const std::size_t back = std::min<std::size_t>(5, ba.size() - 1);
        in.basal_area_growth_m2_per_ha_per_yr =
            (ba.back() - ba[ba.size() - 1 - back]) / static_cast<double>(back);
    }
    in.light_only = m_scene.competition == Competition::light_only;
    in.area_ha = plant_grid().width_m() * plant_grid().height_m() / 1e4;
    const auto& soil = m_scene.hydro.soil;
    std::vector<double> classes(12, 0.0);
    double ph = 0, n = 0;
    for (std::int64_t c = 0; c < hg.size(); ++c) {
        const int i = static_cast<int>(c % hg.nx), j = static_cast<int>(c / hg.nx);
        if (std::isnan(m_scene.hydro.dem(i, j))) continue;
        classes[std::min<std::size_t>(11, static_cast<std::size_t>(soil.texture(i, j)))] += 1;
        ph += soil.ph(i, j);
        n += 1;
    }
    in.soil_texture = hydro::texture_name(static_cast<hydro::Texture>(
        std::max_element(classes.begin(), classes.end()) - classes.begin()));
    in.soil_ph = n > 0 ? ph / n : 0;
    return diagnose(in);
}

StandMetrics Ecosystem::stand() const {
    const auto& sp = m_scene.ecosystem.species;
    std::vector<double> d;
    d.reserve(m_pop.size());
    for (std::size_t k = 0; k < m_pop.size(); ++k)
        if (sp[m_pop.species[k]].life_form == LifeForm::tree)
            d.push_back(m_pop.dbh_m[k]); // 0 below 1.3 m
    return stand_metrics(d, plant_grid().width_m() * plant_grid().height_m());
}

UndergrowthMetrics Ecosystem::undergrowth() const {
    const auto& sp = m_scene.ecosystem.species;
    UndergrowthCounter count;
    for (std::size_t k = 0; k < m_pop.size(); ++k)
        count.add(sp[m_pop.species[k]].life_form, m_pop.crown_radius_m[k], m_pop.height_m[k]);
    UndergrowthMetrics u = count.metrics(plant_grid().width_m() * plant_grid().height_m());
    const auto cells = static_cast<double>(std::max<std::int64_t>(m_ground.cells(), 1));
    for (std::size_t g = 0; g < m_ground.species().size(); ++g) {
        double a = 0;
        for (std::int64_t c = 0; c < m_ground.cells(); ++c) a += m_ground.cover(g, c);
        u.ground_cover_by_species.push_back({m_ground.species()[g], a / cells});
        u.ground_cover_fraction += a / cells;
    }
    return u;
}

RasterD Ecosystem::ground_cover() const {
    RasterD r(m_scene.hydro.dem.grid(), 0.0);
    for (std::int64_t c = 0; c < r.size(); ++c) r.data()[c] = m_ground.total(c);
    return r;
}

RasterD Ecosystem::ground_cover(std::size_t g) const {
    RasterD r(m_scene.hydro.dem.grid(), 0.0);
    for (std::int64_t c = 0; c < r.size(); ++c) r.data()[c] = m_ground.cover(g, c);
    return r;
}

std::uint64_t Ecosystem::observed_weather_hash() const {
    if (!m_scene.hydro.observed) return 0;
    // FNV-1a over the day values (field by field, whatever the layout of DayWeather).
    std::uint64_t h = kFnvOffsetBasis;
    for (const auto& d : m_scene.hydro.observed->days) {
        h = fnv1a64(&d.year, sizeof d.year, h);
        h = fnv1a64(&d.doy, sizeof d.doy, h);
        for (double v : {d.tmin_c, d.tmax_c, d.rain_mm, d.tdew_c, d.u2_m_per_s, d.rs_mj})
            h = fnv1a64(&v, sizeof v, h);
    }
    return h | 1; // never 0, the generator's value
}

double Ecosystem::carbon_residual_relative() const {
    return std::abs(m_ledger.cumulative_residual_kg) /
           std::max(m_ledger.cumulative_throughput_kg, 1e-300);
}

namespace {
/// Whether column `c` of `t` is stored as integers in a run file (hydro::write_table).
bool integer_column(const Table& t, std::size_t c) {
    return c < t.types.size() &&
           (t.types[c] == ColumnType::int64 || t.types[c] == ColumnType::int32);
}

/// Whether every integer column of `t` reads back from a run file as itself: whole numbers within
/// a double's exact integers, and no negative zero.
bool round_trips(const Table& t) {
    for (std::size_t c = 0; c < t.names.size(); ++c) {
        if (!integer_column(t, c)) continue;
        for (const double x : t.columns[c])
            if (!(std::abs(x) <= 9007199254740992.0) || x != std::trunc(x) ||
                (x == 0 && std::signbit(x)))
                return false;
    }
    return true;
}

/// FNV-1a over a column's values as a run file stores them: whole numbers, or the doubles' bits.
std::uint64_t column_hash(const std::vector<double>& v, bool integer) {
    std::uint64_t h = kFnvOffsetBasis;
    for (const double x : v)
        h = fnv1a64_fold(h, integer ? static_cast<std::uint64_t>(static_cast<std::int64_t>(x))
                                    : std::bit_cast<std::uint64_t>(x));
    return h;
}

/// The series section: a flag (1: the values are in the run file), then per table its columns by
/// name, each with its values, or with its row count and hash.
void save_series(ArchiveWriter& s, const std::array<const Table*, 2>& tables, bool outside) {
    s.put<std::uint8_t>(outside ? 1 : 0);
    for (const Table* t : tables) {
        s.put<std::uint64_t>(t->names.size());
        for (std::size_t c = 0; c < t->names.size(); ++c) {
            s.put_string(t->names[c]);
            if (!outside) {
                s.put_vector(t->columns[c]);
                continue;
            }
            s.put<std::uint64_t>(t->columns[c].size());
            s.put<std::uint64_t>(column_hash(t->columns[c], integer_column(*t, c)));
        }
    }
}
} // namespace

void Ecosystem::save_state(ArchiveWriter& a, SeriesIn series) const {
    if (m_ground.pending())
        throw Error("internal: a checkpoint with ground-layer days not yet applied");
    a.put(kCheckpointMagic);
    a.put(kCheckpointVersion);
    SectionWriter w(a);
    w.section("clock", kSectionClock, [&](ArchiveWriter& s) {
        s.put(m_years_done);
        s.put(m_days_done);
        s.put(m_weather);
        s.put(observed_weather_hash());
        s.put(m_gen.state());
    });
    w.section("random", kSectionRandom, [&](ArchiveWriter& s) {
        s.put(m_rng_seed.state());
        s.put(m_rng_mort.state());
        s.put(m_rng_arrival.state());
    });
    w.section("plants", kSectionPlants, [&](ArchiveWriter& s) {
        m_pop.save(s);
        s.put(m_next_id);
    });
    w.section("canopy", kSectionCanopy,
              [&](ArchiveWriter& s) { s.put_raster(m_canopy.ground_shade); });
    w.section("ground_layer", kSectionGround,
              [&](ArchiveWriter& s) { s.put_vector(m_ground.raw()); });
    w.section("hydrology", kSectionHydro, [&](ArchiveWriter& s) {
        m_hydro->save_state(s);
        s.put_raster(m_hydro->vegetation_density());
    });
    const bool outside =
        series == SeriesIn::run_file && round_trips(m_daily) && round_trips(m_yearly);
    w.section("series", kSectionSeries, [&](ArchiveWriter& s) {
        save_series(s, {&m_daily, &m_yearly}, outside);
    });
    w.section("budget", kSectionBudget, [&](ArchiveWriter& s) {
        s.put(m_sum);
        s.put(m_ledger);
    });
    w.section("deadwood", kSectionDeadWood, [&](ArchiveWriter& s) { m_dead.save(s); });
    w.section("windthrow", kSectionWindthrow, [&](ArchiveWriter& s) { m_wind.save(s); });
    w.section("diagnosis", kSectionDiagnosis, [&](ArchiveWriter& s) { s.put_vector(m_diag); });
}

namespace {
/// The index of column `name` in `t`; CheckpointError naming it when this ecoterra lacks it.
std::size_t column_index(const Table& t, const std::string& name, const char* which) {
    const auto it = std::find(t.names.begin(), t.names.end(), name);
    if (it == t.names.end())
        throw CheckpointError(std::string("checkpoint section 'series': the ") + which +
                              " series has a column '" + name + "' this ecoterra does not write");
    return static_cast<std::size_t>(it - t.names.begin());
}

/// Reads a series table by column name, the values from the checkpoint or, when `source` is
/// given, from the run file (checked against the row count and hash the checkpoint holds): a
/// column the checkpoint lacks (added since) is NaN in the rows before the resume; one this
/// ecoterra lacks is an error naming it.
void load_table(ArchiveReader& a, Table& t, const char* which,
                const Ecosystem::SeriesSource* source) {
    const auto n = a.get<std::uint64_t>();
    std::vector<bool> seen(t.names.size(), false);
    std::size_t rows = 0;
    for (std::uint64_t k = 0; k < n; ++k) {
        const std::string name = a.get_string();
        if (!source) {
            const std::size_t c = column_index(t, name, which);
            t.columns[c] = a.get_vector<double>();
            rows = t.columns[c].size();
            seen[c] = true;
            continue;
        }
        const auto saved_rows = a.get<std::uint64_t>();
        const auto hash = a.get<std::uint64_t>();
        const std::size_t c = column_index(t, name, which);
        auto values = (*source)(which, name);
        if (values.size() != saved_rows || column_hash(values, integer_column(t, c)) != hash)
            throw CheckpointError(
                std::string("the run file's /series/") + which + "/" + name +
                " is not the column its checkpoint was saved with (" +
                std::to_string(values.size()) + " rows against " + std::to_string(saved_rows) +
                (values.size() == saved_rows ? ", other values" : "") + "): it is damaged");
        rows = values.size();
        t.columns[c] = std::move(values);
        seen[c] = true;
    }
    for (std::size_t c = 0; c < t.names.size(); ++c)
        if (!seen[c]) t.columns[c].assign(rows, std::numeric_limits<double>::quiet_NaN());
}
} // namespace

void Ecosystem::load_state(ArchiveReader& a, const SeriesSource& series) {
    if (a.get<std::uint32_t>() != kCheckpointMagic)
        throw CheckpointError("the checkpoint is not an ecoterra ecosystem checkpoint");
    const auto version = a.get<std::uint32_t>();
    if (version == kCheckpointVersion)
        load_sections(a, series);
    else if (version == kLastUnsectionedVersion)
        load_version6(a);
    else
        throw CheckpointError("the checkpoint has format version " + std::to_string(version) +
                              ", this ecoterra reads versions " +
                              std::to_string(kLastUnsectionedVersion) + " and " +
                              std::to_string(kCheckpointVersion));
    // Crowns and roots are derived from the plants; shade fractions are restored with them.
    m_canopy.rebuild(m_pop);
    m_canopy.shade_per_cell();
}

void Ecosystem::load_sections(ArchiveReader& a, const SeriesSource& series) {
    SectionReader r(a, "the checkpoint");
    r.read("clock", kSectionClock, kSectionClock, [&](ArchiveReader& s, std::uint32_t) {
        m_years_done = s.get<int>();
        m_days_done = s.get<int>();
        m_weather = s.get<hydro::DayWeather>();
        if (s.get<std::uint64_t>() != observed_weather_hash())
            throw CheckpointError(
                m_scene.hydro.observed
                    ? "the observed weather series differs from the one the run was "
                      "made with (was the weather CSV changed?)"
                    : "the checkpoint was made with observed weather, the scene has none");
        m_gen.set_state(s.get<hydro::WeatherGenerator::State>());
    });
    r.read("random", kSectionRandom, kSectionRandom, [&](ArchiveReader& s, std::uint32_t) {
        m_rng_seed.set_state(s.get<std::array<std::uint64_t, 4>>());
        m_rng_mort.set_state(s.get<std::array<std::uint64_t, 4>>());
        m_rng_arrival.set_state(s.get<std::array<std::uint64_t, 4>>());
    });
    r.read("plants", kSectionPlants, kSectionPlants, [&](ArchiveReader& s, std::uint32_t) {
        m_pop.load(s);
        m_next_id = s.get<std::int64_t>();
    });
    r.read("canopy", kSectionCanopy, kSectionCanopy, [&](ArchiveReader& s, std::uint32_t) {
        m_canopy.ground_shade = s.get_raster<double>();
    });
    r.read("ground_layer", kSectionGround, kSectionGround,
           [&](ArchiveReader& s, std::uint32_t) { m_ground.set_raw(s.get_vector<double>()); });
    std::uint32_t hydro_version = kSectionHydro;
    r.read("hydrology", 1, kSectionHydro, [&](ArchiveReader& s, std::uint32_t version) {
        hydro_version = version;
        m_hydro->load_state(s, version);
        m_hydro->set_vegetation_density(s.get_raster<double>());
    });
    r.read("series", 1, kSectionSeries, [&](ArchiveReader& s, std::uint32_t version) {
        const bool outside = version >= 2 && s.get<std::uint8_t>() == 1;
        if (outside && !series)
            throw CheckpointError("checkpoint section 'series': the series are kept in the run "
                                  "file's /series, and none were given (resume from the run "
                                  "file)");
        load_table(s, m_daily, "daily", outside ? &series : nullptr);
        if (hydro_version < 2) zero_surface_layer_era_columns(m_daily);
        load_table(s, m_yearly, "yearly", outside ? &series : nullptr);
        // Checkpoints from before the yearly water columns: their sums are in the daily series.
        if (std::isnan(m_yearly.rows() ? m_yearly.column("rain_mm").front() : 0.0))
            yearly_water_from_daily(m_daily, m_yearly, 0);
    });
    r.read("budget", kSectionBudget, kSectionBudget, [&](ArchiveReader& s, std::uint32_t) {
        m_sum = s.get<PlantSums>();
        m_ledger = s.get<CarbonLedger>();
    });
    // Checkpoints from before dead wood have none: the trees that died then left nothing.
    if (r.version("deadwood") != 0)
        r.read("deadwood", 1, kSectionDeadWood,
               [&](ArchiveReader& s, std::uint32_t) { m_dead.load(s); });
    // Checkpoints from before windthrow: the storm stream starts afresh at the resume.
    if (r.version("windthrow") != 0)
        r.read("windthrow", 1, kSectionWindthrow,
               [&](ArchiveReader& s, std::uint32_t) { m_wind.load(s); });
    // Checkpoints from before the diagnosis: its counts start at the resume.
    if (r.version("diagnosis") != 0)
        r.read("diagnosis", 1, kSectionDiagnosis, [&](ArchiveReader& s, std::uint32_t) {
            auto d = s.get_vector<SpeciesLedger>();
            if (d.size() != m_diag.size())
                throw CheckpointError(
                    "checkpoint section 'diagnosis': " + std::to_string(d.size()) +
                    " species, the scene has " + std::to_string(m_diag.size()));
            m_diag = std::move(d);
        });
    r.finish();
}

void Ecosystem::load_version6(ArchiveReader& a) {
    // Format 6 (ecoterra before the sections): the same state, in one sequence, the plants as
    // rows (Plant has no padding, so the rows are their bytes).
    m_years_done = a.get<int>();
    m_days_done = a.get<int>();
    m_weather = a.get<hydro::DayWeather>();
    if (a.get<std::uint64_t>() != observed_weather_hash())
        throw CheckpointError("the observed weather series differs from the one the run was made "
                              "with, or only one of them has observed weather");
    m_gen.set_state(a.get<hydro::WeatherGenerator::State>());
    m_rng_seed.set_state(a.get<std::array<std::uint64_t, 4>>());
    m_rng_mort.set_state(a.get<std::array<std::uint64_t, 4>>());
    m_rng_arrival.set_state(a.get<std::array<std::uint64_t, 4>>());
    m_pop.clear();
    for (const Plant& p : a.get_vector<Plant>()) m_pop.push(p);
    m_next_id = a.get<std::int64_t>();
    m_canopy.ground_shade = a.get_raster<double>();
    m_ground.set_raw(a.get_vector<double>());
    m_hydro->load_state(a, 1);
    m_hydro->set_vegetation_density(a.get_raster<double>());
    // Format 6 predates the interception and drainage columns.
    for (std::size_t c = 0; c < m_daily.columns.size(); ++c)
        if (!is_surface_layer_era_column(m_daily.names[c]))
            m_daily.columns[c] = a.get_vector<double>();
    zero_surface_layer_era_columns(m_daily);
    // ... and the yearly water columns, summed from the daily series, and dead wood (there was
    // none: its columns hold 0).
    std::vector<std::size_t> dead_wood_columns;
    for (std::size_t c = 0; c < m_yearly.columns.size(); ++c) {
        if (is_dead_wood_column(m_yearly.names[c]))
            dead_wood_columns.push_back(c);
        else if (std::none_of(kYearlyWater.begin(), kYearlyWater.end(),
                              [&](const auto& w) { return m_yearly.names[c] == w.first; }))
            m_yearly.columns[c] = a.get_vector<double>();
    }
    for (const std::size_t c : dead_wood_columns) m_yearly.columns[c].assign(m_yearly.rows(), 0.0);
    yearly_water_from_daily(m_daily, m_yearly, 0);
    m_sum = a.get<PlantSums>();
    m_ledger.stock_at_year_start_kg = a.get<double>();
    m_ledger.cumulative_residual_kg = a.get<double>();
    m_ledger.cumulative_throughput_kg = a.get<double>();
}

} // namespace ecoterra::eco
