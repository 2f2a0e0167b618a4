#include "ecoterra/eco/ecosystem.hpp"
#include "ecoterra/units.hpp"

#include "ecoterra/eco/dispersal.hpp"
#include "ecoterra/eco/growth.hpp"
#include "ecoterra/eco/roots.hpp"
#include "ecoterra/hydro/penman.hpp"
#include "ecoterra/parallel.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>

namespace ecoterra::eco {

namespace {
/// Light-only mode: diameters approach the one at which H = 95 % of Hmax (MAVS's saturating
/// growth curve applied to the stem, see docs/ecosystem.md s6).
constexpr double kLightOnlyHeightFraction = 0.95;
/// The diameter at which H = kLightOnlyHeightFraction * Hmax, m.
double light_only_d95_m(const Species& s) {
    return -std::log(1 - kLightOnlyHeightFraction) / s.height_dbh_slope_per_cm / kCmPerM;
}
/// Light-only growth curve D(t) = D95 (1 - exp(-r t)).
double light_only_dbh_m(const Species& s, double age_yr) {
    return light_only_d95_m(s) * (1 - std::exp(-s.growth_rate_per_yr * age_yr));
}
/// Age on the light-only curve of an initial stem: the diameter's share of D95 is capped here (a
/// stem at or above D95 gets the age of this share), and 1 - share floored at kMinRemainder.
constexpr double kLightOnlyMaxShareOfD95 = 0.999;
constexpr double kMinRemainder = 1e-9;
/// The yearly carbon check: |cumulative residual| may reach this share of the cumulative
/// throughput (at least 1 kg of it) plus kCarbonStockRounding of the stock.
constexpr double kCarbonTolerance = 1e-9;
constexpr double kCarbonStockRounding = 1e-12;
/// Memory per plant-grid cell: the ground shade and the shading pass's work rasters, bytes.
constexpr double kPlantGridBytesPerCell = 24.0;
/// Field capacity minus wilting point below which the relative soil water is taken as dry.
constexpr double kMinAvailableWater = 1e-9;
/// Stem files: the age and diameter a listed stem may have.
constexpr double kMaxStemAgeYr = 10000;
constexpr double kMaxStemDbhCm = 500;
/// MAVS's competitive radius is half of its height-to-diameter ratio times the height.
double mavs_competition_radius_m(const Species& s, double height_m) {
    return 0.5 * s.height_to_diameter_ratio * height_m;
}
constexpr std::uint32_t kCheckpointMagic = 0x45434f54; // "ECOT"
// 4: catchments on the depression hierarchy; 5: no padding in plants and the weather state,
// bands sorted once (the order wet cells are walked in)
// 6: life forms (the ground layer's cover)
constexpr std::uint32_t kCheckpointVersion = 6;
} // namespace

Ecosystem::Ecosystem(const EcoScene& scene)
    : m_scene(scene), m_gen(scene.hydro.climate, scene.seed), m_rng_seed(scene.seed, "eco.seeding"),
      m_rng_mort(scene.seed, "eco.mortality"), m_rng_arrival(scene.seed, "eco.arrival") {
    const auto& hg = scene.hydro.dem.grid();
    m_map.factor = static_cast<int>(std::lround(hg.cell_size_m / scene.plant_cell_m));
    m_map.hydro_nx = hg.nx;
    m_pgrid = hg;
    m_pgrid.cell_size_m = hg.cell_size_m / m_map.factor;
    m_pgrid.nx = hg.nx * m_map.factor;
    m_pgrid.ny = hg.ny * m_map.factor;
    ensure_fits_in_memory(m_pgrid.size(), kPlantGridBytesPerCell, "the plant grid");
    m_hydro_cell_area = hg.cell_size_m * hg.cell_size_m;
    m_hydro =
        std::make_unique<hydro::HydrologyModel>(scene.hydro.dem, scene.hydro.soil, RasterD(hg, 0.0),
                                                scene.hydro.options, scene.hydro.climate);
    m_ground_shade = RasterD(m_pgrid, 0.0);
    m_request_mm = RasterD(hg, 0.0);
    const auto& species = scene.ecosystem.species;
    for (const auto& s : species) m_is_object.push_back(s.life_form == LifeForm::object);
    const auto& soil = scene.hydro.soil;
    m_ground = GroundLayer(species, hg.size(), [&](std::uint16_t k, std::int64_t c) {
        const int i = static_cast<int>(c % hg.nx), j = static_cast<int>(c / hg.nx);
        const Species& s = species[k];
        return texture_factor(s.texture, s.texture_tolerance_pct, soil.sand_pct(i, j),
                              soil.silt_pct(i, j), soil.clay_pct(i, j)) *
               ph_factor(s.ph, soil.ph(i, j));
    });
    m_daily = Table::of(hydro::daily_budget_columns());
    m_yearly = Table::of(yearly_columns());
    place_initial_plants();
    refresh_canopy();
    update_vegetation_density();
    for (const auto& p : m_plants) m_stock_at_year_start += p.wood_kg + p.reserve_kg;
}

Ecosystem::~Ecosystem() = default;

Plant Ecosystem::new_plant(std::uint16_t sp, double x, double y, double dbh) {
    const Species& s = m_scene.ecosystem.species[sp];
    const auto& soil = m_scene.hydro.soil;
    Plant p;
    p.id = m_next_id++;
    p.species = sp;
    p.x_m = x;
    p.y_m = y;
    p.z_m = m_scene.hydro.dem.sample_bilinear(x, y);
    p.dbh_m = dbh;
    if (s.life_form == LifeForm::object) {
        allometry::apply(s, p); // full size, no carbon
    } else if (m_scene.competition == Competition::light_only) {
        p.dbh_m = 0;
        allometry::apply(s, p);
        p.height_m = 0;
    } else {
        allometry::apply(s, p);
        p.wood_kg = allometry::stem_mass_kg(s, dbh);
        p.reserve_kg =
            s.initial_reserve_fraction * s.reserve_capacity_kg_per_m2_leaf * p.leaf_area_m2;
        p.mass_at_year_start_kg = p.wood_kg + p.reserve_kg;
    }
    const auto [i, j] = soil.grid().clamped_cell(x, y);
    p.soil_factor = texture_factor(s.texture, s.texture_tolerance_pct, soil.sand_pct(i, j),
                                   soil.silt_pct(i, j), soil.clay_pct(i, j)) *
                    ph_factor(s.ph, soil.ph(i, j));
    return p;
}

void Ecosystem::place_initial_plants() {
    const auto& ini = m_scene.initial;
    const auto& g = m_pgrid;
    const auto nsp = static_cast<std::uint16_t>(m_scene.ecosystem.species.size());
    if (ini.kind == InitialPlants::Kind::random) {
        Rng rng(m_scene.seed, "eco.initial");
        const double area_ha = g.width_m() * g.height_m() / kM2PerHa;
        const std::int64_t n = std::llround(ini.stems_per_ha * area_ha);
        // Trees and shrubs only (the ground layer starts bare; objects arrive).
        std::vector<std::uint16_t> plants;
        for (std::uint16_t k = 0; k < nsp; ++k)
            if (is_individual_plant(m_scene.ecosystem.species[k])) plants.push_back(k);
        if (n > 0 && plants.empty())
            throw InputError("vegetation.initial: random stems need a tree or shrub species in " +
                             m_scene.ecosystem.source.string());
        for (std::int64_t k = 0; k < n; ++k) {
            const auto sp = plants[static_cast<std::size_t>(rng.below(plants.size()))];
            const double x = g.origin_x_m + rng.uniform() * g.width_m();
            const double y = g.origin_y_m + rng.uniform() * g.height_m();
            const Species& s = m_scene.ecosystem.species[sp];
            const double d = rng.uniform(s.recruit_dbh_m, std::max(ini.max_dbh_m, s.recruit_dbh_m));
            Plant p = new_plant(sp, x, y, d);
            if (m_scene.competition == Competition::light_only) {
                // Age that gives this diameter on the light-only growth curve.
                p.age_yr = std::ceil(
                    -std::log(std::max(kMinRemainder, 1 - std::min(d / light_only_d95_m(s),
                                                                   kLightOnlyMaxShareOfD95))) /
                    s.growth_rate_per_yr);
                p.dbh_m = light_only_dbh_m(s, p.age_yr);
                allometry::apply(s, p);
            }
            m_plants.push_back(p);
        }
    } else if (ini.kind == InitialPlants::Kind::file) {
        std::ifstream in(ini.file);
        if (!in) throw InputError(ini.file.string() + ": cannot open the initial plant list");
        std::string line;
        std::getline(in, line);
        if (line.rfind("x_m,y_m,species,dbh_cm", 0) != 0)
            throw InputError(ini.file.string() +
                             ": the header must start with x_m,y_m,species,dbh_cm, got '" + line +
                             "'");
        int lineno = 1;
        while (std::getline(in, line)) {
            ++lineno;
            if (line.empty()) continue;
            std::stringstream ss(line);
            constexpr int kColumns = 5, kRequiredColumns = 4; // x_m,y_m,species,dbh_cm[,age_yr]
            std::string f[kColumns];
            int nf = 0;
            while (nf < kColumns && std::getline(ss, f[nf], ',')) ++nf;
            const std::string where = ini.file.string() + " line " + std::to_string(lineno);
            if (nf < kRequiredColumns)
                throw InputError(where + ": expected x_m,y_m,species,dbh_cm[,age_yr]");
            // Numbers in full (no "12abc"), finite; the column is named with its value.
            auto number = [&](int k, const char* column) {
                std::string v = f[k];
                v.erase(0, v.find_first_not_of(" \t\r"));
                v.erase(v.find_last_not_of(" \t\r") + 1);
                double out = 0;
                std::size_t used = 0;
                try {
                    out = std::stod(v, &used);
                } catch (const std::exception&) {
                    used = 0;
                }
                if (v.empty() || used != v.size() || !std::isfinite(out))
                    throw InputError(where + ": " + column + " = '" + f[k] +
                                     "' is not a finite number");
                return out;
            };
            const double x = number(0, "x_m"), y = number(1, "y_m"), dcm = number(3, "dbh_cm");
            const double age = nf == kColumns ? number(4, "age_yr") : 0.0;
            if (age < 0 || age > kMaxStemAgeYr)
                throw InputError(where + ": age_yr = " + f[4] + " is outside [0, " +
                                 format_number(kMaxStemAgeYr) + "]");
            if (!g.contains_point(x, y))
                throw InputError(where + ": position (" + format_number(x) + ", " +
                                 format_number(y) + ") m is outside the terrain");
            if (!(dcm > 0 && dcm < kMaxStemDbhCm))
                throw InputError(where + ": dbh_cm = " + f[3] + " is outside (0, " +
                                 format_number(kMaxStemDbhCm) + ")");
            int sp = -1;
            for (std::size_t k = 0; k < nsp; ++k) {
                const auto& s = m_scene.ecosystem.species[k];
                if (s.name == f[2] || s.mesh_file == f[2]) sp = static_cast<int>(k);
            }
            if (sp < 0)
                throw InputError(where + ": species '" + f[2] + "' is not in " +
                                 m_scene.ecosystem.source.string());
            if (!is_individual_plant(m_scene.ecosystem.species[static_cast<std::size_t>(sp)]))
                throw InputError(
                    where + ": species '" + f[2] + "' is a " +
                    life_form_name(
                        m_scene.ecosystem.species[static_cast<std::size_t>(sp)].life_form) +
                    ", not a tree or shrub: it has no stem to list");
            Plant p = new_plant(static_cast<std::uint16_t>(sp), x, y, dcm / kCmPerM);
            p.age_yr = age;
            if (m_scene.competition == Competition::light_only) {
                p.dbh_m = dcm / kCmPerM;
                allometry::apply(m_scene.ecosystem.species[static_cast<std::size_t>(sp)], p);
            }
            m_plants.push_back(p);
        }
    }
}

void Ecosystem::refresh_canopy() {
    remove_dead();
    const auto& sp = m_scene.ecosystem.species;
    const auto n = static_cast<std::int64_t>(m_plants.size());
    if (m_scene.competition == Competition::coupled) {
#pragma omp parallel for schedule(static) if (n >= parallel_min_items())
        for (std::int64_t k = 0; k < n; ++k) {
            Plant& p = m_plants[static_cast<std::size_t>(k)];
            const Species& s = sp[p.species];
            if (s.life_form == LifeForm::object) continue;
            p.dbh_m = allometry::dbh_from_stem_mass(s, p.wood_kg, p.dbh_m);
            allometry::apply(s, p);
        }
    }
    rebuild_crowns();
    std::vector<double> h(m_plants.size()), lai(m_plants.size());
    for (std::size_t k = 0; k < m_plants.size(); ++k) {
        const Plant& p = m_plants[k];
        h[k] = p.height_m;
        lai[k] = m_is_object[p.species] ? 0.0 : sp[p.species].leaf_area_per_crown_area;
    }
    const auto shade = compute_shading(m_pgrid, m_crowns, h, lai, m_scene.shading,
                                       m_scene.extinction, &m_ground_shade);
    for (std::size_t k = 0; k < m_plants.size(); ++k) m_plants[k].shade_fraction = shade[k];
    crown_shade_per_cell();
}

void Ecosystem::crown_shade_per_cell() {
    const auto& hg = m_scene.hydro.dem.grid();
    m_cell_shade.assign(static_cast<std::size_t>(hg.size()), 0.0);
    const double inv = 1.0 / (m_map.factor * m_map.factor);
    for (int j = 0; j < m_pgrid.ny; ++j)
        for (int i = 0; i < m_pgrid.nx; ++i)
            m_cell_shade[static_cast<std::size_t>(j / m_map.factor) * hg.nx + i / m_map.factor] +=
                m_ground_shade(i, j) * inv;
    for (auto& v : m_cell_shade) v = std::clamp(v, 0.0, 1.0);
}

double Ecosystem::relative_water(int hi, int hj) const {
    const auto& soil = m_scene.hydro.soil;
    const double wp = soil.wilting_point(hi, hj), fc = soil.field_capacity(hi, hj);
    return (m_hydro->soil_moisture()(hi, hj) - wp) / std::max(fc - wp, kMinAvailableWater);
}

void Ecosystem::ground_environment(bool coupled) {
    const auto& hg = m_scene.hydro.dem.grid();
    m_ground_env.resize(static_cast<std::size_t>(hg.size()));
    for (std::int64_t c = 0; c < hg.size(); ++c) {
        GroundCell& e = m_ground_env[static_cast<std::size_t>(c)];
        const auto k = static_cast<std::size_t>(c);
        e.crown_shade = m_cell_shade[k];
        e.relative_water = relative_water(static_cast<int>(c % hg.nx), static_cast<int>(c / hg.nx));
        e.ponded = m_hydro->catchments().owner(c) != 0;
        e.water_met = 1.0;
        if (coupled && m_ground_demand[k] > 0)
            e.water_met = m_ratio[k] * m_ground_request[k] / m_ground_demand[k];
    }
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
    return m_weather;
}

void Ecosystem::plant_water_demand(double et0_m, const std::vector<double>& phen) {
    const auto& species = m_scene.ecosystem.species;
    const auto& hg = m_scene.hydro.dem.grid();
    const std::size_t n = m_plants.size();
    m_demand.assign(n, 0.0);
    for (std::size_t k = 0; k < n; ++k) {
        const Plant& p = m_plants[k];
        if (!p.alive) continue;
        m_demand[k] = species[p.species].transpiration_per_leaf_area * p.leaf_area_m2 *
                      phen[p.species] * et0_m;
    }
    m_request.assign(static_cast<std::size_t>(hg.size()), 0.0);
    scatter_demand(m_roots, m_demand, m_request);
    // The ground layer asks for its demand, at most the water above its roots.
    m_ground_demand.assign(m_request.size(), 0.0);
    m_ground_request.assign(m_request.size(), 0.0);
    if (!m_ground.empty()) {
        const double zr = m_scene.hydro.options.root_zone_depth_m;
        const auto& soil = m_scene.hydro.soil;
        for (std::int64_t c = 0; c < hg.size(); ++c) {
            const auto k = static_cast<std::size_t>(c);
            const double d = m_ground.demand_m3(species, c, phen, et0_m, m_hydro_cell_area);
            if (!(d > 0)) continue;
            const int i = static_cast<int>(c % hg.nx), j = static_cast<int>(c / hg.nx);
            const double above =
                std::max(0.0, m_hydro->soil_moisture()(i, j) - soil.wilting_point(i, j)) *
                std::min(m_ground.root_depth_m(species, c), zr) * m_hydro_cell_area;
            m_ground_demand[k] = d;
            m_ground_request[k] = std::min(d, above);
            m_request[k] += m_ground_request[k];
        }
    }
    for (std::int64_t c = 0; c < hg.size(); ++c)
        m_request_mm.data()[c] =
            m_request[static_cast<std::size_t>(c)] / m_hydro_cell_area * kMmPerM;
}

void Ecosystem::water_supply_fractions() {
    const auto& hg = m_scene.hydro.dem.grid();
    const auto& supplied = m_hydro->transpiration_supplied_mm();
    m_ratio.assign(static_cast<std::size_t>(hg.size()), 1.0);
    bool all_met = true;
    for (std::int64_t c = 0; c < hg.size(); ++c) {
        const double r = m_request_mm.data()[c];
        if (r > 0) {
            const double q = std::min(1.0, supplied.data()[c] / r);
            m_ratio[static_cast<std::size_t>(c)] = q;
            all_met = all_met && q == 1.0;
        }
    }
    if (all_met)
        m_fraction.assign(m_plants.size(), 1.0);
    else
        gather_supply(m_roots, m_ratio, m_fraction);
}

void Ecosystem::carbon_balance(const std::vector<double>& phen, const std::vector<double>& ftemp,
                               double q10) {
    const auto& species = m_scene.ecosystem.species;
    const std::size_t n = m_plants.size();
    std::vector<CarbonDay>& cd = m_carbon;
    cd.assign(n, CarbonDay{});
#pragma omp parallel for schedule(static) if (static_cast <std::int64_t>(n) >= parallel_min_items())
    for (std::int64_t k = 0; k < static_cast<std::int64_t>(n); ++k) {
        Plant& p = m_plants[static_cast<std::size_t>(k)];
        if (!p.alive || m_is_object[p.species]) continue;
        const Species& s = species[p.species];
        const double ph = phen[p.species];
        const double g = shade_factor(s.shade, p.shade_fraction) *
                         water_factor(s.water, m_fraction[static_cast<std::size_t>(k)]) *
                         p.soil_factor;
        if (ph > 0) {
            p.growth_sum += g;
            p.growth_days += 1;
        }
        cd[static_cast<std::size_t>(k)] = carbon_day(s, p, g, ph, ftemp[p.species], q10);
    }
    // Sums and starvation in plant order (one order whatever the thread count).
    for (std::size_t k = 0; k < n; ++k) {
        m_sum.production += cd[k].production_kg;
        m_sum.maintenance += cd[k].maintenance_kg;
        m_sum.growth_resp += cd[k].growth_respiration_kg;
        m_sum.turnover += cd[k].turnover_kg;
        m_sum.demand_m3 += m_demand[k];
        m_sum.supplied_m3 += m_demand[k] * m_fraction[k];
        if (cd[k].starved) {
            // Dead from today: no more demand or carbon; removed at the next refresh.
            m_plants[k].alive = false;
            m_sum.deaths_starvation += 1;
        }
    }
}

bool Ecosystem::step_day() {
    const hydro::DayWeather& w = next_weather();
    const auto& species = m_scene.ecosystem.species;
    const auto& hg = m_scene.hydro.dem.grid();
    const bool coupled = m_scene.competition == Competition::coupled;
    hydro::DailyFluxes f;
    if (coupled) {
        // Weather -> plant water demand -> hydrology -> supply -> carbohydrate balance, and every
        // canopy_interval_days the structure, crowns and shading.
        const auto dw = hydro::et_weather(w, m_scene.hydro.climate);
        const double et0_m = std::max(0.0, hydro::et::fao56_reference_daily(dw)) / kMmPerM;
        const double tmean = 0.5 * (w.tmin_c + w.tmax_c);
        const double q10 = std::pow(kQ10, (tmean - kRespirationRefC) / 10.0);
        std::vector<double> phen(species.size()), ftemp(species.size());
        for (std::size_t s = 0; s < species.size(); ++s) {
            phen[s] = phenology(species[s], w.doy);
            ftemp[s] = temperature_factor(species[s], tmean);
        }
        plant_water_demand(et0_m, phen);
        f = m_hydro->step(w, &m_request_mm);
        water_supply_fractions();
        carbon_balance(phen, ftemp, q10);
        if (!m_ground.empty()) {
            ground_environment(true);
            for (std::size_t c = 0; c < m_ground_demand.size(); ++c) {
                m_sum.ground_demand_m3 += m_ground_demand[c];
                m_sum.ground_supplied_m3 += m_ground_demand[c] * m_ground_env[c].water_met;
            }
            // "Growth Rate" is the rate over a growing season: a leaf-on day grows 1/season of it.
            std::vector<double> season_phen(phen);
            for (std::size_t k = 0; k < species.size(); ++k)
                if (!species[k].evergreen)
                    season_phen[k] *= static_cast<double>(year_length(w)) /
                                      std::max(1, species[k].leaf_off_doy - species[k].leaf_on_doy);
            m_ground.accumulate(species, m_ground_env, 1.0 / year_length(w), season_phen, ftemp);
        }
        const bool refresh = m_days_done % m_scene.canopy_interval_days == 0;
        // The ground layer steps once a canopy interval and on the year's last day (the year end
        // and its checkpoint see no pending days).
        if (refresh || w.doy >= year_length(w)) m_ground.apply(species);
        if (refresh) refresh_canopy();
    } else {
        f = m_hydro->step(w, nullptr);
    }
    const double domain_m2 = hg.width_m() * hg.height_m();
    m_daily.push(hydro::daily_budget_row(m_days_done, w, f, domain_m2),
                 hydro::daily_budget_columns());
    if (w.doy < year_length(w)) return false;
    if (coupled)
        year_end_coupled();
    else
        year_end_light_only();
    year_end_common();
    return true;
}

int Ecosystem::year_length(const hydro::DayWeather& w) const {
    return m_scene.hydro.observed ? hydro::days_in_calendar_year(w.year) : hydro::kDaysPerYear;
}

void Ecosystem::run_year() {
    while (!step_day()) {
    }
}

void Ecosystem::remove_dead() {
    std::size_t out = 0;
    for (std::size_t k = 0; k < m_plants.size(); ++k) {
        if (!m_plants[k].alive) {
            m_sum.dead_carbon += m_plants[k].wood_kg + m_plants[k].reserve_kg;
            continue;
        }
        m_plants[out++] = m_plants[k];
    }
    m_plants.resize(out);
}

void Ecosystem::rebuild_crowns() {
    m_crowns.clear();
    for (const auto& p : m_plants) m_crowns.add(m_pgrid, p.x_m, p.y_m, p.crown_radius_m);
    m_roots = root_cells(m_crowns, m_map);
}

void Ecosystem::update_vegetation_density() {
    // Canopy cover on the hydrology grid drives the runoff coefficients and surface ET.
    const auto& hg = m_scene.hydro.dem.grid();
    RasterD density(hg, 0.0);
    const double inv = 1.0 / (m_map.factor * m_map.factor);
    for (int j = 0; j < m_pgrid.ny; ++j)
        for (int i = 0; i < m_pgrid.nx; ++i)
            density(i / m_map.factor, j / m_map.factor) += m_ground_shade(i, j) * inv;
    for (std::int64_t c = 0; c < density.size(); ++c) {
        // Crowns and the ground layer below them: 1 - (1 - crown cover)(1 - ground cover).
        const double crown = std::clamp(density.data()[c], 0.0, 1.0);
        density.data()[c] =
            m_ground.empty()
                ? crown
                : 1.0 - (1.0 - crown) * (1.0 - std::clamp(m_ground.total(c), 0.0, 1.0));
    }
    m_hydro->set_vegetation_density(density);
}

bool Ecosystem::establishes(const Species& s, double x, double y, Rng& rng) const {
    const double draw = rng.uniform(); // always drawn: the stream does not depend on the tests
    const auto [i, j] = m_pgrid.clamped_cell(x, y);
    const int hi = i / m_map.factor, hj = j / m_map.factor;
    // Light through the crowns and then through the grass and herbs (none without a ground layer).
    double light = 1.0 - m_ground_shade(i, j);
    if (!m_ground.empty())
        light *= m_ground.transmission(m_scene.ecosystem.species,
                                       static_cast<std::int64_t>(hj) * m_map.hydro_nx + hi,
                                       m_scene.extinction);
    if (light < s.germination_min_light) return false;
    const auto& soil = m_scene.hydro.soil;
    if (relative_water(hi, hj) < s.germination_min_soil_water) return false;
    if (m_hydro->catchments().owner(static_cast<std::int64_t>(hj) * m_map.hydro_nx + hi) != 0)
        return false;
    const double suit = texture_factor(s.texture, s.texture_tolerance_pct, soil.sand_pct(hi, hj),
                                       soil.silt_pct(hi, hj), soil.clay_pct(hi, hj)) *
                        ph_factor(s.ph, soil.ph(hi, hj));
    return draw < s.germination_probability * suit;
}

void Ecosystem::year_end_coupled() {
    std::vector<char> dead = ageing_and_mortality();
    std::vector<Plant> recruits = seed_dispersal(dead);
    background_arrivals(recruits);
    for (auto& p : m_plants) p.growth_sum = p.growth_days = 0;
    for (std::size_t k = 0; k < m_plants.size(); ++k)
        if (dead[k]) m_plants[k].alive = false;
    remove_dead();
    for (auto& r : recruits) {
        m_sum.recruit_carbon += r.wood_kg + r.reserve_kg;
        m_plants.push_back(r);
    }
    m_sum.births += static_cast<double>(recruits.size());
    refresh_canopy();
}

std::vector<char> Ecosystem::ageing_and_mortality() {
    const auto& species = m_scene.ecosystem.species;
    std::vector<char> dead(m_plants.size(), 0);
    for (std::size_t k = 0; k < m_plants.size(); ++k) {
        Plant& p = m_plants[k];
        const Species& s = species[p.species];
        const double u = m_rng_mort.uniform(); // drawn for every plant: the stream stays aligned
        if (!p.alive) continue;                // starved this year, counted then
        p.age_yr += 1;
        if (m_is_object[p.species]) { // no growth, no background death: removed at Max Age
            if (p.age_yr >= s.max_age_yr) {
                dead[k] = 1;
                m_sum.deaths_age += 1;
            }
            continue;
        }
        update_growth_efficiency(p);
        const double suppression = suppression_mortality(s, p.growth_efficiency);
        if (p.age_yr >= s.max_age_yr) {
            dead[k] = 1;
            m_sum.deaths_age += 1;
        } else if (u < s.background_mortality_per_yr) {
            dead[k] = 1;
            m_sum.deaths_background += 1;
        } else if (u < s.background_mortality_per_yr + suppression) {
            dead[k] = 1;
            m_sum.deaths_suppression += 1;
        }
    }
    return dead;
}

std::vector<Plant> Ecosystem::seed_dispersal(const std::vector<char>& dead) {
    const auto& species = m_scene.ecosystem.species;
    const auto& g = m_pgrid;
    std::vector<Plant> recruits;
    for (std::size_t k = 0; k < m_plants.size(); ++k) {
        const Plant& p = m_plants[k];
        const Species& s = species[p.species];
        if (dead[k] || !p.alive || m_is_object[p.species] || p.age_yr < s.maturity_age_yr) continue;
        const double vigor = p.growth_days > 0 ? p.growth_sum / p.growth_days : 0.0;
        const std::int64_t n = poisson(m_rng_seed, seeds_per_year(s, p.dbh_m, vigor));
        m_sum.seeds += static_cast<double>(n);
        for (std::int64_t q = 0; q < n; ++q) {
            const double d = sample_dispersal_distance(s.dispersal, m_rng_seed);
            const double a = 2.0 * std::numbers::pi * m_rng_seed.uniform();
            const double x = p.x_m + d * std::cos(a), y = p.y_m + d * std::sin(a);
            if (!g.contains_point(x, y) || x >= g.origin_x_m + g.width_m() ||
                y >= g.origin_y_m + g.height_m()) {
                m_sum.seeds_lost += 1;
                m_rng_seed.uniform(); // keep the stream aligned with the landed case
                continue;
            }
            if (establishes(s, x, y, m_rng_seed))
                recruits.push_back(new_plant(p.species, x, y, s.recruit_dbh_m));
        }
    }
    return recruits;
}

void Ecosystem::background_arrivals(std::vector<Plant>& recruits) {
    const auto& species = m_scene.ecosystem.species;
    const auto& g = m_pgrid;
    const double area = g.width_m() * g.height_m();
    for (std::size_t sp = 0; sp < species.size(); ++sp) {
        const Species& s = species[sp];
        if (s.life_form == LifeForm::grass) continue; // arrives into the ground layer's cover
        const std::int64_t n = poisson(m_rng_arrival, s.new_per_area_per_yr * area);
        for (std::int64_t q = 0; q < n; ++q) {
            const double x = g.origin_x_m + m_rng_arrival.uniform() * g.width_m();
            const double y = g.origin_y_m + m_rng_arrival.uniform() * g.height_m();
            if (m_is_object[sp] || establishes(s, x, y, m_rng_arrival))
                recruits.push_back(
                    new_plant(static_cast<std::uint16_t>(sp), x, y, s.recruit_dbh_m));
        }
    }
}

void Ecosystem::year_end_light_only() {
    if (!m_ground.empty()) {
        // The ground layer in a whole-year step: light under the crowns, no water limit.
        const auto& sp = m_scene.ecosystem.species;
        ground_environment(false);
        m_ground.step(sp, m_ground_env, 1.0, std::vector<double>(sp.size(), 1.0),
                      std::vector<double>(sp.size(), 1.0));
    }
    std::vector<char> dead = light_only_growth();
    light_only_arrivals(dead);
    overlap_thinning(dead);
    std::size_t out = 0;
    for (std::size_t k = 0; k < m_plants.size(); ++k)
        if (!dead[k]) m_plants[out++] = m_plants[k];
    m_plants.resize(out);
    refresh_canopy();
}

std::vector<char> Ecosystem::light_only_growth() {
    const auto& species = m_scene.ecosystem.species;
    std::vector<char> dead(m_plants.size(), 0);
    for (std::size_t k = 0; k < m_plants.size(); ++k) {
        Plant& p = m_plants[k];
        const Species& s = species[p.species];
        p.age_yr += 1;
        if (p.age_yr >= s.max_age_yr) {
            dead[k] = 1;
            m_sum.deaths_age += 1;
            continue;
        }
        if (m_is_object[p.species]) continue;
        p.dbh_m = light_only_dbh_m(s, p.age_yr);
        allometry::apply(s, p);
    }
    return dead;
}

void Ecosystem::light_only_arrivals(std::vector<char>& dead) {
    const auto& species = m_scene.ecosystem.species;
    const auto& g = m_pgrid;
    const double area = g.width_m() * g.height_m();
    for (std::size_t sp = 0; sp < species.size(); ++sp) {
        if (species[sp].life_form == LifeForm::grass) continue;
        const std::int64_t n = poisson(m_rng_arrival, species[sp].new_per_area_per_yr * area);
        for (std::int64_t q = 0; q < n; ++q) {
            const double x = g.origin_x_m + m_rng_arrival.uniform() * g.width_m();
            const double y = g.origin_y_m + m_rng_arrival.uniform() * g.height_m();
            m_plants.push_back(new_plant(static_cast<std::uint16_t>(sp), x, y, 0.0));
            dead.push_back(0);
            m_sum.births += 1;
        }
    }
}

void Ecosystem::overlap_thinning(std::vector<char>& dead) {
    const auto& species = m_scene.ecosystem.species;
    const auto& g = m_pgrid;
    std::vector<std::size_t> order(m_plants.size());
    for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
    std::vector<double> radius(m_plants.size());
    for (std::size_t k = 0; k < m_plants.size(); ++k) {
        const Plant& p = m_plants[k];
        radius[k] = m_scene.light_only_radius == LightOnlyRadius::mavs
                        ? mavs_competition_radius_m(species[p.species], p.height_m)
                        : p.crown_radius_m;
    }
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return radius[a] > radius[b]; });
    // Kept plants in square buckets at least two of the largest radii wide: a circle can only
    // overlap one in its own or a neighbouring bucket.
    double rmax = 0;
    for (const double r : radius) rmax = std::max(rmax, r);
    const double bucket = std::max(2 * rmax, g.cell_size_m);
    const int bx = static_cast<int>(std::ceil(g.width_m() / bucket)) + 1;
    const int by = static_cast<int>(std::ceil(g.height_m() / bucket)) + 1;
    std::vector<std::vector<std::size_t>> kept(static_cast<std::size_t>(bx) * by);
    for (const std::size_t k : order) {
        if (dead[k]) continue;
        const Plant& p = m_plants[k];
        const int cx = static_cast<int>((p.x_m - g.origin_x_m) / bucket);
        const int cy = static_cast<int>((p.y_m - g.origin_y_m) / bucket);
        bool overlaps = false;
        for (int dy = -1; dy <= 1 && !overlaps; ++dy)
            for (int dx = -1; dx <= 1 && !overlaps; ++dx) {
                const int x = cx + dx, y = cy + dy;
                if (x < 0 || y < 0 || x >= bx || y >= by) continue;
                for (const std::size_t o : kept[static_cast<std::size_t>(y) * bx + x]) {
                    const Plant& q = m_plants[o];
                    const double dist = std::hypot(p.x_m - q.x_m, p.y_m - q.y_m);
                    if (dist < radius[k] + radius[o]) {
                        overlaps = true;
                        break;
                    }
                }
            }
        if (overlaps) {
            dead[k] = 1;
            m_sum.deaths_overlap += 1;
        } else {
            kept[static_cast<std::size_t>(cy) * bx + cx].push_back(k);
        }
    }
}

