// Manifest expansion: members as pure functions of (manifest, index).
#include "ecoterra/analyses/analyses.hpp"
#include "ecoterra/ensemble/manifest.hpp"
#include "ecoterra/ensemble/member.hpp"
#include "ecoterra/ensemble/summary.hpp"
#include "ecoterra/error.hpp"
#include "ecoterra/io/atomic_file.hpp"
#include "support/temp_dir.hpp"

#include <catch2/catch.hpp>

#include <fstream>
#include <set>

using namespace ecoterra;
using namespace ecoterra::ensemble;
using nlohmann::json;

namespace {

/// A manifest over a copy of the quickstart scene and its ecosystem, in `dir`.
std::filesystem::path write_manifest(const test::TempDir& dir, const json& extra) {
    namespace fs = std::filesystem;
    fs::create_directories(dir / "scenes");
    fs::create_directories(dir / "ecosystems");
    fs::copy_file(test::data_dir() / "scenes/quickstart.json", dir / "scenes/quickstart.json");
    fs::copy_file(test::data_dir() / "ecosystems/humid_subtropical_broadleaf.json",
                  dir / "ecosystems/humid_subtropical_broadleaf.json");
    json m = {{"name", "unit"},
              {"base", {{"run", "scenes/quickstart.json"}}},
              {"seed", 11},
              {"replicates", 3},
              {"axes",
               {{{"key", "vegetation.competition"}, {"values", {"coupled", "light_only"}}},
                {{"key", "simulation.years"}, {"values", {5, 10, 20}}}}}};
    m.update(extra);
    const auto p = dir / "m.json";
    io::write_text_atomic(p, m.dump());
    return p;
}

} // namespace

TEST_CASE("ensemble members: index order, axis values and seeds", "[ensemble]") {
    test::TempDir dir;
    const Manifest m = load_manifest(write_manifest(dir, json::object()));
    REQUIRE(m.combinations() == 6);
    REQUIRE(m.members() == 18);
    std::set<std::string> hashes;
    for (std::size_t i = 0; i < m.members(); ++i) {
        const Member a = make_member(m, i);
        // Replicates innermost, the first axis slowest.
        CHECK(a.replicate == static_cast<int>(i % 3));
        CHECK(a.combination == i / 3);
        CHECK(a.axes[0].second == m.axes[0].values[(i / 9) % 2]);
        CHECK(a.axes[1].second == m.axes[1].values[(i / 3) % 3]);
        CHECK(a.scene["vegetation"]["competition"] == a.axes[0].second);
        CHECK(a.scene["simulation"]["years"] == a.axes[1].second);
        // The seed is that of its replicate, shared across combinations (common random numbers),
        // different between replicates, below 2^53, and written into the scene.
        CHECK(a.seed == derive_seed(11, "member", static_cast<std::uint64_t>(a.replicate)));
        CHECK(a.seed < (1ULL << 53));
        CHECK(a.scene["simulation"]["seed"].get<std::uint64_t>() == a.seed);
        CHECK(a.scene["terrain"]["generate"]["seed"].get<std::uint64_t>() ==
              derive_seed(a.seed, "terrain", 0));
        // A pure function: built again, the same member.
        const Member b = make_member(m, i);
        CHECK(b.input_hash == a.input_hash);
        CHECK(b.scene == a.scene);
        hashes.insert(a.input_hash);
    }
    CHECK(hashes.size() == m.members());
    CHECK(make_member(m, 0).seed != make_member(m, 1).seed);
    CHECK_THROWS_WITH(make_member(m, 18), Catch::Contains("member 18 is out of range") &&
                                              Catch::Contains("members 0 to 17"));
}

TEST_CASE("ensemble members: per-member seeds and seeds the manifest sets", "[ensemble]") {
    test::TempDir dir;
    const Manifest per = load_manifest(write_manifest(dir, {{"seeds", "per_member"}}));
    std::set<std::uint64_t> seeds;
    for (std::size_t i = 0; i < per.members(); ++i) seeds.insert(make_member(per, i).seed);
    CHECK(seeds.size() == per.members());

    test::TempDir dir2;
    const Manifest fixed =
        load_manifest(write_manifest(dir2, {{"set", {{"terrain.generate.seed", 5}}}}));
    for (std::size_t i = 0; i < fixed.members(); ++i) {
        const Member mb = make_member(fixed, i);
        CHECK(mb.scene["terrain"]["generate"]["seed"] == 5);
        CHECK(mb.seeds["terrain.generate.seed"] == 5);
    }
}

TEST_CASE("ensemble members: the input hash follows the files a member reads", "[ensemble]") {
    test::TempDir dir;
    const auto file = write_manifest(dir, json::object());
    const std::string before = make_member(load_manifest(file), 4).input_hash;
    CHECK(make_member(load_manifest(file), 4).input_hash == before);
    // An edited ecosystem file changes every member's inputs.
    std::ofstream(dir / "ecosystems/humid_subtropical_broadleaf.json", std::ios::app) << "\n ";
    CHECK(make_member(load_manifest(file), 4).input_hash != before);
}

