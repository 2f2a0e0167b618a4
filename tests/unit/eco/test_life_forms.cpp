// Life forms (issue 15 s1): MAVS's own ecosystem files (tests/data/mavs_ecosystem_files, from MAVS
// commit eaaebc2) load with the life forms their keys imply, life stages group, objects and shrubs
// follow their allometry, wood growth ends at the maximum diameter with the carbon balance closed,
// the ground layer reaches its analytic equilibrium, and mobility treats objects as rigid.
#include "support/temp_dir.hpp"

#include "ecoterra/eco/ground_layer.hpp"
#include "ecoterra/eco/growth.hpp"
#include "ecoterra/eco/plant.hpp"
#include "ecoterra/eco/species.hpp"
#include "ecoterra/error.hpp"
#include "ecoterra/mobility/override.hpp"
#include "ecoterra/mobility/smg.hpp"
#include "ecoterra/mobility/stand.hpp"
#include "ecoterra/mobility/vehicle.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <set>
#include <tuple>

using namespace ecoterra;
using namespace ecoterra::eco;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

fs::path mavs_dir() {
    return fs::path(ECOTERRA_TESTS_DIR) / "data/mavs_ecosystem_files";
}

const Species* find(const EcosystemDef& d, const std::string& name) {
    for (const auto& s : d.species)
        if (s.name == name) return &s;
    return nullptr;
}

bool noted(const EcosystemDef& d, const std::string& text) {
    for (const auto& n : d.notes)
        if (n.find(text) != std::string::npos) return true;
    return false;
}

std::map<LifeForm, int> count_forms(const EcosystemDef& d) {
    std::map<LifeForm, int> n;
    for (const auto& s : d.species) ++n[s.life_form];
    return n;
}

json read_json(const fs::path& p) {
    std::ifstream in(p);
    return json::parse(in);
}

} // namespace

TEST_CASE("life forms: MAVS's rule on its keys", "[eco][species][lifeform]") {
    std::string why;
    CHECK(mavs_life_form("urban/roadblock/RoadBlockade_02.obj", 0.9, 0.5, &why) ==
          LifeForm::object);
    CHECK_THAT(why, Catch::Contains("urban"));
    CHECK(mavs_life_form("misc/cube.obj", 6, 0.5) == LifeForm::object);
    CHECK(mavs_life_form("vegetation/Groundcover/GC17_1.obj", 0.02, 0.05) == LifeForm::grass);
    CHECK(mavs_life_form("vegetation/fern/fern_1.obj", 0.45, 2.0) == LifeForm::grass);
    CHECK(mavs_life_form("vegetation/Groundcover/GC08_3.obj", 2.0, 0.05) == LifeForm::grass);
    CHECK(mavs_life_form("vegetation/USA_Southwest/SW11_1.obj", 3.0, 0.5) == LifeForm::shrub);
    CHECK(mavs_life_form("vegetation/USA_Southwest/SW15_1.obj", 1.1, 0.5) == LifeForm::shrub);
    CHECK(mavs_life_form("vegetation/USA_East/EA10y.obj", 4.0, 0.05) == LifeForm::grass);
    CHECK(mavs_life_form("vegetation/USA_East/EA10a.obj", 17, 0.05) == LifeForm::tree);
    // The boundaries: 0.5 m and 5 m belong to the taller class, a ratio of 0.2 to the shrubs.
    CHECK(mavs_life_form("v/a.obj", 0.5, 0.05) == LifeForm::grass);
    CHECK(mavs_life_form("v/a.obj", 0.5, 0.2) == LifeForm::shrub);
    CHECK(mavs_life_form("v/a.obj", 0.4999, 0.2) == LifeForm::grass);
    CHECK(mavs_life_form("v/a.obj", 5.0, 0.5) == LifeForm::tree);
}

