#include "ecoterra/eco/scene_config.hpp"

#include "ecoterra/json_util.hpp"

#include <cmath>

namespace ecoterra::eco {

using nlohmann::json;
namespace fs = std::filesystem;

std::string competition_name(Competition c) {
    return c == Competition::coupled ? "coupled" : "light_only";
}

EcoScene load_eco_scene(const json& s, const fs::path& base) {
    if (!s.is_object()) throw InputError("scene: must be a JSON object");
    require_known_keys(s, {"terrain", "soil", "vegetation", "climate", "hydrology", "simulation"},
                       "");
    EcoScene e;
    // The hydrology half, with the hydrology-only keys.
    json h = s;
    const json veg = s.value("vegetation", json::object());
    const json sim = s.value("simulation", json::object());
    require_known_keys(veg,
                       {"ecosystem", "competition", "shading", "extinction_coefficient",
                        "plant_cell_m", "canopy_interval_days", "initial", "light_only_radius"},
                       "vegetation");
    require_known_keys(sim,
                       {"years", "seed", "snapshot_interval_years", "target_basal_area_m2_per_ha"},
                       "simulation");
    h["vegetation"] = {{"density", 0.0}};
    h["simulation"] = json::object();
    for (const char* k : {"years", "seed"})
        if (sim.contains(k)) h["simulation"][k] = sim[k];
    e.hydro = hydro::load_hydro_scene(h, base);
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
    e.years = e.hydro.years;
    e.seed = e.hydro.seed;
    e.resolved = e.hydro.resolved;
    e.resolved.erase("vegetation");

    const std::string w = "vegetation";
    if (!veg.contains("ecosystem"))
        throw InputError("vegetation.ecosystem: missing (an ecosystem file, e.g. "
                         "data/ecosystems/humid_subtropical_broadleaf.json)");
    fs::path eco = get_string(veg, "ecosystem", "", w);
    if (eco.is_relative()) eco = base / eco;
    e.ecosystem = load_ecosystem(eco);
    const std::vector<std::string> comps = {"coupled", "light_only"};
    const std::string comp = comps[get_choice(veg, "competition", comps, 0, w)];
    e.competition = comp == "coupled" ? Competition::coupled : Competition::light_only;
    const std::vector<std::string> shadings = {"blocking", "beer_lambert"};
    const std::string sh = shadings[get_choice(veg, "shading", shadings, 0, w)];
    e.shading = sh == "blocking" ? ShadingMode::blocking : ShadingMode::beer_lambert;
    e.extinction = get_number(veg, "extinction_coefficient", e.extinction, w, 0.01, 5);
    const std::vector<std::string> radii = {"crown", "mavs"};
    const std::string radius = radii[get_choice(veg, "light_only_radius", radii, 0, w)];
    e.light_only_radius = radius == "mavs" ? LightOnlyRadius::mavs : LightOnlyRadius::crown;
    const double terrain_cell = e.hydro.dem.grid().cell_size_m;
    e.plant_cell_m = get_number(veg, "plant_cell_m", std::min(1.0, terrain_cell), w, 0.05, 100);
    const double ratio = terrain_cell / e.plant_cell_m;
    if (std::abs(ratio - std::round(ratio)) > 1e-9 || std::round(ratio) < 1)
        throw InputError("vegetation.plant_cell_m = " + format_number(e.plant_cell_m) +
                         " must divide the terrain cell (" + format_number(terrain_cell) +
                         " m) a whole number of times");
    e.canopy_interval_days =
        static_cast<int>(get_integer(veg, "canopy_interval_days", 7, w, 1, 365));
    json init_resolved = "bare";
    if (veg.contains("initial")) {
        const json& in = veg.at("initial");
        if (in.is_string() && in.get<std::string>() == "bare") {
            e.initial.kind = InitialPlants::Kind::bare;
        } else if (in.is_object() && in.contains("random")) {
            require_known_keys(in, {"random"}, "vegetation.initial");
            const json& r = in.at("random");
            require_known_keys(r, {"stems_per_ha", "max_dbh_m"}, "vegetation.initial.random");
            e.initial.kind = InitialPlants::Kind::random;
            e.initial.stems_per_ha =
                get_number(r, "stems_per_ha", 500, "vegetation.initial.random", 0, 1e5);
            e.initial.max_dbh_m =
                get_number(r, "max_dbh_m", 0.3, "vegetation.initial.random", 0.001, 5);
            init_resolved = {
                {"random",
                 {{"stems_per_ha", e.initial.stems_per_ha}, {"max_dbh_m", e.initial.max_dbh_m}}}};
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
    e.snapshot_interval_years =
        static_cast<int>(get_integer(sim, "snapshot_interval_years", 5, "simulation", 1, 100000));
    if (sim.contains("target_basal_area_m2_per_ha"))
        e.target_basal_area_m2_per_ha =
            get_number(sim, "target_basal_area_m2_per_ha", 0, "simulation", 0.001, 500);
    e.resolved["vegetation"] = {{"ecosystem", eco.string()},
                                {"competition", comp},
                                {"shading", sh},
                                {"extinction_coefficient", e.extinction},
                                {"light_only_radius", radius},
                                {"plant_cell_m", e.plant_cell_m},
                                {"canopy_interval_days", e.canopy_interval_days},
                                {"initial", init_resolved}};
    e.resolved["simulation"] = {{"years", e.years},
                                {"seed", e.seed},
                                {"snapshot_interval_years", e.snapshot_interval_years}};
    if (e.target_basal_area_m2_per_ha)
        e.resolved["simulation"]["target_basal_area_m2_per_ha"] = *e.target_basal_area_m2_per_ha;
    return e;
}

} // namespace ecoterra::eco