void Ecosystem::year_end_common() {
    ++m_years_done;
    update_vegetation_density();
    const CarbonStocks c = close_carbon_budget();
    record_year(c);
    m_sum = YearSums{};
}

Ecosystem::CarbonStocks Ecosystem::close_carbon_budget() {
    CarbonStocks c;
    for (const auto& p : m_plants) c.wood_kg += p.wood_kg, c.reserve_kg += p.reserve_kg;
    const double stock = c.wood_kg + c.reserve_kg;
    const double expected = m_stock_at_year_start + m_sum.production - m_sum.maintenance -
                            m_sum.growth_resp + m_sum.recruit_carbon - m_sum.dead_carbon -
                            m_sum.turnover;
    c.residual_kg = stock - expected;
    m_cum_carbon_residual += c.residual_kg;
    m_cum_carbon_throughput += m_sum.production + m_sum.maintenance + m_sum.growth_resp +
                               m_sum.recruit_carbon + std::abs(m_sum.dead_carbon) + m_sum.turnover;
    if (std::abs(m_cum_carbon_residual) >
        kCarbonTolerance * std::max(m_cum_carbon_throughput, 1.0) + kCarbonStockRounding * stock)
        throw Error("carbon budget broke in year " + std::to_string(m_years_done) + ": residual " +
                    format_number(m_cum_carbon_residual) + " kg against a throughput of " +
                    format_number(m_cum_carbon_throughput) + " kg");
    m_stock_at_year_start = stock;
    return c;
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
    row.live_plants = static_cast<double>(m_plants.size());
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
    m_yearly.push(row, yearly_columns());
}