TEST_CASE("every MAVS ecosystem file loads with the life forms its keys imply",
          "[eco][species][lifeform][mavs]") {
    int files = 0;
    for (const auto& entry : fs::directory_iterator(mavs_dir())) {
        if (entry.path().extension() != ".json") continue;
        ++files;
        CAPTURE(entry.path().filename().string());
        const EcosystemDef d = load_ecosystem(entry.path());
        REQUIRE_FALSE(d.species.empty());
        std::set<std::string> names;
        for (const auto& s : d.species) {
            CAPTURE(s.name);
            CHECK(names.insert(s.name).second); // names are unique after renaming
            // Each species' form is MAVS's rule on its (possibly grouped) keys.
            CHECK(s.life_form ==
                  mavs_life_form(s.mesh_file, s.max_height_m, s.height_to_diameter_ratio));
            if (s.life_form == LifeForm::tree || s.life_form == LifeForm::shrub)
                CHECK(s.max_stem_diameter_m == Approx(s.max_height_m / 20));
            if (s.life_form == LifeForm::grass) CHECK(s.root_depth_m == Approx(0.4));
        }
        // Every arrival in the file is somewhere in the loaded species (grouping sums them).
        const json raw = read_json(entry.path());
        if (raw.contains("Species")) {
            double in = 0, out = 0;
            for (const auto& e : raw.at("Species")) in += e.at("Num New Per Area").get<double>();
            for (const auto& s : d.species) out += s.new_per_area_per_yr;
            CHECK(out == Approx(in).epsilon(1e-12));
        }
    }
    CHECK(files == 12);

    const auto se = load_ecosystem(mavs_dir() / "american_southeast_forest.json");
    auto n = count_forms(se);
    CHECK(n[LifeForm::tree] == 4);
    CHECK(n[LifeForm::grass] == 9);
    const Species* mag = find(se, "Southern Magnolia");
    REQUIRE(mag);
    CHECK(mag->max_height_m == 17.0);
    CHECK(mag->min_height_m == 2.0);
    CHECK(mag->new_per_area_per_yr == Approx(0.003));
    CHECK(mag->mesh_file == "vegetation/USA_East/EA10a.obj");
    CHECK(find(se, "Southern Magnolia young") == nullptr);
    CHECK(noted(se, "life stages of 'Southern Magnolia' grouped into one species: young"));
    // MAVS names two Bluegrass meshes "Bluegrass 1": the second takes its mesh's name.
    CHECK(find(se, "Bluegrass 1"));
    CHECK(find(se, "Bluegrass 1 (GC14_3)"));

    const auto desert = load_ecosystem(mavs_dir() / "american_southwest_desert.json");
    n = count_forms(desert);
    CHECK(n[LifeForm::tree] == 4); // three saguaros, the 7 m paloverde
    CHECK(n[LifeForm::shrub] == 8);
    CHECK(n[LifeForm::grass] == 0);
    const auto obstacles = load_ecosystem(mavs_dir() / "american_southeast_forest_obstacles.json");
    REQUIRE(find(obstacles, "Roadblock"));
    CHECK(find(obstacles, "Roadblock")->life_form == LifeForm::object);
    CHECK(find(obstacles, "Clover 3")->life_form == LifeForm::grass);
    CHECK(load_ecosystem(mavs_dir() / "cubes_only.json").species[0].life_form == LifeForm::object);
}

TEST_CASE("life stages: grouped by default, kept apart on request, bad values named",
          "[eco][species][lifeform]") {
    json j = read_json(mavs_dir() / "american_southeast_forest.json");
    j["life_stages"] = "separate";
    const auto sep = parse_ecosystem(j, "se.json");
    REQUIRE(find(sep, "Southern Magnolia young"));
    // Kept apart, the 4 m young magnolia is by MAVS's rule a grass, the others trees.
    CHECK(find(sep, "Southern Magnolia young")->life_form == LifeForm::grass);
    CHECK(find(sep, "Southern Magnolia adult")->life_form == LifeForm::tree);
    CHECK(sep.species.size() == 21);
    j["life_stages"] = "merge";
    CHECK_THROWS_WITH(parse_ecosystem(j, "se.json"),
                      Catch::Contains("se.json") && Catch::Contains("'life_stages' = \"merge\""));
    // A stage with a bad value is not grouped: the species reader names it.
    json bad = j;
    bad["life_stages"] = "group";
    bad["Species"][1]["Min Height"] = "two";
    CHECK_THROWS_WITH(parse_ecosystem(bad, "se.json"),
                      Catch::Contains("se.json") && Catch::Contains("'Southern Magnolia medium'") &&
                          Catch::Contains("Min Height"));
    // An entry with its own physiology block is left alone.
    j["life_stages"] = "group";
    j["Species"][0]["physiology"] = {{"life_form", "tree"}};
    const auto part = parse_ecosystem(j, "se.json");
    CHECK(find(part, "Southern Magnolia young"));
    CHECK(find(part, "Southern Magnolia young")->life_form == LifeForm::tree);
    REQUIRE(find(part, "Southern Magnolia"));
    CHECK(find(part, "Southern Magnolia")->new_per_area_per_yr == Approx(0.0015));
}