TEST_CASE("ensemble manifests: bad input names the file, the key and the value", "[ensemble]") {
    struct Case {
        json extra;
        std::vector<std::string> says;
    };
    const std::vector<Case> cases{
        {{{"replicate", 3}}, {"m.json", "unknown key 'replicate'", "did you mean 'replicates'"}},
        {{{"replicates", 0}}, {"m.json", "replicates = 0 is outside [1,"}},
        {{{"axes", {{{"key", "vegetation.competiton"}, {"values", {"coupled"}}}}}},
         {"m.json", "axes[0].key = 'vegetation.competiton'",
          "did you mean 'vegetation.competition'"}},
        {{{"axes", {{{"key", "vegetation.competition"}, {"values", json::array()}}}}},
         {"m.json", "axes[0] (vegetation.competition): values is empty"}},
        {{{"set", {{"simulation.yeers", 3}}}}, {"set key = 'simulation.yeers'"}},
        {{{"analyses", {{"mobility", {{"lines", 10}}}}}},
         {"analyses.mobility: missing key 'vehicle'"}},
        {{{"analyses", {{"traverse", {{"vehicle", "v.json"}, {"mission", 3}}}}}},
         {"unknown key 'analyses.traverse.mission'"}},
        {{{"base", {{"forest", "scenes/quickstart.json"}}}},
         {"base.forest", "run, terrain or mobility"}},
        {{{"base", {{"run", "scenes/missing.json"}}}}, {"missing.json"}},
        {{{"name", "a b"}}, {"name 'a b'"}},
        {{{"pictures",
           json::array({json{{"name", "p"}, {"x", "simulation.seed"}, {"y", "stand.stems"}}})}},
         {"pictures[0].x = 'simulation.seed' is not an axis"}},
    };
    for (const auto& c : cases) {
        test::TempDir dir;
        const auto file = write_manifest(dir, c.extra);
        INFO(c.extra.dump());
        try {
            load_manifest(file);
            FAIL("no error");
        } catch (const InputError& e) {
            for (const auto& s : c.says) CHECK_THAT(e.what(), Catch::Contains(s));
        }
    }
}

TEST_CASE("ensemble summaries: index ranges and units", "[ensemble]") {
    CHECK(index_ranges({}) == "");
    CHECK(index_ranges({3}) == "3");
    CHECK(index_ranges({0, 1, 2, 4, 7, 8}) == "0-2,4,7-8");
    CHECK(unit_of("mobility.smg_mean_m_per_s") == "m/s");
    CHECK(unit_of("traverse.median_rms_vertical_acceleration_m_per_s2") == "m/s2");
    CHECK(unit_of("stand.basal_area_m2_per_ha") == "m2/ha");
    CHECK(unit_of("stand.stems_per_ha") == "1/ha");
    CHECK(unit_of("terrain.low_pct") == "%");
    CHECK(unit_of("mobility.nogo_fraction") == "1");
    // From the catalogues, not from the name: an aggregate's statistics keep the metric's unit,
    // scene keys of axes have the scene catalogue's, the tables' own columns theirs.
    CHECK(unit_of("mobility.smg_mean_m_per_s.p90") == "m/s");
    CHECK(unit_of("stand.reineke_sdi_per_ha.mean") == "1/ha");
    CHECK(unit_of("run.years") == "yr");
    CHECK(unit_of("hydrology.root_zone_depth_m") == "m");
    CHECK(unit_of("terrain.generate.params.d_high") == "1");
    CHECK(unit_of("seconds") == "s");
    CHECK(unit_of("not.a.column") == "");
    // Every metric has a unit, and a name unique within its analysis.
    std::set<std::string> names;
    for (const auto& m : analyses::describe_metrics()) {
        CAPTURE(m.name);
        CHECK_FALSE(m.unit.empty());
        CHECK(names.insert(m.name).second);
    }
}

TEST_CASE("ensemble analyses: options are read through their catalogues at load, naming the key",
          "[ensemble][analyses]") {
    const auto e = analyses::export_catalog().read(
        nlohmann::json{{"formats", {"gltf", "mavs"}}, {"layers", true}}, {});
    CHECK(e.formats == std::vector<std::string>{"gltf", "mavs"});
    CHECK(e.layers);
    for (const auto& [bad, says] : std::vector<std::pair<nlohmann::json, std::string>>{
             {{{"formats", "gltf"}}, "analyses.export.formats must be an array"},
             {{{"formats", {"gltf", 3}}}, "3 is not a name"},
             {{{"formats", {"obj"}}}, "'obj' is not one of mavs, gazebo, unreal, gltf"},
             {{{"formats", {"gltf", "gltf"}}}, "'gltf' is given twice"},
             {{{"layers", "yes"}}, "analyses.export.layers"}}) {
        CAPTURE(bad.dump());
        CHECK_THROWS_WITH(analyses::export_catalog().read(bad, {}), Catch::Contains(says));
    }
    CHECK_THROWS_WITH(
        analyses::mobility_catalog().read(nlohmann::json{{"vehicle", "v.json"}, {"lines", 0}}, {}),
        Catch::Contains("analyses.mobility.lines"));
    CHECK_THROWS_WITH(analyses::traverse_catalog().read(
                          nlohmann::json{{"vehicle", "v.json"}, {"speed_m_per_s", -1}}, {}),
                      Catch::Contains("analyses.traverse.speed_m_per_s"));
}