StandMetrics Ecosystem::stand() const {
    const auto& sp = m_scene.ecosystem.species;
    std::vector<double> d;
    d.reserve(m_plants.size());
    for (const auto& p : m_plants)
        if (sp[p.species].life_form == LifeForm::tree) d.push_back(p.dbh_m); // 0 below 1.3 m
    return stand_metrics(d, m_pgrid.width_m() * m_pgrid.height_m());
}

UndergrowthMetrics Ecosystem::undergrowth() const {
    const auto& sp = m_scene.ecosystem.species;
    UndergrowthCounter count;
    for (const auto& p : m_plants) count.add(sp[p.species].life_form, p.crown_radius_m, p.height_m);
    UndergrowthMetrics u = count.metrics(m_pgrid.width_m() * m_pgrid.height_m());
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
    std::uint64_t h = fnv1a64(nullptr, 0);
    for (const auto& d : m_scene.hydro.observed->days) {
        h = fnv1a64(&d.year, sizeof d.year, h);
        h = fnv1a64(&d.doy, sizeof d.doy, h);
        for (double v : {d.tmin_c, d.tmax_c, d.rain_mm, d.tdew_c, d.u2_m_per_s, d.rs_mj})
            h = fnv1a64(&v, sizeof v, h);
    }
    return h | 1; // never 0, the generator's value
}