TEST_CASE("life forms: an explicit form overrides MAVS's rule, a short tree is an error",
          "[eco][species][lifeform]") {
    json j = {{"Species",
               {{{"Mesh File", "v/a.obj"},
                 {"Species Name", "Hazel"},
                 {"Num New Per Area", 0.01},
                 {"Growth Rate", 0.2},
                 {"Max Height", 1.2},
                 {"Min Height", 0.1},
                 {"Mesh Height", 1.0},
                 {"Height To Diameter Ratio", 0.5},
                 {"Max Age", 30},
                 {"Rotate Mesh", false}}}}};
    CHECK(parse_ecosystem(j, "e.json").species[0].life_form == LifeForm::shrub);
    j["Species"][0]["physiology"] = {{"life_form", "tree"}};
    CHECK_THROWS_WITH(parse_ecosystem(j, "e.json"),
                      Catch::Contains("e.json") && Catch::Contains("'Hazel'") &&
                          Catch::Contains("1.3") && Catch::Contains("shrub or grass"));
    j["Species"][0]["physiology"] = {{"life_form", "fungus"}};
    CHECK_THROWS_WITH(parse_ecosystem(j, "e.json"),
                      Catch::Contains("physiology.life_form") && Catch::Contains("fungus"));
    j["Species"][0]["physiology"] = {{"life_form", "grass"}, {"root_depth_m", 0.8}};
    const auto g = parse_ecosystem(j, "e.json").species[0];
    CHECK(g.life_form == LifeForm::grass);
    CHECK(g.root_depth_m == 0.8);
}

TEST_CASE("MAVS random-scene inputs name the ecosystem, Plant Density scales the arrivals",
          "[eco][species][mavs]") {
    // The file as MAVS ships it names a Windows path: the file beside it is read.
    const auto d = load_ecosystem(mavs_dir() / "random_scene_inputs.json");
    const auto se = load_ecosystem(mavs_dir() / "american_southeast_forest.json");
    REQUIRE(d.species.size() == se.species.size());
    CHECK(noted(d, "found by its file name beside the inputs file"));
    CHECK(noted(d, "'Terrain Width'"));
    test::TempDir tmp;
    fs::copy_file(mavs_dir() / "cubes_only.json", tmp.path() / "cubes.json");
    auto write = [&](const json& j) {
        std::ofstream(tmp.path() / "inputs.json") << j.dump();
        return tmp.path() / "inputs.json";
    };
    const auto half =
        load_ecosystem(write({{"Ecosystem File", "cubes.json"}, {"Plant Density", 0.5}}));
    CHECK(half.species[0].new_per_area_per_yr == Approx(0.0025));
    const auto abs_path =
        load_ecosystem(write({{"Ecosystem File", (tmp.path() / "cubes.json").string()}}));
    CHECK(abs_path.species[0].new_per_area_per_yr == Approx(0.005));
    CHECK_THROWS_WITH(load_ecosystem(write({{"Ecosystem File", "nowhere.json"}})),
                      Catch::Contains("inputs.json") && Catch::Contains("'nowhere.json'") &&
                          Catch::Contains("does not exist"));
    CHECK_THROWS_WITH(
        load_ecosystem(write({{"Ecosystem File", "cubes.json"}, {"Plant Density", -1}})),
        Catch::Contains("'Plant Density' = -1"));
    CHECK_THROWS_WITH(load_ecosystem(write({{"Ecosystem File", "inputs.json"}})),
                      Catch::Contains("names another random-scene inputs file"));
}

TEST_CASE("allometry of shrubs and objects", "[eco][growth][lifeform]") {
    Species shrub;
    shrub.life_form = LifeForm::shrub;
    shrub.max_height_m = 3.0;
    shrub.height_dbh_slope_per_cm = 0.3;
    // A shrub's diameter is its stem's at the ground: the height starts at 0, not breast height.
    CHECK(allometry::height_m(shrub, 0.0) == 0.0);
    CHECK(allometry::height_m(shrub, 0.05) == Approx(3.0 * (1 - std::exp(-1.5))));
    for (double d : {0.002, 0.03, 0.15}) {
        const double m = allometry::stem_mass_kg(shrub, d);
        CHECK(allometry::dbh_from_stem_mass(shrub, m, 0.01) == Approx(d).epsilon(1e-10));
    }
    Species cube;
    cube.life_form = LifeForm::object;
    cube.max_height_m = 6.0;
    cube.height_to_diameter_ratio = 0.5;
    Plant p;
    allometry::apply(cube, p);
    CHECK(p.dbh_m == Approx(3.0)); // ratio x Hmax: its footprint
    CHECK(p.height_m == 6.0);
    CHECK(p.crown_radius_m == Approx(1.5));
    CHECK(p.leaf_area_m2 == 0.0);
}

