#include "ecoterra/eco/scene_config.hpp"

#include "ecoterra/json_util.hpp"

#include <cmath>
#include <cstdio>

namespace ecoterra::eco {

using nlohmann::json;
namespace fs = std::filesystem;

std::string competition_name(Competition c) {
    return c == Competition::coupled ? "coupled" : "light_only";
}

const ParamCatalog<EcoScene>& vegetation_catalog() {
    using E = EcoScene;
    static const ParamCatalog<E> c(
        "vegetation",
        {choice<E>("competition", &E::competition,
                   std::vector<std::pair<std::string, Competition>>{
                       {"coupled", Competition::coupled}, {"light_only", Competition::light_only}},
                   "model: coupled (carbohydrate, light and root water) or light_only (the "
                   "geometric rule of MAVS), docs/ecosystem.md s7"),
         choice<E>(
             "shading", &E::shading,
             std::vector<std::pair<std::string, ShadingMode>>{
                 {"blocking", ShadingMode::blocking},
                 {"beer_lambert", ShadingMode::beer_lambert},
                 {"crown_profile", ShadingMode::crown_profile}},
             "shading rule: blocking (paper 002 Fig 2), beer_lambert (through the leaf area of "
             "every taller crown) or crown_profile (through the leaf area above the plant's "
             "mid-crown, each crown's spread over its depth), docs/ecosystem.md s4"),
         choice<E>("growth", &E::growth,
                   std::vector<std::pair<std::string, GrowthModel>>{
                       {"light_and_turnover", GrowthModel::light_and_turnover},
                       {"paper002", GrowthModel::paper002}},
                   "plant growth model: light_and_turnover (production saturating in the light on "
                   "the crown, leaves and fine roots rebuilt as they turn over, sapwood "
                   "respiration, suppressed plants starve below their light compensation point, "
                   "water demand following the crown's light; the shipped forests calibrated to "
                   "stand figures, docs/validation.md s2c) or paper002 (the shade preference, no "
                   "tissue turnover, growth-efficiency suppression, paper 002 s3), "
                   "docs/ecosystem.md s3"),
         number<E>("extinction_coefficient", &E::extinction, "1", 0.01, 5,
                   "Beer-Lambert extinction coefficient k"),
         choice<E>("light_only_radius", &E::light_only_radius,
                   std::vector<std::pair<std::string, LightOnlyRadius>>{
                       {"crown", LightOnlyRadius::crown}, {"mavs", LightOnlyRadius::mavs}},
                   "light-only overlap circle of the diameter_curve model: the crown radius or "
                   "MAVS's 0.5 ratio H"),
         choice<E>("light_only_model", &E::light_only_model,
                   std::vector<std::pair<std::string, LightOnlyModel>>{
                       {"diameter_curve", LightOnlyModel::diameter_curve},
                       {"mavs", LightOnlyModel::mavs}},
                   "light-only yearly step: diameter_curve (ecoterra's: the diameter curve, "
                   "Poisson arrivals, largest-first thinning with light_only_radius) or mavs "
                   "(MAVS's ecosystem step: the height curve, MAVS's arrivals and circle, every "
                   "overlapping pair at once, the smaller dies), docs/ecosystem.md s7"),
         number<E>("mavs_plant_density", &E::mavs_plant_density, "1", 0, 1000,
                   "MAVS's \"Plant Density\" (its random scene's growth factor): multiplies "
                   "every species' Num New Per Area in the mavs light-only model"),
         number<E>("plant_cell_m", &E::plant_cell_m, "m", 0.05, 10,
                   "crown and root grid cell; divides the terrain cell a whole number of times "
                   "(to 1e-6). Crowns, roots, seeds and light live on these cells, so a cell "
                   "wider than a mature crown (10 m) cannot hold a stand: give a coarse DEM "
                   "terrain.cell_m instead (docs/formats.md, DEM windows)")
             .with_note("min(1, terrain cell)"),
         integer<E>("canopy_interval_days", &E::canopy_interval_days, "day", 1, 365,
                    "days between refreshes of structure, crowns, roots, shading and ground cover "
                    "(14; 7 before 2026-11-29 reproduces earlier runs, docs/validation.md s2b)"),
         choice<E>("plant_order", &E::plant_order,
                   std::vector<std::pair<std::string, PlantOrder>>{
                       {"stem_cell", PlantOrder::stem_cell}, {"birth", PlantOrder::birth}},
                   "the order the plants are kept and visited in: stem_cell (by the cell of "
                   "their stem, row by row: the per-cell passes read memory in order, 1.2-1.3 x "
                   "faster in a dense square kilometre) or birth (the order of ecoterra before "
                   "2026-11-28, whose runs and checkpoints it continues bit for bit). The order "
                   "decides which plant takes which random draw, so the two give different "
                   "runs with the same statistics, docs/scaling.md"),
         flag<E>(
             "deadwood.enabled", +[](E& e) -> bool& { return e.deadwood.enabled; },
             "trees that die become snags and logs (docs/ecosystem.md s8); false: they vanish"),
         number<E>(
             "deadwood.min_dbh_m", +[](E& e) -> double& { return e.deadwood.min_dbh_m; }, "m", 0,
             10,
             "smallest DBH of a dead tree kept as a snag or log (FIA's coarse woody debris: "
             "7.62 cm)"),
         number<E>(
             "deadwood.removal_mass_fraction",
             +[](E& e) -> double& { return e.deadwood.removal_mass_fraction; }, "1", 0, 0.99,
             "a piece vanishes when less than this share of its mass is left (iLand: 0.05)")});
    return c;
}

const ParamCatalog<EcoScene>& eco_simulation_catalog() {
    using E = EcoScene;
    static const ParamCatalog<E> c(
        "simulation",
        {integer<E>("snapshot_interval_years", &E::snapshot_interval_years, "yr", 1, 100000,
                    "years between snapshots and checkpoints; the last year always gets one"),
         flag<E>("snapshot_checkpoints", &E::snapshot_checkpoints,
                 "every snapshot keeps the full state, so that `ecoterra mobility map --season` "
                 "replays a year from the snapshot before it instead of from the start (larger "
                 "snapshot files)"),
         optional_number<E>("target_basal_area_m2_per_ha", &E::target_basal_area_m2_per_ha, "m2/ha",
                            0.001, 500, "stop at the first year end at or above this basal area")});
    return c;
}

MemoryEstimate memory_estimate(const EcoScene& scene) {
    MemoryEstimate m = hydro::memory_estimate(scene.hydro);
    const GridSpec& g = scene.hydro.dem.grid();
    const double area_m2 = g.width_m() * g.height_m();
    m.terms.push_back(
        {"plant cells", area_m2 / (scene.plant_cell_m * scene.plant_cell_m), kBytesPerPlantCell});
    const double initial = scene.initial.kind == InitialPlants::Kind::random
                               ? scene.initial.stems_per_ha * area_m2 / 1e4
                               : 0;
    m.terms.push_back(
        {"plants", std::max(initial, kStemCeilingPerHa * area_m2 / 1e4), kBytesPerPlant});
    return m;
}

namespace {
/// vegetation.initial into `e`; returns its resolved form.
json read_initial(const json& veg, const fs::path& base, EcoScene& e) {
    json init_resolved = "bare";
    if (veg.contains("initial")) {
        const json& in = veg.at("initial");
        if (in.is_string() && in.get<std::string>() == "bare") {
            e.initial.kind = InitialPlants::Kind::bare;
        } else if (in.is_object() && in.contains("random")) {
            require_known_keys(in, {"random"}, "vegetation.initial");
            e.initial = initial_random_catalog().read(in.at("random"), InitialPlants{});
            e.initial.kind = InitialPlants::Kind::random;
            init_resolved = {{"random", initial_random_catalog().to_json(e.initial)}};
        } else if (in.is_object() && in.contains("file")) {
            require_known_keys(in, {"file"}, "vegetation.initial");
            e.initial.kind = InitialPlants::Kind::file;
            e.initial.file = get_string(in, "file", "", "vegetation.initial");
            if (e.initial.file.is_relative()) e.initial.file = base / e.initial.file;
            init_resolved = {{"file", e.initial.file.string()}};
        } else {
            throw InputError("vegetation.initial must be \"bare\", {\"random\": {...}} or "
                             "{\"file\": \"stems.csv\"}, got " +
                             in.dump());
        }
    }
    return init_resolved;
}
} // namespace

namespace {
/// The mean wind at 2 m of the scene's weather: the observed series' or the generator's.
double mean_wind_u2(const hydro::HydroScene& h) {
    if (!h.observed) return h.climate.wind_mean_m_per_s;
    double sum = 0;
    for (const auto& d : h.observed->days) sum += d.u2_m_per_s;
    return h.observed->days.empty() ? h.climate.wind_mean_m_per_s
                                    : sum / static_cast<double>(h.observed->days.size());
}
} // namespace

EcoScene load_eco_scene(const json& s, const fs::path& base) {
    if (!s.is_object()) throw InputError("scene: must be a JSON object");
    require_known_keys(s, {"terrain", "soil", "vegetation", "climate", "hydrology", "simulation"},
                       "");
    EcoScene e;
    // The hydrology half, with the hydrology-only keys.
    json h = s;
    const json veg = s.value("vegetation", json::object());
    const json sim = s.value("simulation", json::object());
    h["vegetation"] = {{"density", 0.0}};
    h["simulation"] = json::object();
    for (const char* k : {"years", "seed"})
        if (sim.is_object() && sim.contains(k)) h["simulation"][k] = sim[k];
    e = eco_simulation_catalog().read(sim, e, {"years", "seed"});
    // years and seed are the hydrology scene's keys (hydro_simulation_catalog).
    e.hydro = hydro::load_hydro_scene(h, base);
    e.years = e.hydro.years;
    e.seed = e.hydro.seed;
    if (e.hydro.observed) {
        // Replayed year by year in a cycle, so the series must hold whole calendar years.
        const auto& d = e.hydro.observed->days;
        const auto& first = d.front();
        const auto& last = d.back();
        const std::string file = h["climate"]["csv"].get<std::string>();
        if (first.doy != 1 || last.doy != hydro::days_in_calendar_year(last.year))
            throw InputError("climate.csv " + file +
                             ": an ecosystem run replays observed weather by calendar years and "
                             "needs whole years (1 January to 31 December); the series runs from "
                             "day " +
                             std::to_string(first.doy) + " of " + std::to_string(first.year) +
                             " to day " + std::to_string(last.doy) + " of " +
                             std::to_string(last.year));
    }
    e.resolved = e.hydro.resolved;
    e.resolved.erase("vegetation");

    const double terrain_cell = e.hydro.dem.grid().cell_size_m;
    e.plant_cell_m = std::min(1.0, terrain_cell);
    e = vegetation_catalog().read(veg, e, {"ecosystem", "initial", "management", "windthrow"});
    if (veg.contains("management")) e.management = read_management(veg.at("management"), e.years);
    if (veg.contains("windthrow")) e.windthrow = read_windthrow(veg.at("windthrow"), e.years);
    if (!e.windthrow.weibull_scale_m_per_s)
        e.windthrow.weibull_scale_m_per_s =
            wind::weibull_scale_from_u2(mean_wind_u2(e.hydro), e.windthrow.weibull_shape);
    e.deadwood.stump_height_m = e.management.stump_height_m;
    if (!veg.contains("ecosystem"))
        throw InputError("vegetation.ecosystem: missing (an ecosystem file, e.g. "
                         "data/ecosystems/humid_subtropical_broadleaf.json)");
    fs::path eco = get_string(veg, "ecosystem", "", "vegetation");
    if (eco.is_relative()) eco = base / eco;
    e.ecosystem = load_ecosystem(eco);
    // Cell sides compare to a relative 1e-6, so that a side printed to 7 digits (89.99407 for a
    // DEM's 89.994067349...) is taken; the plant cell is then the terrain cell's exact part.
    const double ratio = terrain_cell / e.plant_cell_m;
    const double parts = std::round(ratio);
    if (parts < 1 || std::abs(ratio - parts) > 1e-6 * parts) {
        char cell[32];
        std::snprintf(cell, sizeof cell, "%.10g", terrain_cell);
        throw InputError("vegetation.plant_cell_m = " + format_number(e.plant_cell_m) +
                         " must divide the terrain cell (" + cell +
                         " m) a whole number of times; to grow plants on a DEM of coarse cells, "
                         "resample it with terrain.cell_m (e.g. 1) and keep the area small with "
                         "terrain.window (docs/formats.md \"DEM windows\")");
    }
    e.plant_cell_m = terrain_cell / parts;
    const json init_resolved = read_initial(veg, base, e);
    e.resolved["vegetation"] = vegetation_catalog().to_json(e);
    e.resolved["vegetation"]["ecosystem"] = eco.string();
    e.resolved["vegetation"]["initial"] = init_resolved;
    e.resolved["vegetation"]["management"] = to_json(e.management);
    e.resolved["vegetation"]["windthrow"] = to_json(e.windthrow);
    json& sim_resolved = e.resolved["simulation"]; // years and seed, from the hydrology half
    sim_resolved.erase("snapshot_interval_days");
    sim_resolved.update(eco_simulation_catalog().to_json(e));
    return e;
}

const ParamCatalog<InitialPlants>& initial_random_catalog() {
    using I = InitialPlants;
    static const ParamCatalog<I> c(
        "vegetation.initial.random",
        {number<I>("stems_per_ha", &I::stems_per_ha, "1/ha", 0, 1e5,
                   "stem density of the initial stand, species drawn uniformly"),
         number<I>("max_dbh_m", &I::max_dbh_m, "m", 0.001, 5,
                   "diameters are uniform in [the species' recruit diameter, this]")});
    return c;
}

Methods scene_methods(const EcoScene& sc) {
    Methods m = hydro::scene_methods(sc.hydro);
    bool ground = false;
    for (const auto& s : sc.ecosystem.species) ground = ground || s.life_form == LifeForm::grass;
    if (sc.competition == Competition::light_only && sc.light_only_model == LightOnlyModel::mavs) {
        m.push_back({"plants (light-only baseline)",
                     "MAVS's ecosystem step (Goodin 2018; MAVS terrain_generator/ecosystem.cpp): "
                     "the height curve, uniform arrivals, every overlapping pair of circles, "
                     "after Deussen, Hanrahan, Lintermann, Mech, Pharr & Prusinkiewicz (1998) "
                     "SIGGRAPH"});
    } else if (sc.competition == Competition::light_only) {
        m.push_back({"plants (light-only baseline)",
                     "overlap thinning of Deussen, Hanrahan, Lintermann, Mech, Pharr & "
                     "Prusinkiewicz (1998) SIGGRAPH, as MAVS implements it (Goodin et al.)"});
    } else {
        m.push_back({"plants (coupled)",
                     "the coupled soil-moisture and carbohydrate growth model of Goodin, Hudson et "
                     "al. (2024) SIMULATION, doi:10.1177/00375497241261412 (paper 002)"});
        m.push_back({"allometry",
                     "SORTIE-ND height and crown curves (Pacala et al. 1996); stem form "
                     "factor of Husch, Beers & Kershaw (2003)"});
        m.push_back({"respiration", "maintenance Q10 = 2 (Ryan 1991) over the pipe model "
                                    "(Shinozaki et al. 1964); growth respiration (Penning de "
                                    "Vries 1975)"});
        m.push_back({"maximum diameter", "JABOWA and FORET (Botkin, Janak & Wallis 1972)"});
        m.push_back({"growth suppression mortality", "LPJ-GUESS's greff_min (Smith, Prentice & "
                                                     "Sykes 2001)"});
        m.push_back({"seed production", "SORTIE-ND (Ribbens, Silander & Pacala 1994)"});
        m.push_back({"growth", sc.growth == GrowthModel::light_and_turnover
                                   ? "saturating in light (SORTIE-ND, Pacala et al. 1996); leaf "
                                     "and fine-root turnover (LPJ-GUESS; leaf mass per area from "
                                     "life span, Reich et al. 1997)"
                                   : "shade preference, paper 002 s3"});
    }
    if (sc.shading == ShadingMode::beer_lambert)
        m.push_back({"shading", "Beer-Lambert light extinction (Monsi & Saeki 1953)"});
    else if (sc.shading == ShadingMode::crown_profile)
        m.push_back({"shading", "Beer-Lambert light extinction (Monsi & Saeki 1953) through the "
                                "leaf area above mid-crown, crowns of ForestGALES depth (Gardiner "
                                "et al. 2000)"});
    else
        m.push_back({"shading", "blocking crowns, Goodin, Hudson et al. 2024 (paper 002) Fig 2"});
    if (ground)
        m.push_back({"ground layer", "logistic cover with Beer-Lambert light extinction (Monsi & "
                                     "Saeki 1953); transpiration against FAO-56 grass"});
    m.push_back({"stand density index", "Reineke (1933) J. Agric. Res. 46:627"});
    return m;
}

} // namespace ecoterra::eco
