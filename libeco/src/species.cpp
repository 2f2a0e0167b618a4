#include "ecoterra/eco/species.hpp"

#include "ecoterra/json_util.hpp"

#include <fstream>
#include <set>
#include <sstream>

namespace ecoterra::eco {

namespace {

using nlohmann::json;

const std::vector<std::string> kMavsTopKeys = {"Texture Inputs",    "Surface Mesh",
                                               "Simulation Length", "Anvel Replay File",
                                               "PathToMeshes",      "Trail Properties"};
const std::vector<std::string> kMavsSpeciesKeys = {
    "Mesh File",  "Species Name", "Num New Per Area",         "Growth Rate", "Max Height",
    "Min Height", "Mesh Height",  "Height To Diameter Ratio", "Max Age",     "Rotate Mesh"};
constexpr double kTiny = 1e-9;

struct Reader {
    const json& obj;
    std::string where;
    Species& s;
    double num(const char* key, double fallback, double lo, double hi) {
        if (!obj.contains(key)) s.defaulted.push_back(where.empty() ? key : where + "." + key);
        return get_number(obj, key, fallback, where, lo, hi);
    }
    Preference pref(const char* key, Preference fallback, double lo, double hi) {
        const std::string w = where.empty() ? key : where + "." + key;
        if (!obj.contains(key)) {
            s.defaulted.push_back(w);
            return fallback;
        }
        const json& p = obj.at(key);
        if (!p.is_object())
            throw InputError(w + " must be an object {\"desired\": .., \"tolerance\": ..}");
        require_known_keys(p, {"desired", "tolerance"}, w);
        Preference r;
        r.desired = get_number(p, "desired", fallback.desired, w, lo, hi);
        r.tolerance = get_number(p, "tolerance", fallback.tolerance, w, kTiny, 1e6);
        return r;
    }
};

void parse_physiology(const json& p, Species& s) {
    const std::vector<std::string> keys = {"height_dbh_slope_per_cm",
                                           "crown_radius_coefficient_m",
                                           "crown_radius_exponent",
                                           "max_crown_radius_m",
                                           "wood_density_kg_per_m3",
                                           "leaf_area_per_crown_area",
                                           "max_production_kg_per_m2_leaf_per_day",
                                           "respiration_kg_per_m2_leaf_per_m_per_yr",
                                           "reserve_capacity_kg_per_m2_leaf",
                                           "initial_reserve_fraction",
                                           "temperature_base_c",
                                           "temperature_optimum_c",
                                           "evergreen",
                                           "leaf_on_doy",
                                           "leaf_off_doy",
                                           "shade",
                                           "water",
                                           "ph",
                                           "texture",
                                           "texture_tolerance_pct",
                                           "transpiration_per_leaf_area",
                                           "maturity_age_yr",
                                           "seeds_per_yr_at_30cm",
                                           "dispersal",
                                           "germination",
                                           "recruit_dbh_m",
                                           "background_mortality_per_yr",
                                           "suppression"};
    require_known_keys(p, keys, "physiology");
    Reader r{p, "physiology", s};
    s.height_dbh_slope_per_cm =
        r.num("height_dbh_slope_per_cm", s.height_dbh_slope_per_cm, 1e-4, 1.0);
    s.crown_radius_coefficient_m =
        r.num("crown_radius_coefficient_m", s.crown_radius_coefficient_m, kTiny, 10);
    s.crown_radius_exponent = r.num("crown_radius_exponent", s.crown_radius_exponent, 0.1, 1.5);
    s.max_crown_radius_m = r.num("max_crown_radius_m", s.max_crown_radius_m, 0.1, 50);
    s.wood_density_kg_per_m3 = r.num("wood_density_kg_per_m3", s.wood_density_kg_per_m3, 50, 1500);
    s.leaf_area_per_crown_area =
        r.num("leaf_area_per_crown_area", s.leaf_area_per_crown_area, 0.05, 20);
    s.max_production_kg_per_m2_leaf_per_day = r.num(
        "max_production_kg_per_m2_leaf_per_day", s.max_production_kg_per_m2_leaf_per_day, kTiny, 1);
    s.respiration_kg_per_m2_leaf_per_m_per_yr =
        r.num("respiration_kg_per_m2_leaf_per_m_per_yr", s.respiration_kg_per_m2_leaf_per_m_per_yr,
              0, 10);
    s.reserve_capacity_kg_per_m2_leaf =
        r.num("reserve_capacity_kg_per_m2_leaf", s.reserve_capacity_kg_per_m2_leaf, kTiny, 100);
    s.initial_reserve_fraction =
        r.num("initial_reserve_fraction", s.initial_reserve_fraction, kTiny, 1);
    s.temperature_base_c = r.num("temperature_base_c", s.temperature_base_c, -30, 40);
    s.temperature_optimum_c = r.num("temperature_optimum_c", s.temperature_optimum_c, -20, 50);
    if (!(s.temperature_optimum_c > s.temperature_base_c))
        throw InputError("physiology.temperature_optimum_c must exceed temperature_base_c");
    if (!p.contains("evergreen")) s.defaulted.push_back("physiology.evergreen");
    s.evergreen = get_bool(p, "evergreen", s.evergreen, "physiology");
    s.leaf_on_doy = static_cast<int>(r.num("leaf_on_doy", s.leaf_on_doy, 1, 366));
    s.leaf_off_doy = static_cast<int>(r.num("leaf_off_doy", s.leaf_off_doy, 1, 366));
    if (!s.evergreen && s.leaf_off_doy <= s.leaf_on_doy)
        throw InputError("physiology.leaf_off_doy must come after leaf_on_doy");
    s.shade = r.pref("shade", s.shade, 0, 1);
    s.water = r.pref("water", s.water, 0, 1);
    s.ph = r.pref("ph", s.ph, 0, 14);
    if (p.contains("texture")) {
        const std::string t = get_string(p, "texture", "", "physiology");
        const auto tex = hydro::parse_texture(t);
        if (!tex)
            throw InputError("physiology.texture: unknown USDA texture class '" + t +
                             "' (sand, loamy_sand, sandy_loam, loam, silt_loam, silt, "
                             "sandy_clay_loam, clay_loam, silty_clay_loam, sandy_clay, "
                             "silty_clay, clay)");
        s.texture = *tex;
    } else {
        s.defaulted.push_back("physiology.texture");
    }
    s.texture_tolerance_pct = r.num("texture_tolerance_pct", s.texture_tolerance_pct, kTiny, 200);
    s.transpiration_per_leaf_area =
        r.num("transpiration_per_leaf_area", s.transpiration_per_leaf_area, 0, 5);
    s.maturity_age_yr = r.num("maturity_age_yr", s.maturity_age_yr, 0, 5000);
    s.seeds_per_yr_at_30cm = r.num("seeds_per_yr_at_30cm", s.seeds_per_yr_at_30cm, 0, 1e6);
    if (p.contains("dispersal")) {
        const json& d = p.at("dispersal");
        require_known_keys(d, {"mean_distance_m", "long_distance_m", "long_fraction"},
                           "physiology.dispersal");
        const std::string w = "physiology.dispersal";
        s.dispersal.mean_distance_m =
            get_number(d, "mean_distance_m", s.dispersal.mean_distance_m, w, 0.01, 1e5);
        s.dispersal.long_distance_m =
            get_number(d, "long_distance_m", s.dispersal.long_distance_m, w, 0.01, 1e5);
        s.dispersal.long_fraction =
            get_number(d, "long_fraction", s.dispersal.long_fraction, w, 0, 1);
    } else {
        s.defaulted.push_back("physiology.dispersal");
    }
    if (p.contains("germination")) {
        const json& g = p.at("germination");
        const std::string w = "physiology.germination";
        require_known_keys(g, {"min_light", "min_soil_water", "probability"}, w);
        s.germination_min_light = get_number(g, "min_light", s.germination_min_light, w, 0, 1);
        s.germination_min_soil_water =
            get_number(g, "min_soil_water", s.germination_min_soil_water, w, 0, 1);
        s.germination_probability =
            get_number(g, "probability", s.germination_probability, w, 0, 1);
    } else {
        s.defaulted.push_back("physiology.germination");
    }
    s.recruit_dbh_m = r.num("recruit_dbh_m", s.recruit_dbh_m, 1e-4, 0.5);
    s.background_mortality_per_yr =
        r.num("background_mortality_per_yr", s.background_mortality_per_yr, 0, 1);
    if (p.contains("suppression")) {
        const json& m = p.at("suppression");
        const std::string w = "physiology.suppression";
        require_known_keys(m, {"growth_efficiency_kg_per_m2_leaf_per_yr", "mortality_per_yr"}, w);
        s.suppression_growth_efficiency_kg_per_m2_leaf_per_yr =
            get_number(m, "growth_efficiency_kg_per_m2_leaf_per_yr",
                       s.suppression_growth_efficiency_kg_per_m2_leaf_per_yr, w, 0, 10);
        s.suppression_mortality_per_yr =
            get_number(m, "mortality_per_yr", s.suppression_mortality_per_yr, w, 0, 1);
    } else {
        s.defaulted.push_back("physiology.suppression");
    }
}

Species parse_species(const json& e) {
    if (!e.is_object()) throw InputError("a species entry must be a JSON object");
    auto keys = kMavsSpeciesKeys;
    keys.push_back("physiology");
    require_known_keys(e, keys, "");
    Species s;
    if (!e.contains("Mesh File"))
        throw InputError("missing key 'Mesh File' (the species identity, as in MAVS)");
    s.mesh_file = get_string(e, "Mesh File", "", "");
    // MAVS never reads "Species Name"; ecoterra names species by it in stem files, outputs and
    // pictures, so it is required rather than taken silently from the mesh path.
    if (!e.contains("Species Name"))
        throw InputError("missing key 'Species Name' (Mesh File '" + s.mesh_file +
                         "'): ecoterra names species by it in stem files and outputs");
    s.name = get_string(e, "Species Name", "", "");
    if (s.name.find_first_not_of(" \t") == std::string::npos)
        throw InputError("'Species Name' is empty (Mesh File '" + s.mesh_file + "')");
    auto req = [&](const char* key, double lo, double hi) {
        if (!e.contains(key)) throw InputError("missing key '" + std::string(key) + "'");
        return get_number(e, key, 0, "", lo, hi);
    };
    s.new_per_area_per_yr = req("Num New Per Area", 0, 100);
    s.growth_rate_per_yr = req("Growth Rate", kTiny, 100);
    s.max_height_m = req("Max Height", 1.4, 150);
    s.min_height_m = get_number(e, "Min Height", 0, "", 0, s.max_height_m);
    s.mesh_height = get_number(e, "Mesh Height", 1, "", kTiny, 1e9);
    s.height_to_diameter_ratio = req("Height To Diameter Ratio", kTiny, 100);
    s.max_age_yr = req("Max Age", 1, 10000);
    s.rotate_mesh = get_bool(e, "Rotate Mesh", false, "");
    if (e.contains("physiology")) {
        if (!e.at("physiology").is_object()) throw InputError("'physiology' must be an object");
        parse_physiology(e.at("physiology"), s);
    } else {
        // A plain MAVS entry: everything physiological defaults.
        parse_physiology(json::object(), s);
    }
    // Defaults derived from the MAVS keys where they carry the information.
    auto derived = [&](const char* key) {
        const std::string k = std::string("physiology.") + key;
        for (const auto& d : s.defaulted)
            if (d == k) return true;
        return false;
    };
    if (derived("maturity_age_yr")) s.maturity_age_yr = std::min(15.0, 0.2 * s.max_age_yr);
    return s;
}

} // namespace

EcosystemDef parse_ecosystem(const json& j, const std::string& source) {
    if (!j.is_object()) throw InputError(source + ": an ecosystem file must be a JSON object");
    auto top = kMavsTopKeys;
    top.insert(top.end(), {"name", "description", "references", "Species"});
    try {
        require_known_keys(j, top, "");
    } catch (const InputError& e) {
        throw InputError(source + ": " + e.what());
    }
    EcosystemDef def;
    def.source = source;
    def.name = j.value("name", std::filesystem::path(source).stem().string());
    for (const auto& k : kMavsTopKeys)
        if (j.contains(k)) def.notes.push_back("MAVS key '" + k + "' is not used by ecoterra");
    if (!j.contains("Species") || !j.at("Species").is_array() || j.at("Species").empty())
        throw InputError(source + ": 'Species' must be a non-empty array");
    std::set<std::string> seen;
    int index = 0;
    for (const auto& e : j.at("Species")) {
        std::string label;
        if (e.is_object() && e.contains("Species Name") && e.at("Species Name").is_string()) {
            label = e.at("Species Name").get<std::string>();
            label.insert(label.begin(), '\'');
            label.push_back('\'');
        } else {
            label = std::to_string(index);
            label.insert(label.begin(), '#');
        }
        try {
            Species s = parse_species(e);
            if (!seen.insert(s.mesh_file).second)
                throw InputError("'Mesh File' " + s.mesh_file +
                                 " appears twice (it is the species identity)");
            if (!s.defaulted.empty()) {
                std::string list;
                for (const auto& d : s.defaulted) list += (list.empty() ? "" : ", ") + d;
                def.notes.push_back("species " + label + ": defaults for " + list);
            }
            def.species.push_back(std::move(s));
        } catch (const InputError& err) {
            throw InputError(source + ": species " + label + ": " + err.what());
        }
        ++index;
    }
    if (def.species.size() > 65535) throw InputError(source + ": more than 65535 species");
    return def;
}

EcosystemDef load_ecosystem(const std::filesystem::path& path) {
    std::ifstream in(path);
    if (!in) throw InputError(path.string() + ": cannot open the ecosystem file");
    std::stringstream ss;
    ss << in.rdbuf();
    return parse_ecosystem(parse_json(ss.str(), path.string()), path.string());
}

json species_to_json(const Species& s) {
    json p = {
        {"height_dbh_slope_per_cm", s.height_dbh_slope_per_cm},
        {"crown_radius_coefficient_m", s.crown_radius_coefficient_m},
        {"crown_radius_exponent", s.crown_radius_exponent},
        {"max_crown_radius_m", s.max_crown_radius_m},
        {"wood_density_kg_per_m3", s.wood_density_kg_per_m3},
        {"leaf_area_per_crown_area", s.leaf_area_per_crown_area},
        {"max_production_kg_per_m2_leaf_per_day", s.max_production_kg_per_m2_leaf_per_day},
        {"respiration_kg_per_m2_leaf_per_m_per_yr", s.respiration_kg_per_m2_leaf_per_m_per_yr},
        {"reserve_capacity_kg_per_m2_leaf", s.reserve_capacity_kg_per_m2_leaf},
        {"initial_reserve_fraction", s.initial_reserve_fraction},
        {"temperature_base_c", s.temperature_base_c},
        {"temperature_optimum_c", s.temperature_optimum_c},
        {"evergreen", s.evergreen},
        {"leaf_on_doy", s.leaf_on_doy},
        {"leaf_off_doy", s.leaf_off_doy},
        {"shade", {{"desired", s.shade.desired}, {"tolerance", s.shade.tolerance}}},
        {"water", {{"desired", s.water.desired}, {"tolerance", s.water.tolerance}}},
        {"ph", {{"desired", s.ph.desired}, {"tolerance", s.ph.tolerance}}},
        {"texture", hydro::texture_name(s.texture)},
        {"texture_tolerance_pct", s.texture_tolerance_pct},
        {"transpiration_per_leaf_area", s.transpiration_per_leaf_area},
        {"maturity_age_yr", s.maturity_age_yr},
        {"seeds_per_yr_at_30cm", s.seeds_per_yr_at_30cm},
        {"dispersal",
         {{"mean_distance_m", s.dispersal.mean_distance_m},
          {"long_distance_m", s.dispersal.long_distance_m},
          {"long_fraction", s.dispersal.long_fraction}}},
        {"germination",
         {{"min_light", s.germination_min_light},
          {"min_soil_water", s.germination_min_soil_water},
          {"probability", s.germination_probability}}},
        {"recruit_dbh_m", s.recruit_dbh_m},
        {"background_mortality_per_yr", s.background_mortality_per_yr},
        {"suppression",
         {{"growth_efficiency_kg_per_m2_leaf_per_yr",
           s.suppression_growth_efficiency_kg_per_m2_leaf_per_yr},
          {"mortality_per_yr", s.suppression_mortality_per_yr}}}};
    return {{"Mesh File", s.mesh_file},
            {"Species Name", s.name},
            {"Num New Per Area", s.new_per_area_per_yr},
            {"Growth Rate", s.growth_rate_per_yr},
            {"Max Height", s.max_height_m},
            {"Min Height", s.min_height_m},
            {"Mesh Height", s.mesh_height},
            {"Height To Diameter Ratio", s.height_to_diameter_ratio},
            {"Max Age", s.max_age_yr},
            {"Rotate Mesh", s.rotate_mesh},
            {"physiology", p}};
}

} // namespace ecoterra::eco