TEST_CASE("wood growth ends at the maximum diameter and the carbon balance stays closed",
          "[eco][growth][lifeform]") {
    Species s;
    s.max_stem_diameter_m = 0.5;
    CHECK(wood_allocation(s, 0.1) == 1.0);
    CHECK(wood_allocation(s, 0.45) == Approx(1.0).margin(1e-12));
    CHECK(wood_allocation(s, 0.475) == Approx(0.5));
    CHECK(wood_allocation(s, 0.5) == 0.0);
    CHECK(wood_allocation(s, 0.7) == 0.0);
    s.max_stem_diameter_m = 0;
    CHECK(wood_allocation(s, 5.0) == 1.0); // no limit
    s.max_stem_diameter_m = 0.5;
    for (double d : {0.2, 0.47, 0.5}) {
        CAPTURE(d);
        Plant p;
        p.dbh_m = d;
        allometry::apply(s, p);
        p.wood_kg = allometry::stem_mass_kg(s, d);
        p.reserve_kg = s.reserve_capacity_kg_per_m2_leaf * p.leaf_area_m2; // full
        const double wood0 = p.wood_kg, reserve0 = p.reserve_kg;
        const auto c = carbon_day(s, p, 1.0, 1.0, 25.0);
        REQUIRE(c.production_kg > c.maintenance_kg);
        // net = reserve + wood + growth respiration + turnover, each as the plant records it.
        CHECK(c.production_kg - c.maintenance_kg ==
              Approx(c.to_reserve_kg + c.to_wood_kg + c.growth_respiration_kg + c.turnover_kg));
        CHECK(p.wood_kg - wood0 == Approx(c.to_wood_kg));
        CHECK(p.reserve_kg - reserve0 == Approx(c.to_reserve_kg));
        CHECK(p.turnover_kg == Approx(c.turnover_kg));
        const double w = wood_allocation(s, d);
        CHECK(c.turnover_kg == Approx((1 - w) * (c.production_kg - c.maintenance_kg)));
        if (d >= 0.5) CHECK(c.to_wood_kg == 0.0);
        if (d <= 0.45) CHECK(c.turnover_kg == 0.0);
    }
    // The turned-over carbon counts as growth: a plant at D_max is not "suppressed".
    Plant p;
    p.dbh_m = 0.5;
    allometry::apply(s, p);
    p.wood_kg = allometry::stem_mass_kg(s, 0.5);
    p.reserve_kg = s.reserve_capacity_kg_per_m2_leaf * p.leaf_area_m2;
    p.mass_at_year_start_kg = p.wood_kg + p.reserve_kg;
    double turned = 0;
    for (int day = 0; day < 100; ++day) turned += carbon_day(s, p, 1.0, 1.0, 25.0).turnover_kg;
    CHECK(update_growth_efficiency(p) == Approx(turned / p.leaf_area_m2));
    CHECK(suppression_mortality(s, p.growth_efficiency) == 0.0);
}

namespace {

Species grass(double r, double max_age, double arrivals) {
    Species g;
    g.life_form = LifeForm::grass;
    g.growth_rate_per_yr = r;
    g.max_age_yr = max_age;
    g.background_mortality_per_yr = 0;
    g.new_per_area_per_yr = arrivals;
    g.germination_probability = 0.5;
    g.germination_min_light = 0.2;
    g.shade = {0.0, 0.35};
    g.water = {1.0, 0.5};
    g.leaf_area_per_crown_area = 2.88;
    g.transpiration_per_leaf_area = 0.35;
    return g;
}

/// Runs the layer of `sp` on one cell for `years` in daily sums applied every `interval` days
/// (the engine's canopy interval; 1: a step a day).
GroundLayer grow(const std::vector<Species>& sp, GroundCell env, double years, int interval = 1) {
    GroundLayer layer(sp, 1, [](std::size_t, std::int64_t) { return 1.0; });
    const std::vector<double> ones(sp.size(), 1.0);
    for (int d = 1; d <= static_cast<int>(years * 365); ++d) {
        layer.accumulate(sp, {env}, 1.0 / 365, ones, ones);
        if (d % interval == 0) layer.apply(sp);
    }
    layer.apply(sp);
    return layer;
}

} // namespace

