#include "ecoterra/eco/species.hpp"

#include "ecoterra/json_util.hpp"

#include <algorithm>
#include <fstream>
#include <set>
#include <sstream>

namespace ecoterra::eco {

namespace {

using nlohmann::json;

const std::vector<std::string> kMavsTopKeys = {"Texture Inputs",    "Surface Mesh",
                                               "Simulation Length", "Anvel Replay File",
                                               "PathToMeshes",      "Trail Properties"};
constexpr double kTiny = 1e-9;

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
    // Defaults derived from the MAVS keys where they carry the information.
    const auto& d = s.defaulted;
    if (std::find(d.begin(), d.end(), "physiology.maturity_age_yr") != d.end())
        s.maturity_age_yr = std::min(15.0, 0.2 * s.max_age_yr);
    return s;
}

} // namespace

EcosystemDef parse_ecosystem(const json& j, const std::string& source) {
    if (!j.is_object()) throw InputError(source + ": an ecosystem file must be a JSON object");
    auto top = kMavsTopKeys;
    top.insert(top.end(), {"name", "description", "references", "Species"});
    with_context(source, [&] { require_known_keys(j, top, ""); });
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
        with_context(source + ": species " + label, [&] {
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
        });
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
         number<S>("Max Height", &S::max_height_m, "m", 1.4, 150, "asymptotic height Hmax")
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
            number<S>("wood_density_kg_per_m3", &S::wood_density_kg_per_m3, "kg/m3", 50, 1500,
                      "dry wood mass per fresh volume"),
            number<S>("leaf_area_per_crown_area", &S::leaf_area_per_crown_area, "m2/m2", 0.05, 20,
                      "leaf area index of the crown"),
            number<S>("max_production_kg_per_m2_leaf_per_day",
                      &S::max_production_kg_per_m2_leaf_per_day, "kg/(m2 d)", kTiny, 1,
                      "carbohydrate production per m2 of leaf in full light, water and warmth"),
            number<S>("respiration_kg_per_m2_leaf_per_m_per_yr",
                      &S::respiration_kg_per_m2_leaf_per_m_per_yr, "kg/(m3 yr)", 0, 10,
                      "maintenance respiration at 20 degC per m2 of leaf and m of height"),
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
            integer<S>("leaf_on_doy", &S::leaf_on_doy, "day", 1, 366, "deciduous: leaves out"),
            integer<S>("leaf_off_doy", &S::leaf_off_doy, "day", 1, 366,
                       "deciduous: leaves fall; after leaf_on_doy"),
        };
        auto add = [&](std::vector<Param<S>> more) {
            for (auto& p : more) v.push_back(std::move(p));
        };
        add(preference<&S::shade>("shade", "1", 0, 1, "shade preference (fraction shaded)"));
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
             number<S>("suppression.growth_efficiency_kg_per_m2_leaf_per_yr",
                       &S::suppression_growth_efficiency_kg_per_m2_leaf_per_yr, "kg/(m2 yr)", 0, 10,
                       "growth efficiency below which a plant is suppressed"),
             number<S>("suppression.mortality_per_yr", &S::suppression_mortality_per_yr, "1/yr", 0,
                       1, "yearly death probability of a fully suppressed plant")});
        return ParamCatalog<S>("physiology", std::move(v));
    }();
    return c;
}

} // namespace ecoterra::eco
