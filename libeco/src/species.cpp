#include "ecoterra/eco/species.hpp"

#include "ecoterra/hydro/weather.hpp"
#include "ecoterra/json_util.hpp"
#include "ecoterra/units.hpp"

#include <algorithm>
#include <cctype>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

namespace ecoterra::eco {

namespace {

using nlohmann::json;

const std::vector<std::string> kMavsTopKeys = {"Texture Inputs",    "Surface Mesh",
                                               "Simulation Length", "Anvel Replay File",
                                               "PathToMeshes",      "Trail Properties"};
constexpr double kTiny = 1e-9;
/// MAVS's folders of meshes that are not plants (data/scenes/meshes).
const std::vector<std::string> kMavsObjectFolders = {"buildings", "misc", "urban", "vehicles"};
/// The MAVS mapping's height limits (m) and the ratio of a broad plant.
constexpr double kGroundLayerMaxHeightM = 0.5;
constexpr double kShrubMaxHeightM = 5.0;
constexpr double kShrubMinRatio = 0.2;
/// Default maximum stem diameter: Max Height over this (m per m).
constexpr double kMaxHeightPerStemDiameter = 20.0;
/// MAVS life stages, in order.
const std::vector<std::string> kStageWords = {"young", "medium", "adult"};

/// Physiology defaults that differ from a tree's, per life form (docs/ecosystem.md s1.1); each
/// applies only where the file leaves the key out.
const nlohmann::json& life_form_defaults(LifeForm f) {
    static const json shrub = {
        {"height_dbh_slope_per_cm", 0.3},
        {"crown_radius_coefficient_m", 0.35},
        {"leaf_area_per_crown_area", 3.0},
        {"recruit_dbh_m", 0.005},
        {"seeds_per_yr_at_30cm", 500.0},
        {"dispersal",
         {{"mean_distance_m", 5.0}, {"long_distance_m", 30.0}, {"long_fraction", 0.1}}},
        {"germination", {{"min_light", 0.1}}},
        {"suppression", {{"growth_efficiency_kg_per_m2_leaf_per_yr", 0.1}}}};
    static const json grass = {{"leaf_area_per_crown_area", 2.88},
                               {"transpiration_per_leaf_area", 0.35},
                               {"shade", {{"desired", 0.0}, {"tolerance", 0.35}}},
                               {"water", {{"desired", 1.0}, {"tolerance", 0.5}}},
                               {"germination", {{"min_light", 0.2}}},
                               {"background_mortality_per_yr", 0.0}};
    static const json none = json::object();
    return f == LifeForm::shrub ? shrub : f == LifeForm::grass ? grass : none;
}

/// How long a leaf lives, yr: an evergreen's life span, a deciduous leaf's season.
double leaf_longevity_yr(const Species& s) {
    if (s.evergreen) return s.leaf_lifespan_yr;
    const int days = s.leaf_off_doy - s.leaf_on_doy;
    return std::max(days, 1) / static_cast<double>(hydro::kDaysPerYear);
}

/// Sets the life-form defaults of the keys `s.defaulted` lists.
void apply_life_form_defaults(Species& s) {
    const auto& d = s.defaulted;
    auto defaulted = [&](const std::string& key) {
        return std::find(d.begin(), d.end(), "physiology." + key) != d.end();
    };
    json keep = json::object();
    const json& lf = life_form_defaults(s.life_form);
    for (const auto& item : lf.items()) {
        if (item.value().is_object()) {
            for (const auto& sub : item.value().items())
                if (defaulted(item.key() + "." + sub.key()))
                    keep[item.key()][sub.key()] = sub.value();
        } else if (defaulted(item.key())) {
            keep[item.key()] = item.value();
        }
    }
    s = physiology_catalog().read(keep, s);
    if (defaulted("max_stem_diameter_m") && s.life_form != LifeForm::grass &&
        s.life_form != LifeForm::object)
        s.max_stem_diameter_m = s.max_height_m / kMaxHeightPerStemDiameter;
    if (defaulted("maturity_age_yr"))
        s.maturity_age_yr = s.life_form == LifeForm::shrub ? std::min(3.0, 0.2 * s.max_age_yr)
                                                           : std::min(15.0, 0.2 * s.max_age_yr);
    if (defaulted("leaf_lifespan_yr")) s.leaf_lifespan_yr = s.evergreen ? 2.0 : 1.0;
    if (defaulted("sapwood_respiration_kg_per_m2_leaf_per_m_per_yr"))
        s.sapwood_respiration_kg_per_m2_leaf_per_m_per_yr =
            s.respiration_kg_per_m2_leaf_per_m_per_yr;
    if (defaulted("leaf_mass_per_area_kg_per_m2"))
        s.leaf_mass_per_area_kg_per_m2 = leaf_mass_per_area_from_longevity(leaf_longevity_yr(s));
    if (s.life_form == LifeForm::shrub && defaulted("max_crown_radius_m"))
        s.max_crown_radius_m = std::clamp(0.6 * s.max_height_m, 0.3, 5.0);
}

/// A preference {desired, tolerance} as two dotted keys.
template <Preference Species::*M>
std::vector<Param<Species>> preference(const std::string& key, const std::string& unit, double lo,
                                       double hi, const std::string& what) {
    return {number<Species>(
                key + ".desired", +[](Species& s) -> double& { return (s.*M).desired; }, unit, lo,
                hi, what + ": the preferred value"),
            number<Species>(
                key + ".tolerance", +[](Species& s) -> double& { return (s.*M).tolerance; }, unit,
                kTiny, 1e6, what + ": the distance from it at which the factor falls to 1/e")};
}

std::vector<std::pair<std::string, hydro::Texture>> texture_choices() {
    std::vector<std::pair<std::string, hydro::Texture>> v;
    for (int k = 0; k < hydro::kTextureCount; ++k)
        v.emplace_back(hydro::texture_name(static_cast<hydro::Texture>(k)),
                       static_cast<hydro::Texture>(k));
    return v;
}

void parse_physiology(const json& p, Species& s) {
    const auto& c = physiology_catalog();
    s = c.read(p, s);
    for (const auto& k : c.absent(p)) s.defaulted.push_back("physiology." + k);
    if (!p.contains("life_form"))
        s.life_form = mavs_life_form(s.mesh_file, s.max_height_m, s.height_to_diameter_ratio);
    apply_life_form_defaults(s);
    if (s.life_form != LifeForm::grass) // only the ground layer uses it: not worth a note
        std::erase(s.defaulted, std::string("physiology.root_depth_m"));
    if (s.life_form == LifeForm::tree && !(s.max_height_m > kBreastHeightM))
        throw InputError("Max Height = " + format_number(s.max_height_m) +
                         " m: a tree must outgrow breast height (" + format_number(kBreastHeightM) +
                         " m); a shorter plant is a shrub or grass (physiology.life_form)");
    if (!(s.temperature_optimum_c > s.temperature_base_c))
        throw InputError("physiology.temperature_optimum_c must exceed temperature_base_c");
    if (!s.evergreen && s.leaf_off_doy <= s.leaf_on_doy)
        throw InputError("physiology.leaf_off_doy must come after leaf_on_doy");
}

Species parse_species(const json& e) {
    if (!e.is_object()) throw InputError("a species entry must be a JSON object");
    Species s;
    if (!e.contains("Mesh File"))
        throw InputError("missing key 'Mesh File' (the species identity, as in MAVS)");
    s.mesh_file = get_string(e, "Mesh File", "", "");
    // MAVS never reads "Species Name"; ecoterra names species by it in stem files, outputs and
    // pictures, so it is required rather than taken silently from the mesh path.
    if (!e.contains("Species Name"))
        throw InputError("missing key 'Species Name' (Mesh File '" + s.mesh_file +
                         "'): ecoterra names species by it in stem files and outputs");
    s = mavs_species_catalog().read(e, s, {"physiology"});
    if (s.name.find_first_not_of(" \t") == std::string::npos)
        throw InputError("'Species Name' is empty (Mesh File '" + s.mesh_file + "')");
    if (s.min_height_m > s.max_height_m)
        throw InputError("Min Height = " + format_number(s.min_height_m) +
                         " is above Max Height = " + format_number(s.max_height_m));
    if (e.contains("physiology") && !e.at("physiology").is_object())
        throw InputError("'physiology' must be an object");
    parse_physiology(e.value("physiology", json::object()), s);
    return s;
}

} // namespace

namespace {

/// The JSON of an ecosystem file; InputError naming it if it cannot be read or parsed.
json read_ecosystem_json(const std::filesystem::path& path) {
    std::ifstream in(path);
    if (!in) throw InputError(path.string() + ": cannot open the ecosystem file");
    std::stringstream ss;
    ss << in.rdbuf();
    return parse_json(ss.str(), path.string());
}

/// "Pecan young" -> {"Pecan", 0}; no stage word -> {"", -1}.
std::pair<std::string, int> stage_of_name(const std::string& name) {
    const auto sp = name.find_last_of(' ');
    if (sp == std::string::npos || sp == 0) return {"", -1};
    std::string word = name.substr(sp + 1);
    for (auto& c : word) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    for (std::size_t k = 0; k < kStageWords.size(); ++k)
        if (word == kStageWords[k]) return {name.substr(0, sp), static_cast<int>(k)};
    return {"", -1};
}

/// MAVS lists a species' young, medium and adult meshes as separate species: entries named
/// "<name> young|medium|adult" without a physiology block become one species named <name> with
/// the adult's keys, the largest Max Height and Max Age, the smallest Min Height and the sum of
/// the arrival rates (docs/ecosystem.md s1.1).
json group_life_stages(const json& species, std::vector<std::string>& notes) {
    std::map<std::string, std::vector<std::pair<int, std::size_t>>> groups;
    for (std::size_t k = 0; k < species.size(); ++k) {
        const json& e = species[k];
        if (!e.is_object() || e.contains("physiology") || !e.contains("Species Name") ||
            !e.at("Species Name").is_string())
            continue;
        const auto [base, stage] = stage_of_name(e.at("Species Name").get<std::string>());
        if (stage >= 0) groups[base].push_back({stage, k});
    }
    std::vector<char> merged_away(species.size(), 0);
    std::map<std::size_t, json> replacement;
    for (auto& [base, members] : groups) {
        std::stable_sort(members.begin(), members.end());
        json g = species[members.back().second]; // the oldest stage's keys
        std::string list;
        bool numbers_ok = true;
        double arrivals = 0, hmax = 0, hmin = 1e300, age = 0;
        for (const auto& [stage, k] : members) {
            const json& e = species[k];
            for (const char* key : {"Num New Per Area", "Max Height", "Max Age"})
                numbers_ok = numbers_ok && e.contains(key) && e.at(key).is_number();
            numbers_ok =
                numbers_ok && (!e.contains("Min Height") || e.at("Min Height").is_number());
            if (!numbers_ok) break;
            arrivals += e.at("Num New Per Area").get<double>();
            hmax = std::max(hmax, e.at("Max Height").get<double>());
            age = std::max(age, e.at("Max Age").get<double>());
            hmin =
                std::min(hmin, e.contains("Min Height") ? e.at("Min Height").get<double>() : 0.0);
            if (!list.empty()) list += ", ";
            list += kStageWords[static_cast<std::size_t>(stage)];
            list += " (";
            const auto mesh = e.find("Mesh File");
            list += mesh != e.end() && mesh->is_string() ? mesh->get<std::string>() : "?";
            list += ')';
        }
        if (!numbers_ok) continue; // the species reader names the bad key
        g["Species Name"] = base;
        g["Num New Per Area"] = arrivals;
        g["Max Height"] = hmax;
        g["Min Height"] = std::min(hmin, hmax);
        g["Max Age"] = age;
        replacement[members.front().second] = g;
        for (std::size_t q = 1; q < members.size(); ++q) merged_away[members[q].second] = 1;
        std::string note = "life stages of '";
        note += base;
        note += "' grouped into one species: ";
        note += list;
        note += "; Max Height ";
        note += format_number(hmax);
        note += " m, arrivals ";
        note += format_number(arrivals);
        note += " per m2 and year (the sum), the mesh of the oldest stage";
        notes.push_back(note);
    }
    json out = json::array();
    for (std::size_t k = 0; k < species.size(); ++k) {
        if (merged_away[k]) continue;
        const auto r = replacement.find(k);
        out.push_back(r == replacement.end() ? species[k] : r->second);
    }
    return out;
}

/// MAVS's random-scene inputs (its `random_scene_inputs.json`): the ecosystem is the file its
/// "Ecosystem File" names, read as given or, when that path does not exist here (MAVS's example
/// names a Windows path), by its file name beside the inputs file; "Plant Density" scales the
/// arrival rates as MAVS's growth factor does. The terrain keys are noted, not used.
EcosystemDef read_random_scene_inputs(const json& j, const std::string& source) {
    const std::string eco = with_context(source, [&] {
        if (!j.at("Ecosystem File").is_string())
            throw InputError("'Ecosystem File' must be a file name");
        return j.at("Ecosystem File").get<std::string>();
    });
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::path here = fs::path(source).parent_path();
    fs::path path = fs::path(eco).is_absolute() ? fs::path(eco) : here / eco;
    std::string how;
    if (!fs::exists(path, ec)) {
        // A Windows path on Linux has no directory separators std::filesystem knows.
        std::string name = eco.substr(eco.find_last_of("/\\") + 1);
        const fs::path beside = here / name;
        if (!fs::exists(beside, ec))
            throw InputError(source + ": 'Ecosystem File' = '" + eco +
                             "' does not exist, nor does '" + beside.string() + "' beside it");
        how = " (found by its file name beside the inputs file; the path given does not exist)";
        path = beside;
    }
    json inner = read_ecosystem_json(path);
    if (inner.is_object() && inner.contains("Ecosystem File") && !inner.contains("Species"))
        throw InputError(source + ": 'Ecosystem File' names another random-scene inputs file");
    EcosystemDef def = parse_ecosystem(inner, path.string());
    double density = 1.0;
    with_context(source, [&] {
        if (j.contains("Plant Density")) {
            const json& d = j.at("Plant Density");
            if (!d.is_number() || !(d.get<double>() >= 0) || d.get<double>() > 1e6)
                throw InputError("'Plant Density' = " + d.dump() +
                                 " must be a number in [0, 1e6] (MAVS's growth factor)");
            density = d.get<double>();
        }
    });
    for (auto& s : def.species) s.new_per_area_per_yr *= density;
    std::vector<std::string> notes;
    notes.push_back("MAVS random-scene inputs: ecosystem " + path.string() + how +
                    ", arrival rates times Plant Density " + format_number(density));
    std::string unused;
    for (const auto& item : j.items())
        if (item.key() != "Ecosystem File" && item.key() != "Plant Density") {
            if (!unused.empty()) unused += ", ";
            unused += "'" + item.key() + "'";
        }
    if (!unused.empty())
        notes.push_back("MAVS random-scene keys not used by ecoterra (the scene's terrain and "
                        "paths come from the ecoterra scene): " +
                        unused);
    notes.insert(notes.end(), def.notes.begin(), def.notes.end());
    def.notes = std::move(notes);
    def.source = source;
    return def;
}

} // namespace

namespace {
/// The file's `life_stages`: true for "group" (the default), false for "separate".
bool life_stages_grouped(const json& j, const std::string& source) {
    if (!j.contains("life_stages")) return true;
    const json& v = j.at("life_stages");
    if (!v.is_string() || (v != "group" && v != "separate"))
        throw InputError(source + ": 'life_stages' = " + v.dump() +
                         " must be \"group\" (MAVS's young, medium and adult entries of a "
                         "species become one species, the default) or \"separate\"");
    return v == "group";
}
} // namespace

namespace {
/// How messages name an entry of "Species": 'its name', or #its index without one.
std::string species_label(const json& e, int index) {
    if (e.is_object() && e.contains("Species Name") && e.at("Species Name").is_string())
        return "'" + e.at("Species Name").get<std::string>() + "'";
    return "#" + std::to_string(index);
}
} // namespace

EcosystemDef parse_ecosystem(const json& j, const std::string& source) {
    if (!j.is_object()) throw InputError(source + ": an ecosystem file must be a JSON object");
    if (j.contains("Ecosystem File") && !j.contains("Species"))
        return read_random_scene_inputs(j, source);
    auto top = kMavsTopKeys;
    top.insert(top.end(), {"name", "description", "references", "Species", "life_stages"});
    with_context(source, [&] { require_known_keys(j, top, ""); });
    EcosystemDef def;
    def.source = source;
    with_context(source, [&] {
        def.name = get_string(j, "name", std::filesystem::path(source).stem().string(), "");
    });
    for (const auto& k : kMavsTopKeys)
        if (j.contains(k)) def.notes.push_back("MAVS key '" + k + "' is not used by ecoterra");
    if (!j.contains("Species") || !j.at("Species").is_array() || j.at("Species").empty())
        throw InputError(source + ": 'Species' must be a non-empty array");
    const json entries = life_stages_grouped(j, source)
                             ? group_life_stages(j.at("Species"), def.notes)
                             : j.at("Species");
    std::set<std::string> seen, names;
    std::set<std::string> defaulted_keys; // physiology keys some species leave to their default
    int species_with_defaults = 0;
    int index = 0;
    for (const auto& e : entries) {
        const std::string label = species_label(e, index);
        with_context(source + ": species " + label, [&] {
            Species s = parse_species(e);
            if (!seen.insert(s.mesh_file).second)
                throw InputError("'Mesh File' " + s.mesh_file +
                                 " appears twice (it is the species identity)");
            if (!names.insert(s.name).second) {
                // MAVS's files name two meshes "Bluegrass 1"; outputs need one name per species.
                const std::string stem = std::filesystem::path(s.mesh_file).stem().string();
                const std::string renamed = s.name + " (" + stem + ")";
                def.notes.push_back("species " + label + " (Mesh File " + s.mesh_file +
                                    ") shares its name with an earlier species: named '" + renamed +
                                    "'");
                s.name = renamed;
                if (!names.insert(s.name).second)
                    throw InputError("'Species Name' appears twice with the same mesh name");
            }
            if (!e.contains("physiology")) {
                def.notes.push_back("species " + label +
                                    ": no physiology block, every physiology key takes its "
                                    "default for " +
                                    (s.life_form == LifeForm::object ? "an " : "a ") +
                                    life_form_name(s.life_form) + " (docs/ecosystem.md s1)");
            } else {
                for (const auto& d : s.defaulted)
                    if (d != "physiology.life_form") defaulted_keys.insert(d);
                if (!s.defaulted.empty()) ++species_with_defaults;
            }
            if (std::find(s.defaulted.begin(), s.defaulted.end(), "physiology.life_form") !=
                s.defaulted.end()) {
                std::string why;
                mavs_life_form(s.mesh_file, s.max_height_m, s.height_to_diameter_ratio, &why);
                def.notes.push_back("species " + label + ": life form " +
                                    life_form_name(s.life_form) + " (" + why + ")");
            }
            def.species.push_back(std::move(s));
        });
        ++index;
    }
    if (def.species.size() > 65535) throw InputError(source + ": more than 65535 species");
    // One line for the defaults, not one per species: they are documented values, nothing to act
    // on; the run's /species json records every value used.
    if (!defaulted_keys.empty())
        def.notes.push_back(std::to_string(species_with_defaults) + " of " +
                            std::to_string(def.species.size()) + " species leave " +
                            std::to_string(defaulted_keys.size()) +
                            " physiology keys at their defaults (`ecoterra describe species` "
                            "lists them; the run's /species records every value used)");
    return def;
}

const char* life_form_name(LifeForm f) {
    for (const auto& [name, form] : kLifeForms)
        if (form == f) return name;
    return "?";
}

LifeForm mavs_life_form(const std::string& mesh_file, double h, double ratio, std::string* why) {
    const std::filesystem::path mesh(mesh_file); // the iterator below points into it
    std::string folder = mesh.begin() == mesh.end() ? "" : mesh.begin()->string();
    for (auto& c : folder) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    auto say = [&](const std::string& w) {
        if (why) *why = w;
    };
    if (std::find(kMavsObjectFolders.begin(), kMavsObjectFolders.end(), folder) !=
        kMavsObjectFolders.end()) {
        say("its mesh lies in MAVS's '" + folder + "' folder, not a plant's");
        return LifeForm::object;
    }
    if (h < kGroundLayerMaxHeightM) {
        say("Max Height " + format_number(h) + " m < " + format_number(kGroundLayerMaxHeightM) +
            " m");
        return LifeForm::grass;
    }
    if (h < kShrubMaxHeightM) {
        if (ratio >= kShrubMinRatio) {
            say("Max Height " + format_number(h) + " m < " + format_number(kShrubMaxHeightM) +
                " m and Height To Diameter Ratio " + format_number(ratio) +
                " >= " + format_number(kShrubMinRatio));
            return LifeForm::shrub;
        }
        say("Max Height " + format_number(h) + " m < " + format_number(kShrubMaxHeightM) +
            " m and Height To Diameter Ratio " + format_number(ratio) + " < " +
            format_number(kShrubMinRatio) + " (slender)");
        return LifeForm::grass;
    }
    say("Max Height " + format_number(h) + " m >= " + format_number(kShrubMaxHeightM) + " m");
    return LifeForm::tree;
}

EcosystemDef load_ecosystem(const std::filesystem::path& path) {
    return parse_ecosystem(read_ecosystem_json(path), path.string());
}

json species_to_json(const Species& s) {
    json j = mavs_species_catalog().to_json(s);
    j["physiology"] = physiology_catalog().to_json(s);
    return j;
}

const ParamCatalog<Species>& mavs_species_catalog() {
    using S = Species;
    static const ParamCatalog<S> c(
        "",
        {text<S>("Mesh File", &S::mesh_file, "MAVS mesh of the species; its identity").mandatory(),
         text<S>("Species Name", &S::name, "name in stem files, outputs and pictures").mandatory(),
         number<S>("Num New Per Area", &S::new_per_area_per_yr, "1/(m2 yr)", 0, 100,
                   "background arrivals per square metre and year")
             .mandatory(),
         number<S>("Growth Rate", &S::growth_rate_per_yr, "1/yr", kTiny, 100,
                   "r of H = Hmax (1 - exp(-r t)) (light-only growth)")
             .mandatory(),
         number<S>("Max Height", &S::max_height_m, "m", 0.01, 150,
                   "asymptotic height Hmax (a tree's above breast height, 1.3 m)")
             .mandatory(),
         number<S>("Min Height", &S::min_height_m, "m", 0, 150,
                   "MAVS prunes plants below it; at most Max Height"),
         number<S>("Mesh Height", &S::mesh_height, "mesh units", kTiny, 1e9,
                   "height of the unscaled mesh"),
         number<S>("Height To Diameter Ratio", &S::height_to_diameter_ratio, "1", kTiny, 100,
                   "MAVS's competition ratio: competitive radius 0.5 ratio H")
             .mandatory(),
         number<S>("Max Age", &S::max_age_yr, "yr", 1, 10000, "age at which a plant dies")
             .mandatory(),
         flag<S>("Rotate Mesh", &S::rotate_mesh, "MAVS: the mesh is Y-up and is turned")});
    return c;
}

const ParamCatalog<Species>& physiology_catalog() {
    using S = Species;
    static const ParamCatalog<S> c = [] {
        std::vector<Param<S>> v = {
            number<S>("height_dbh_slope_per_cm", &S::height_dbh_slope_per_cm, "1/cm", 1e-4, 1.0,
                      "b of H = 1.3 + (Hmax - 1.3)(1 - exp(-b D_cm))"),
            number<S>("crown_radius_coefficient_m", &S::crown_radius_coefficient_m, "m", kTiny, 10,
                      "c1 of the crown radius R = c1 D_cm^c2"),
            number<S>("crown_radius_exponent", &S::crown_radius_exponent, "1", 0.1, 1.5,
                      "c2 of the crown radius R = c1 D_cm^c2"),
            number<S>("max_crown_radius_m", &S::max_crown_radius_m, "m", 0.1, 50,
                      "upper bound of the crown radius"),
            number<S>("max_stem_diameter_m", &S::max_stem_diameter_m, "m", 0, 10,
                      "stem diameter at which wood growth ends (from 0.9 of it the surplus is "
                      "turned over); 0 = none")
                .with_note("Max Height / 20"),
            number<S>("wood_density_kg_per_m3", &S::wood_density_kg_per_m3, "kg/m3", 50, 1500,
                      "dry wood mass per fresh volume"),
            number<S>("leaf_area_per_crown_area", &S::leaf_area_per_crown_area, "m2/m2", 0.05, 20,
                      "leaf area index of the crown"),
            number<S>("shaded_crown_leaf_fraction", &S::shaded_crown_leaf_fraction, "1", 0.01, 1,
                      "leaf area index of a crown in full shade as a fraction of "
                      "leaf_area_per_crown_area (vegetation.growth = light_and_turnover: the "
                      "crown's LAI is LAI (f + (1 - f) I) at light I; 1 = fixed)"),
            number<S>("max_production_kg_per_m2_leaf_per_day",
                      &S::max_production_kg_per_m2_leaf_per_day, "kg/(m2 d)", kTiny, 1,
                      "carbohydrate production per m2 of leaf in full light, water and warmth"),
            number<S>("respiration_kg_per_m2_leaf_per_m_per_yr",
                      &S::respiration_kg_per_m2_leaf_per_m_per_yr, "kg/(m3 yr)", 0, 10,
                      "maintenance respiration at 20 degC per m2 of leaf and m of height"),
            number<S>("sapwood_respiration_kg_per_m2_leaf_per_m_per_yr",
                      &S::sapwood_respiration_kg_per_m2_leaf_per_m_per_yr, "kg/(m3 yr)", 0, 10,
                      "maintenance respiration of the sapwood at 20 degC per m2 of leaf and m of "
                      "height (vegetation.growth = light_and_turnover, whose tissue cost carries "
                      "leaves and fine roots)")
                .with_note("respiration_kg_per_m2_leaf_per_m_per_yr"),
            number<S>("reserve_capacity_kg_per_m2_leaf", &S::reserve_capacity_kg_per_m2_leaf,
                      "kg/m2", kTiny, 100, "carbohydrate reserve a plant holds per m2 of leaf"),
            number<S>("initial_reserve_fraction", &S::initial_reserve_fraction, "1", kTiny, 1,
                      "reserve of a recruit as a fraction of its capacity"),
            number<S>("temperature_base_c", &S::temperature_base_c, "degC", -30, 40,
                      "production starts above it"),
            number<S>("temperature_optimum_c", &S::temperature_optimum_c, "degC", -20, 50,
                      "production is full above it; above temperature_base_c"),
            flag<S>("evergreen", &S::evergreen, "leaves all year (else leaf_on_doy..leaf_off_doy)"),
            choice<S>("crown_shape", &S::crown_shape,
                      std::vector<std::pair<std::string, CrownShape>>{
                          {"cone", CrownShape::cone},
                          {"ellipsoid", CrownShape::ellipsoid},
                          {"umbrella", CrownShape::umbrella}},
                      "outline of the crown in scene exports (`ecoterra export scene`); growth "
                      "uses only the crown radius"),
            choice<S>(
                "life_form", &S::life_form,
                std::vector<std::pair<std::string, LifeForm>>(kLifeForms.begin(), kLifeForms.end()),
                "tree (trunk at breast height), shrub (stem at the ground), grass (grass "
                "or herb: ground-layer cover) or object (inert obstacle)")
                .with_note("from the MAVS keys (docs/ecosystem.md s1.1)"),
            number<S>("root_depth_m", &S::root_depth_m, "m", 0.01, 10,
                      "grass: depth its roots reach; it takes only the water above it"),
            integer<S>("leaf_on_doy", &S::leaf_on_doy, "day", 1, 366, "deciduous: leaves out"),
            integer<S>("leaf_off_doy", &S::leaf_off_doy, "day", 1, 366,
                       "deciduous: leaves fall; after leaf_on_doy"),
        };
        auto add = [&](std::vector<Param<S>> more) {
            for (auto& p : more) v.push_back(std::move(p));
        };
        add(preference<&S::shade>("shade", "1", 0, 1,
                                  "shade preference (fraction shaded); vegetation.growth = "
                                  "paper002"));
        add({number<S>("light_half_saturation", &S::light_half_saturation, "1", 0.001, 100,
                       "light (fraction of full sun) at which production per m2 of leaf is half "
                       "its saturated rate; low for shade-tolerant species (vegetation.growth = "
                       "light_and_turnover)"),
             number<S>("leaf_lifespan_yr", &S::leaf_lifespan_yr, "yr", 0.05, 50,
                       "years between a leaf's building and its fall; the crown is rebuilt every "
                       "leaf_lifespan_yr (light_and_turnover)")
                 .with_note("2 evergreen (LPJ-GUESS leaflong), 1 deciduous"),
             number<S>("leaf_mass_per_area_kg_per_m2", &S::leaf_mass_per_area_kg_per_m2, "kg/m2",
                       0.005, 2, "dry mass of a m2 of leaf (light_and_turnover)")
                 .with_note("from leaf longevity, Reich et al. 1997"),
             number<S>("fine_root_to_leaf_mass", &S::fine_root_to_leaf_mass, "1", 0, 20,
                       "fine-root mass per leaf mass (LPJ-GUESS ltor_max)"),
             number<S>("fine_root_turnover_per_yr", &S::fine_root_turnover_per_yr, "1/yr", 0, 20,
                       "share of the fine roots renewed a year (LPJ-GUESS turnover_root)")});
        add(preference<&S::water>("water", "1", 0, 1,
                                  "water preference (fraction of demand supplied)"));
        add(preference<&S::ph>("ph", "pH", 0, 14, "soil pH preference"));
        add({choice<S>("texture", &S::texture, texture_choices(), "preferred USDA texture class"),
             number<S>("texture_tolerance_pct", &S::texture_tolerance_pct, "%", kTiny, 200,
                       "distance in the texture triangle at which the factor falls to 1/e"),
             number<S>("transpiration_per_leaf_area", &S::transpiration_per_leaf_area, "m3/(m2 m)",
                       0, 5, "water per m2 of leaf per m of FAO-56 reference ET"),
             number<S>("maturity_age_yr", &S::maturity_age_yr, "yr", 0, 5000,
                       "age of the first seeds")
                 .with_note("min(15, 0.2 Max Age)"),
             number<S>("seeds_per_yr_at_30cm", &S::seeds_per_yr_at_30cm, "1/yr", 0, 1e6,
                       "established-seedling potential of a 30 cm tree per year"),
             number<S>(
                 "dispersal.mean_distance_m",
                 +[](S& s) -> double& { return s.dispersal.mean_distance_m; }, "m", 0.01, 1e5,
                 "mean distance of the short-range dispersal kernel"),
             number<S>(
                 "dispersal.long_distance_m",
                 +[](S& s) -> double& { return s.dispersal.long_distance_m; }, "m", 0.01, 1e5,
                 "mean distance of the long-range kernel"),
             number<S>(
                 "dispersal.long_fraction",
                 +[](S& s) -> double& { return s.dispersal.long_fraction; }, "1", 0, 1,
                 "share of seeds in the long-range kernel"),
             number<S>("germination.min_light", &S::germination_min_light, "1", 0, 1,
                       "fraction of full light at the ground a seed needs"),
             number<S>("germination.min_soil_water", &S::germination_min_soil_water, "1", 0, 1,
                       "relative extractable soil water a seed needs"),
             number<S>("germination.probability", &S::germination_probability, "1", 0, 1,
                       "of a seed landing on a suitable cell"),
             number<S>("recruit_dbh_m", &S::recruit_dbh_m, "m", 1e-4, 0.5,
                       "diameter a recruit enters with"),
             number<S>("background_mortality_per_yr", &S::background_mortality_per_yr, "1/yr", 0, 1,
                       "yearly death probability of any plant"),
             number<S>("senescence.mortality_per_yr", &S::senescence_mortality_per_yr, "1/yr", 0, 1,
                       "size-related mortality m_s: a plant of stem diameter D also dies with "
                       "probability m_s (D / D_s)^k a year (Lines et al. 2010's rising arm); 0 = "
                       "none"),
             number<S>("senescence.diameter_m", &S::senescence_diameter_m, "m", 0.01, 10,
                       "D_s, the stem diameter at which the size-related mortality is m_s"),
             number<S>("senescence.exponent", &S::senescence_exponent, "1", 0, 20,
                       "k, how steeply the size-related mortality rises with the stem diameter"),
             number<S>("suppression.growth_efficiency_kg_per_m2_leaf_per_yr",
                       &S::suppression_growth_efficiency_kg_per_m2_leaf_per_yr, "kg/(m2 yr)", 0, 10,
                       "growth efficiency below which a plant is suppressed"),
             number<S>("suppression.mortality_per_yr", &S::suppression_mortality_per_yr, "1/yr", 0,
                       1, "yearly death probability of a fully suppressed plant"),
             number<S>("deadwood.decay_rate_per_yr", &S::deadwood_decay_rate_per_yr, "1/yr", 0, 2,
                       "exponential mass loss of a log, k of m = m0 exp(-k t); hardwoods "
                       "0.043-0.064, conifers 0.024-0.040 (Russell et al. 2014)"),
             number<S>("deadwood.snag_decay_rate_per_yr", &S::snag_decay_rate_per_yr, "1/yr", 0, 2,
                       "exponential mass loss of a standing snag (drier than a log, slower; "
                       "Harmon et al. 2011); the default is iLand's ksw"),
             number<S>("deadwood.snag_fall_multiplier", &S::snag_fall_multiplier, "1", 0.01, 100,
                       "multiplies FVS-FFE's size-dependent snag fall rate (FALLX)"),
             number<S>("wind.creg_n_m_per_kg", &S::wind_creg_n_m_per_kg, "N m/kg", 1, 1000,
                       "resistance to overturning per kg of green stem (ForestGALES Creg; oak "
                       "202, birch 131, Scots pine 143 on free-draining soil, medium rooting)"),
             number<S>("wind.mor_pa", &S::wind_mor_pa, "Pa", 1e6, 2e8,
                       "modulus of rupture of green wood (ForestGALES: oak 59 MPa, birch 63, "
                       "Scots pine 46)"),
             number<S>("wind.green_density_kg_per_m3", &S::wind_green_density_kg_per_m3, "kg/m3",
                       100, 2000, "density of green stem wood (ForestGALES: oak 1158, pines 850)"),
             number<S>("wind.knot_factor", &S::wind_knot_factor, "1", 0.1, 1,
                       "reduces the modulus of rupture for knots (ForestGALES: pines 0.85)"),
             number<S>("wind.drag_c", &S::wind_drag_c, "1", 0.01, 20,
                       "crown streamlining: drag = c u^-n (ForestGALES c_drag)"),
             number<S>("wind.drag_n", &S::wind_drag_n, "1", 0, 3,
                       "crown streamlining exponent (ForestGALES n_drag)"),
             number<S>("wind.crown_depth_intercept_m", &S::wind_crown_depth_intercept_m, "m", -50,
                       50,
                       "crown depth = intercept + slope x height (ForestGALES param0_cr_depth)"),
             number<S>("wind.crown_depth_per_height", &S::wind_crown_depth_per_height, "1", 0, 1,
                       "crown depth per m of height (ForestGALES param1_cr_depth)")});
        return ParamCatalog<S>("physiology", std::move(v));
    }();
    return c;
}

} // namespace ecoterra::eco