TEST_CASE("ground layer: cover reaches the logistic equilibrium with arrivals",
          "[eco][ground][lifeform]") {
    for (const auto& [r, age, n] : std::vector<std::tuple<double, double, double>>{
             {2.0, 8.0, 1.0}, {0.5, 15.0, 0.1}, {5.0, 3.0, 3.0}, {0.2, 2.0, 0.1}}) {
        CAPTURE(r, age, n);
        const std::vector<Species> sp = {grass(r, age, n)};
        // da/dt = a (r (1 - a) - mu) + F (1 - a), F = N a0 p_germ: the positive root of
        // -r a^2 + (r - mu - F) a + F = 0.
        const double mu = 1.0 / age, F = n * kArrivalCoverM2 * 0.5;
        const double b = r - mu - F;
        const double expect = (b + std::sqrt(b * b + 4 * r * F)) / (2 * r);
        const auto layer = grow(sp, GroundCell{}, 60);
        CHECK(layer.cover(0, 0) == Approx(expect).epsilon(2e-3));
        CHECK(layer.total(0) <= 1.0);
        // Stepped once a week as the engine does (the free ground held over the week).
        CHECK(grow(sp, GroundCell{}, 60, 7).cover(0, 0) == Approx(expect).epsilon(5e-3));
        CHECK_FALSE(layer.pending());
    }
    // Shade above a species' tolerance lowers its equilibrium; too little light stops arrivals.
    const std::vector<Species> sp = {grass(2.0, 8.0, 1.0)};
    const double open = grow(sp, GroundCell{}, 40).cover(0, 0);
    GroundCell shaded;
    shaded.crown_shade = 0.5;
    const double under = grow(sp, shaded, 40).cover(0, 0);
    CHECK(under < open);
    shaded.crown_shade = 0.9; // light 0.1 < min_light 0.2 (germination), G = exp(-0.81/0.245)
    CHECK(grow(sp, shaded, 40).cover(0, 0) == 0.0);
    GroundCell wet;
    wet.ponded = true;
    CHECK(grow(sp, wet, 10).cover(0, 0) == 0.0);
}

TEST_CASE("ground layer: species share the ground, their cover never exceeds it",
          "[eco][ground][lifeform]") {
    const std::vector<Species> sp = {grass(6.0, 20.0, 3.0), grass(4.0, 20.0, 3.0),
                                     grass(8.0, 50.0, 3.0)};
    GroundLayer layer(sp, 1, [](std::size_t, std::int64_t) { return 1.0; });
    const std::vector<double> ones(3, 1.0);
    for (int d = 0; d < 3650; ++d) {
        layer.step(sp, {GroundCell{}}, 1.0 / 365, ones, ones);
        REQUIRE(layer.total(0) <= 1.0 + 1e-12);
        for (std::size_t g = 0; g < 3; ++g) REQUIRE(layer.cover(g, 0) >= 0.0);
    }
    CHECK(layer.total(0) > 0.9);
    // Full cover of FAO-56's reference grass (LAI 2.88) transpires ET0: tau LAI = 1.008.
    const std::vector<Species> one = {grass(20.0, 1000.0, 3.0)};
    const auto full = grow(one, GroundCell{}, 20);
    REQUIRE(full.cover(0, 0) > 0.99);
    const double et0 = 0.005, area = 4.0;
    CHECK(full.demand_m3(one, 0, {1.0}, et0, area) ==
          Approx(0.35 * 2.88 * full.cover(0, 0) * area * et0));
    CHECK(full.demand_m3(one, 0, {1.0}, et0, area) / (area * et0) == Approx(1.0).epsilon(0.01));
    CHECK(full.transmission(one, 0, 0.5) == Approx(std::exp(-0.5 * 2.88 * full.cover(0, 0))));
    CHECK(full.root_depth_m(one, 0) == Approx(0.4));
}