double Ecosystem::carbon_residual_relative() const {
    return std::abs(m_cum_carbon_residual) / std::max(m_cum_carbon_throughput, 1e-300);
}

void Ecosystem::save_state(ArchiveWriter& a) const {
    a.put(kCheckpointMagic);
    a.put(kCheckpointVersion);
    a.put(m_years_done);
    a.put(m_days_done);
    a.put(m_weather);
    a.put(observed_weather_hash());
    const auto gs = m_gen.state();
    a.put(gs);
    a.put(m_rng_seed.state());
    a.put(m_rng_mort.state());
    a.put(m_rng_arrival.state());
    a.put_vector(m_plants);
    a.put(m_next_id);
    a.put_raster(m_ground_shade);
    if (m_ground.pending())
        throw Error("internal: a checkpoint with ground-layer days not yet applied");
    a.put_vector(m_ground.raw());
    m_hydro->save_state(a);
    a.put_raster(m_hydro->vegetation_density());
    for (const auto& c : m_daily.columns) a.put_vector(c);
    for (const auto& c : m_yearly.columns) a.put_vector(c);
    a.put(m_sum);
    a.put(m_stock_at_year_start);
    a.put(m_cum_carbon_residual);
    a.put(m_cum_carbon_throughput);
}

void Ecosystem::load_state(ArchiveReader& a) {
    if (a.get<std::uint32_t>() != kCheckpointMagic)
        throw CheckpointError("the checkpoint is not an ecoterra ecosystem checkpoint");
    const auto version = a.get<std::uint32_t>();
    if (version != kCheckpointVersion)
        throw CheckpointError("the checkpoint has format version " + std::to_string(version) +
                              ", this ecoterra reads version " +
                              std::to_string(kCheckpointVersion));
    m_years_done = a.get<int>();
    m_days_done = a.get<int>();
    m_weather = a.get<hydro::DayWeather>();
    if (a.get<std::uint64_t>() != observed_weather_hash())
        throw CheckpointError(
            m_scene.hydro.observed
                ? "the observed weather series differs from the one the run was "
                  "made with (was the weather CSV changed?)"
                : "the checkpoint was made with observed weather, the scene has none");
    m_gen.set_state(a.get<hydro::WeatherGenerator::State>());
    m_rng_seed.set_state(a.get<std::array<std::uint64_t, 4>>());
    m_rng_mort.set_state(a.get<std::array<std::uint64_t, 4>>());
    m_rng_arrival.set_state(a.get<std::array<std::uint64_t, 4>>());
    m_plants = a.get_vector<Plant>();
    m_next_id = a.get<std::int64_t>();
    m_ground_shade = a.get_raster<double>();
    m_ground.set_raw(a.get_vector<double>());
    m_hydro->load_state(a);
    m_hydro->set_vegetation_density(a.get_raster<double>());
    for (auto& c : m_daily.columns) c = a.get_vector<double>();
    for (auto& c : m_yearly.columns) c = a.get_vector<double>();
    m_sum = a.get<YearSums>();
    m_stock_at_year_start = a.get<double>();
    m_cum_carbon_residual = a.get<double>();
    m_cum_carbon_throughput = a.get<double>();
    // Crowns are derived from the plants; shade fractions are restored with them.
    rebuild_crowns();
    crown_shade_per_cell();
}

} // namespace ecoterra::eco