TEST_CASE("mobility: an object is avoided where a tree of its diameter is pushed over",
          "[mobility][smg][lifeform]") {
    using namespace ecoterra::mobility;
    const Vehicle v = load_vehicle(test::data_dir() / "vehicles/mrzr4.json");
    auto drive = [&](std::vector<Stem> stems) {
        return drive_line(v, StemIndex(stems, 2.0), nullptr, {0, 0}, {100, 0});
    };
    Stem thin{50, 0, 0.04};
    REQUIRE(0.04 < critical_diameter_m(v.weight_n(), v.push_height_m));
    const auto pushed = drive({thin});
    CHECK(pushed.overridden == 1);
    CHECK(pushed.avoided == 0);
    CHECK(pushed.path_m == Approx(100));
    thin.rigid = true;
    const auto around = drive({thin});
    CHECK(around.overridden == 0);
    CHECK(around.avoided == 1);
    CHECK(around.path_m > 100);
    // A shrub's stem tapers from its base: half its height up, half its base diameter.
    CHECK(diameter_at_height_from_base_m(0.2, 3.0, 1.5) == Approx(0.1));
    CHECK(diameter_at_height_from_base_m(0.2, 3.0, 0.0) == Approx(0.2));
    CHECK(diameter_at_height_from_base_m(0.2, 3.0, 3.5) == 0.0);
}

TEST_CASE("stem lists: life_form and stem_diameter_cm are read, bad values named",
          "[mobility][lifeform][errors]") {
    using namespace ecoterra::mobility;
    test::TempDir dir;
    auto write = [&](const std::string& text) {
        std::ofstream(dir / "stems.csv") << text;
        return dir / "stems.csv";
    };
    const auto stems = read_stem_csv(write("x_m,y_m,life_form,dbh_cm,stem_diameter_cm,height_m\n"
                                           "1,2,tree,30,30,20\n"
                                           "3,4,shrub,0,8,3\n"
                                           "5,6,object,0,50,0.9\n"));
    REQUIRE(stems.size() == 3);
    CHECK(stems[0].kind == StemKind::tree);
    CHECK(stems[0].dbh_m == Approx(0.3));
    CHECK(stems[1].kind == StemKind::shrub);
    CHECK(stems[1].base_diameter_m == Approx(0.08));
    CHECK(stems[1].dbh_m == 0.0);
    CHECK(stems[2].kind == StemKind::object);
    CHECK(stems[2].base_diameter_m == Approx(0.5));
    // Without life_form every row is a tree (lists made before life forms, field lists).
    const auto old = read_stem_csv(write("x_m,y_m,dbh_cm\n1,2,30\n"));
    CHECK(old[0].kind == StemKind::tree);
    CHECK_THROWS_WITH(read_stem_csv(write("x_m,y_m,life_form,dbh_cm,stem_diameter_cm\n"
                                          "1,2,bush,0,8\n")),
                      Catch::Contains("stems.csv") && Catch::Contains("life_form = 'bush'") &&
                          Catch::Contains("tree, shrub or object"));
    CHECK_THROWS_WITH(read_stem_csv(write("x_m,y_m,life_form,dbh_cm\n1,2,tree,30\n")),
                      Catch::Contains("needs a stem_diameter_cm column"));
    CHECK_THROWS_WITH(read_stem_csv(write("x_m,y_m,life_form,dbh_cm,stem_diameter_cm\n"
                                          "1,2,shrub,0,-3\n")),
                      Catch::Contains("stem_diameter_cm"));
}

TEST_CASE("species files: the sapwood respiration takes paper 002's coefficient unless given",
          "[eco][species]") {
    json j = read_json(mavs_dir() / "american_southeast_forest.json");
    j["Species"][0]["physiology"]["respiration_kg_per_m2_leaf_per_m_per_yr"] = 0.021;
    j["Species"][1]["physiology"]["respiration_kg_per_m2_leaf_per_m_per_yr"] = 0.021;
    j["Species"][1]["physiology"]["sapwood_respiration_kg_per_m2_leaf_per_m_per_yr"] = 0.004;
    const auto d = parse_ecosystem(j, "se.json");
    CHECK(d.species[0].sapwood_respiration_kg_per_m2_leaf_per_m_per_yr == 0.021);
    CHECK(d.species[1].sapwood_respiration_kg_per_m2_leaf_per_m_per_yr == 0.004);
    CHECK(d.species[1].respiration_kg_per_m2_leaf_per_m_per_yr == 0.021);
}
