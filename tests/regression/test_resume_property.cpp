// Resume as a property: a run split at every checkpoint and resumed ends in exactly the state of
// the run that was never split. The checkpoint holds the whole state (plants, soil water,
// catchments, groundwater, generators, the daily and yearly series), so equal checkpoint bytes
// at the end mean every dataset and series is equal bit for bit. The quickstart scene and a
// groundwater scene; splits at every year end.
#include "support/scenes.hpp"
#include "support/temp_dir.hpp"

#include "ecoterra/archive.hpp"
#include "ecoterra/eco/ecosystem.hpp"
#include "ecoterra/eco/scene_config.hpp"
#include "ecoterra/parallel.hpp"
#include "ecoterra/run/run.hpp"
#include "ecoterra/run/run_reader.hpp"

#include <catch2/catch.hpp>

#include <algorithm>

#include <cstring>
#include <fstream>
#include <functional>
#include <iterator>
#include <memory>
#include <omp.h>

using namespace ecoterra;
using nlohmann::json;

namespace {

/// The shipped quickstart scene's JSON, for a test to change.
json quickstart_json() {
    std::ifstream f(test::data_dir() / "scenes/quickstart.json");
    return json::parse(f);
}

/// The quickstart scene on a terrain of `size` x `size` cells.
eco::EcoScene quickstart_scene(int size) {
    json j = quickstart_json();
    j["terrain"]["generate"]["size"] = size;
    return eco::load_eco_scene(j, test::data_dir() / "scenes");
}

std::vector<std::uint8_t> checkpoint(const eco::Ecosystem& e) {
    ArchiveWriter a;
    e.save_state(a);
    return a.bytes();
}

/// Index of the first differing byte, or -1.
std::int64_t first_difference(const std::vector<std::uint8_t>& a,
                              const std::vector<std::uint8_t>& b) {
    const std::size_t n = std::min(a.size(), b.size());
    for (std::size_t k = 0; k < n; ++k)
        if (a[k] != b[k]) return static_cast<std::int64_t>(k);
    return a.size() == b.size() ? -1 : static_cast<std::int64_t>(n);
}

/// The checkpoint up to its diagnosis section (the last; a format-6 checkpoint has none, so a run
/// resumed from one counts its diagnosis from the resume on).
std::vector<std::uint8_t> before_diagnosis(std::vector<std::uint8_t> b) {
    const std::string name = "diagnosis";
    const auto at = std::search(b.begin(), b.end(), name.begin(), name.end());
    REQUIRE(at != b.end());
    b.erase(at, b.end());
    return b;
}

/// The checkpoint with the critical layer's water (the hydrology's last raster before the
/// vegetation density; a format-6 checkpoint has none and starts it as the root zone's) zeroed:
/// its bytes are the last place in the checkpoint that holds the engine's critical layer.
std::vector<std::uint8_t> without_critical_layer(std::vector<std::uint8_t> b,
                                                 const eco::Ecosystem& e) {
    const RasterD& top = e.hydrology().critical_layer_moisture();
    const auto* p = reinterpret_cast<const std::uint8_t*>(top.data());
    const auto n = static_cast<std::size_t>(top.size()) * sizeof(double);
    const auto at = std::find_end(b.begin(), b.end(), p, p + n);
    REQUIRE(at != b.end());
    std::fill(at, at + static_cast<std::ptrdiff_t>(n), std::uint8_t{0});
    return b;
}

/// Names the first part of the state that differs between two engines (for the failure message).
std::string first_different_part(const eco::Ecosystem& a, const eco::Ecosystem& b) {
    if (a.days_done() != b.days_done()) return "days done";
    const auto& ha = a.hydrology();
    const auto& hb = b.hydrology();
    const auto same_raster = [](const RasterD& x, const RasterD& y) {
        return x.size() == y.size() &&
               std::memcmp(x.data(), y.data(), static_cast<std::size_t>(x.size()) * 8) == 0;
    };
    for (std::size_t c = 0; c < a.daily().columns.size(); ++c)
        for (std::size_t d = 0; d < a.daily().columns[c].size(); ++d)
            if (std::memcmp(&a.daily().columns[c][d], &b.daily().columns[c][d], 8) != 0)
                return "daily series '" + a.daily().names[c] + "' from row " + std::to_string(d);
    if (!same_raster(ha.soil_moisture(), hb.soil_moisture())) return "soil moisture";
    if (ha.catchments().catchments().size() != hb.catchments().catchments().size())
        return "catchment count";
    if (a.plants().size() != b.plants().size()) return "plant count";
    if (!a.plants().bitwise_equal(b.plants())) return "a plant column";
    const auto& da = a.dead_wood().pieces();
    const auto& db = b.dead_wood().pieces();
    if (da.size() != db.size()) return "dead-wood piece count";
    if (std::memcmp(da.data(), db.data(), da.size() * sizeof(eco::DeadStem)) != 0)
        return "a snag or log";
    return "a part not compared here";
}

/// Runs `years` unsplit, keeping the checkpoint at each year end, then resumes from each kept
/// checkpoint (every `every` years) to the end and compares the final checkpoints. Returns the
/// number of snags and logs at the end (the tests that need dead wood in the state require some).
std::size_t check_every_split(const eco::EcoScene& scene, int years, int every) {
    std::vector<std::vector<std::uint8_t>> kept;
    std::vector<std::uint8_t> final_state;
    eco::Ecosystem e(scene);
    {
        for (int y = 1; y <= years; ++y) {
            e.run_year();
            kept.push_back(y % every == 0 && y < years ? checkpoint(e)
                                                       : std::vector<std::uint8_t>{});
        }
        final_state = checkpoint(e);
        // Two checkpoints of one state are the same bytes (no uninitialised padding).
        const bool same = checkpoint(e) == final_state;
        CHECK(same);
    }
    for (int split = every; split < years; split += every) {
        CAPTURE(split, years);
        eco::Ecosystem r(scene);
        const auto& bytes = kept[static_cast<std::size_t>(split - 1)];
        ArchiveReader in(bytes.data(), bytes.size(), "checkpoint");
        r.load_state(in);
        // Loading and saving again gives the checkpoint back.
        const std::int64_t reload = first_difference(checkpoint(r), bytes);
        REQUIRE(reload == -1);
        for (int y = split; y < years; ++y) r.run_year();
        const auto end = checkpoint(r);
        const std::int64_t at = first_difference(end, final_state);
        if (at != -1) {
            // The first day the split run leaves the unsplit one.
            INFO("first difference: " << first_different_part(r, e));
            CHECK(at == -1);
        }
    }
    return e.dead_wood().pieces().size();
}

} // namespace

TEST_CASE("resume: the quickstart split at every snapshot ends bit for bit as one run",
          "[eco][resume][property][slow]") {
    json j = quickstart_json();
    j["simulation"]["years"] = 30;
    const auto scene = eco::load_eco_scene(j, test::data_dir() / "scenes");
    CHECK(check_every_split(scene, 30, 5) > 0);
}

TEST_CASE("resume: a groundwater scene split at every year ends bit for bit as one run",
          "[eco][resume][property][slow]") {
    json j = quickstart_json();
    j["terrain"]["generate"]["size"] = 24;
    j["hydrology"]["groundwater"] = true;
    // On the terrain's cells and on aquifer cells of 3 x 3 terrain cells.
    const int factor = GENERATE(1, 3);
    CAPTURE(factor);
    j["hydrology"]["aquifer_cell_factor"] = factor;
    j["simulation"]["years"] = 6;
    j["vegetation"]["initial"] = {{"random", {{"stems_per_ha", 600}, {"max_dbh_m", 0.3}}}};
    // A thinning and a selection cut (stumps and slash, the felling directions' draws).
    j["vegetation"]["management"] = {
        {"operations",
         {{{"year", 3}, {"type", "thin_from_below"}, {"target_basal_area_m2_per_ha", 4}},
          {{"year", 5}, {"type", "selection"}, {"min_dbh_m", 0.2}}}}};
    const auto scene = eco::load_eco_scene(j, test::data_dir() / "scenes");
    CHECK(check_every_split(scene, 6, 1) > 0);
}

TEST_CASE("resume: undergrowth and MAVS objects split at every year end bit for bit as one run",
          "[eco][resume][property][lifeform][slow]") {
    // Shrubs, a ground layer of two species (its cover is in the checkpoint) and, from MAVS's
    // forest_with_cubes.json, objects and grouped life stages.
    for (const std::string& eco :
         {(test::data_dir() / "ecosystems/humid_subtropical_broadleaf_undergrowth.json").string(),
          std::string(ECOTERRA_TESTS_DIR) + "/data/mavs_ecosystem_files/forest_with_cubes.json"}) {
        CAPTURE(eco);
        json j = quickstart_json();
        j["terrain"]["generate"]["size"] = 24;
        j["vegetation"]["ecosystem"] = eco;
        j["vegetation"]["initial"] = {{"random", {{"stems_per_ha", 600}, {"max_dbh_m", 0.1}}}};
        j["simulation"]["years"] = 8;
        const auto scene = eco::load_eco_scene(j, test::data_dir() / "scenes");
        check_every_split(scene, 8, 1);
    }
}

TEST_CASE("resume: storms that fell trees, a thinning between them, split at every year end "
          "bit for bit as one run",
          "[eco][resume][property][windthrow]") {
    // Windthrow's state (the storm stream, the last thinning for the turning-moment ratio) and
    // its pieces (logs downwind, root plates, snapped snags falling later), in both modes; the
    // drawn storms of a windy climate and severe storms every third year as well as the listed
    // ones.
    for (const std::string mode : {"coupled", "light_only"}) {
        CAPTURE(mode);
        auto j = test::small_scene(8, mode);
        j["vegetation"]["windthrow"] = {{"weibull_scale_m_per_s", 6.0},
                                        {"severe_return_period_yr", 3.0},
                                        {"storms",
                                         {{{"year", 3}, {"wind_m_per_s", 24}, {"from_deg", 90}},
                                          {{"year", 6}, {"wind_m_per_s", 28}}}}};
        j["vegetation"]["management"] = {
            {"operations",
             {{{"year", 4}, {"type", "thin_from_below"}, {"target_basal_area_m2_per_ha", 3}}}}};
        const auto scene = eco::load_eco_scene(j, test::data_dir() / "scenes");
        eco::Ecosystem probe(scene);
        double felled = 0;
        for (int y = 1; y <= 8; ++y) {
            probe.run_year();
            felled += probe.yearly().column("windthrow_uprooted").back() +
                      probe.yearly().column("windthrow_broken").back();
        }
        REQUIRE(felled > 0);
        CHECK(check_every_split(scene, 8, 1) > 0);
    }
}

TEST_CASE("threads: the ground layer and shrubs give the same bytes on 1 and 3 threads",
          "[eco][determinism][property][lifeform]") {
    std::ifstream f(test::data_dir() / "scenes/quickstart_undergrowth.json");
    json j = json::parse(f);
    j["terrain"]["generate"]["size"] = 24;
    j["vegetation"]["initial"] = {{"random", {{"stems_per_ha", 800}, {"max_dbh_m", 0.1}}}};
    const auto scene = eco::load_eco_scene(j, test::data_dir() / "scenes");
    const int saved = omp_get_max_threads();
    set_parallel_min_items(1);
    std::vector<std::uint8_t> bytes[2];
    int k = 0;
    for (const int threads : {1, 3}) {
        omp_set_num_threads(threads);
        eco::Ecosystem e(scene);
        for (int y = 0; y < 3; ++y) e.run_year();
        REQUIRE(e.undergrowth().ground_cover_fraction > 0.0);
        bytes[k++] = checkpoint(e);
    }
    CHECK(first_difference(bytes[0], bytes[1]) == -1);
    omp_set_num_threads(saved);
    set_parallel_min_items(kMinParallelItems);
}

TEST_CASE("threads: a run gives the same bytes on 1, 2, 3 and 7 threads",
          "[eco][determinism][property][slow]") {
    // Every loop goes parallel whatever its size (set_parallel_min_items(1)), so the threads
    // really share the plants, the root cells and the cell sums of a small scene; with
    // groundwater. 2 threads check an even split, 3 and 7 uneven ones, 7 more threads than CI's
    // two cores: those run every small parallel loop slowly (a sleeping thread is woken for each),
    // so 7 threads run the first year only (4 threads, dropped, and 7 for two years took over two
    // minutes of CI).
    json j = quickstart_json();
    j["terrain"]["generate"]["size"] = 32;
    j["hydrology"]["groundwater"] = true;
    const int factor = GENERATE(1, 4); // the aquifer on the terrain's cells, and on 4 x 4 of them
    CAPTURE(factor);
    j["hydrology"]["aquifer_cell_factor"] = factor;
    j["simulation"]["years"] = 2;
    j["vegetation"]["initial"] = {{"random", {{"stems_per_ha", 800}, {"max_dbh_m", 0.3}}}};
    const auto scene = eco::load_eco_scene(j, test::data_dir() / "scenes");
    const int saved = omp_get_max_threads();
    set_parallel_min_items(1);
    std::vector<std::uint8_t> one, one_year;
    std::unique_ptr<eco::Ecosystem> first, first_year;
    // (The coarser aquifer's few loops of its own are checked on 1 and 3 threads.)
    for (const int threads : {1, 2, 3, 7}) {
        if (factor > 1 && threads != 1 && threads != 3) continue;
        CAPTURE(threads);
        omp_set_num_threads(threads);
        const int years = threads == 7 ? 1 : 2;
        auto e = std::make_unique<eco::Ecosystem>(scene);
        e->run_year();
        if (threads == 1) {
            one_year = checkpoint(*e);
            first_year = std::make_unique<eco::Ecosystem>(scene);
            first_year->run_year();
        }
        if (years == 2) e->run_year();
        const auto bytes = checkpoint(*e);
        if (threads == 1) {
            one = bytes;
            first = std::move(e);
            REQUIRE(first->plants().size() > 100);
            continue;
        }
        const auto& ref = years == 2 ? *first : *first_year;
        const std::int64_t at = first_difference(bytes, years == 2 ? one : one_year);
        INFO("first difference: " << (at == -1 ? "none" : first_different_part(*e, ref)));
        CHECK(at == -1);
    }
    omp_set_num_threads(saved);
    set_parallel_min_items(kMinParallelItems);
}

TEST_CASE("resume: a checkpoint that does not fit the engine is a CheckpointError, bad input",
          "[eco][resume][errors]") {
    json j = quickstart_json();
    const auto scene = eco::load_eco_scene(j, test::data_dir() / "scenes");
    eco::Ecosystem e(scene);
    const auto bytes = checkpoint(e);
    const auto load = [](const eco::EcoScene& sc, const std::vector<std::uint8_t>& b) {
        eco::Ecosystem r(sc);
        ArchiveReader in(b.data(), b.size(), "run.h5");
        r.load_state(in);
    };
    // Every mismatch is the same class, and that class is bad input (exit code 2).
    std::vector<std::uint8_t> truncated(bytes.begin(), bytes.begin() + bytes.size() / 2);
    CHECK_THROWS_AS(load(scene, truncated), CheckpointError);
    std::vector<std::uint8_t> other = bytes;
    other[0] ^= 0xff;
    CHECK_THROWS_WITH(load(scene, other), Catch::Contains("not an ecoterra ecosystem checkpoint"));
    json k = j;
    k["hydrology"]["groundwater"] = true;
    const auto gw = eco::load_eco_scene(k, test::data_dir() / "scenes");
    CHECK_THROWS_WITH(load(gw, bytes), Catch::Contains("groundwater is off in the checkpoint"));
    CHECK_THROWS_AS(load(gw, bytes), InputError);
    CHECK_NOTHROW(load(scene, bytes));
    // with_context keeps the class and puts what was being done first.
    CHECK_THROWS_WITH(with_context("resuming run.h5", [&] { load(gw, bytes); }),
                      Catch::StartsWith("resuming run.h5: hydrology checkpoint"));
    CHECK_THROWS_AS(with_context("x", [&] { load(gw, bytes); }), CheckpointError);
}

TEST_CASE("resume: a checkpoint of format 6 (before sections) resumes into the same state",
          "[eco][resume][checkpoint]") {
    // tests/data/checkpoints/quickstart_v6_year1.bin: /checkpoint/state of
    //   ecoterra run data/scenes/quickstart.json --years 1 --set terrain.generate.size=12
    //     --set 'vegetation.initial={"random":{"stems_per_ha":3000}}'
    // made by ecoterra at commit 4655e5c (format 6), built by GCC 12 in Release. Read today, it
    // must save and load again unchanged, and resume without a broken budget; in a GCC build it
    // must also be, bit for bit, the year-1 state of today's engine and, resumed for two years,
    // end where a run of three years ends. (A clang build rounds some of the year's arithmetic
    // differently in the last bit, so there the comparison is of the stand, to 1e-9.)
    json j = quickstart_json();
    j["terrain"]["generate"]["size"] = 12;
    j["vegetation"]["initial"] = {{"random", {{"stems_per_ha", 3000}}}};
    j["simulation"]["years"] = 1;
    // The fixture was made with paper 002's soil water, as every run was then.
    j["hydrology"]["evapotranspiration"] = "paper002";
    j["hydrology"]["drainage"] = "none";
    j["hydrology"]["interception"] = "none";
    // ... and without dead wood: the trees that died then left nothing.
    j["vegetation"]["deadwood"]["enabled"] = false;
    // ... and without storms (the stream had not begun).
    j["vegetation"]["windthrow"]["enabled"] = false;
    // ... and with the plants in birth order (the only order then).
    j["vegetation"]["plant_order"] = "birth";
    // ... and with the canopy refreshed weekly (the default then).
    j["vegetation"]["canopy_interval_days"] = 7;
    // ... and with paper 002's growth and shading and the species values of then (a copy of the
    // ecosystem file as it was before the forest calibration of issue 27).
    j["vegetation"]["growth"] = "paper002";
    j["vegetation"]["shading"] = "blocking";
    j["vegetation"]["ecosystem"] =
        std::string(ECOTERRA_TESTS_DIR) + "/data/checkpoints/humid_subtropical_broadleaf_v6.json";
    const auto scene = eco::load_eco_scene(j, test::data_dir() / "scenes");
    std::ifstream in(std::string(ECOTERRA_TESTS_DIR) + "/data/checkpoints/quickstart_v6_year1.bin",
                     std::ios::binary);
    const std::vector<std::uint8_t> v6((std::istreambuf_iterator<char>(in)), {});
    REQUIRE(v6.size() > 1000);
    eco::Ecosystem straight(scene);
    straight.run_year();
    eco::Ecosystem resumed(scene);
    ArchiveReader r(v6.data(), v6.size(), "format-6 checkpoint");
    resumed.load_state(r);
    CHECK(r.at_end());
    const auto saved = checkpoint(resumed);
    eco::Ecosystem again(scene);
    ArchiveReader r2(saved.data(), saved.size(), "format-7 checkpoint");
    again.load_state(r2);
    CHECK(first_difference(checkpoint(again), saved) == -1);
#if defined(__GNUC__) && !defined(__clang__)
    constexpr bool kFixtureCompiler = true;
#else
    constexpr bool kFixtureCompiler = false;
#endif
    // The year-1 state read from format 6 is the year-1 state of today's engine, but for the
    // critical layer, which format 6 lacks (it starts as the root zone's water, and only the
    // soil strength reads it).
    if (kFixtureCompiler)
        CHECK(first_difference(
                  without_critical_layer(before_diagnosis(saved), resumed),
                  without_critical_layer(before_diagnosis(checkpoint(straight)), straight)) == -1);
    for (int y = 0; y < 2; ++y) straight.run_year(), resumed.run_year();
    if (kFixtureCompiler)
        CHECK(first_difference(
                  without_critical_layer(before_diagnosis(checkpoint(resumed)), resumed),
                  without_critical_layer(before_diagnosis(checkpoint(straight)), straight)) == -1);
    CHECK(resumed.stand().basal_area_m2_per_ha ==
          Approx(straight.stand().basal_area_m2_per_ha).epsilon(1e-9));
    CHECK(resumed.plants().size() == straight.plants().size());
    CHECK(resumed.plants().size() > 10);
}

TEST_CASE("resume: checkpoint sections are checked one by one, naming the section",
          "[eco][resume][checkpoint]") {
    const auto scene = quickstart_scene(12);
    eco::Ecosystem e(scene);
    e.run_year();
    const auto bytes = checkpoint(e);
    // Rewrites the sections after the magic and container version through `edit(name, version,
    // bytes)`, which may change the version or the bytes, or drop the section (returns false).
    auto rewrite = [&](auto edit) {
        ArchiveReader in(bytes.data(), bytes.size(), "t");
        ArchiveWriter out;
        out.put(in.get<std::uint32_t>());
        out.put(in.get<std::uint32_t>());
        while (!in.at_end()) {
            std::string name = in.get_string();
            auto version = in.get<std::uint32_t>();
            auto part = in.get_vector<std::uint8_t>();
            if (!edit(name, version, part)) continue;
            out.put_string(name);
            out.put(version);
            out.put_vector(part);
        }
        return out.bytes();
    };
    auto load = [&](const std::vector<std::uint8_t>& b) {
        eco::Ecosystem r(scene);
        ArchiveReader in(b.data(), b.size(), "t");
        r.load_state(in);
    };
    // Unchanged sections load.
    CHECK_NOTHROW(load(rewrite([](auto&, auto&, auto&) { return true; })));
    // A newer plants section, a missing hydrology section, a longer budget section and a section
    // of a newer ecoterra are each refused by name.
    CHECK_THROWS_WITH(load(rewrite([](const std::string& n, std::uint32_t& v, auto&) {
                          if (n == "plants") v += 1;
                          return true;
                      })),
                      Catch::Contains("section 'plants' has version 2"));
    CHECK_THROWS_WITH(
        load(rewrite([](const std::string& n, auto&, auto&) { return n != "hydrology"; })),
        Catch::Contains("no section 'hydrology'"));
    CHECK_THROWS_WITH(load(rewrite([](const std::string& n, auto&, std::vector<std::uint8_t>& p) {
                          if (n == "budget") p.push_back(0);
                          return true;
                      })),
                      Catch::Contains("section 'budget' holds more"));
    CHECK_THROWS_WITH(load([&] {
                          auto b = bytes;
                          ArchiveWriter extra;
                          SectionWriter w(extra);
                          w.section("dead_wood", 1, [](ArchiveWriter& s) { s.put(1.0); });
                          b.insert(b.end(), extra.bytes().begin(), extra.bytes().end());
                          return b;
                      }()),
                      Catch::Contains("section 'dead_wood'") && Catch::Contains("does not know"));
}

TEST_CASE("write_run_file: an engine written at any day and read back continues bit for bit",
          "[resume][run]") {
    // The library path of the Python module's Run.write and Run.from_run_file: split points at
    // year ends and mid-year, and a replaced file.
    json j = quickstart_json();
    j["terrain"]["generate"]["size"] = 20;
    j["simulation"]["years"] = 3;
    const eco::EcoScene sc = eco::load_eco_scene(j, test::data_dir() / "scenes");
    eco::Ecosystem whole(sc);
    for (int y = 0; y < 3; ++y) whole.run_year();
    const auto end = checkpoint(whole);
    test::TempDir dir;
    for (const int split_day : {0, 200, 365, 500, 730, 1000}) {
        CAPTURE(split_day);
        eco::Ecosystem e(sc);
        for (int d = 0; d < split_day; ++d) e.step_day();
        const auto path = dir / "w.h5";
        run::write_run_file(e, path, json::object(), true); // the second on replaces the first
        auto r = run::load_run_engine(path);
        CHECK(first_difference(checkpoint(*r), checkpoint(e)) == -1);
        while (r->days_done() < 3 * 365) r->step_day();
        CHECK(first_difference(checkpoint(*r), end) == -1);
        CHECK(run::read_run_info(path).snapshots == 1);
    }
    CHECK_THROWS_WITH(run::write_run_file(whole, dir / "w.h5", json::object(), false),
                      Catch::Contains("exists"));
}

namespace {
/// A run file's series as the run layer reads them back: the engine's own tables by name, integer
/// columns as the whole numbers the file stores. `change` may alter one column on its way.
eco::Ecosystem::SeriesSource series_of(
    const eco::Ecosystem& e,
    std::function<void(const std::string&, const std::string&, std::vector<double>&)> change = {}) {
    return [&e, change](const std::string& table, const std::string& column) {
        const Table& t = table == "daily" ? e.daily() : e.yearly();
        auto v = t.column(column);
        if (change) change(table, column, v);
        return v;
    };
}

std::vector<std::uint8_t> run_file_checkpoint(const eco::Ecosystem& e) {
    ArchiveWriter a;
    e.save_state(a, eco::Ecosystem::SeriesIn::run_file);
    return a.bytes();
}
} // namespace

TEST_CASE("resume: a checkpoint that keeps its series in the run file resumes from them, and "
          "refuses them changed",
          "[eco][resume][checkpoint]") {
    const auto scene = quickstart_scene(24);
    eco::Ecosystem e(scene);
    for (int y = 0; y < 2; ++y) e.run_year();
    const auto inside = checkpoint(e);
    const auto outside = run_file_checkpoint(e);
    // The series are most of a checkpoint after two years; the hashes that stand for them, little.
    CHECK(outside.size() * 2 < inside.size());
    const auto load = [&](const std::vector<std::uint8_t>& b,
                          const eco::Ecosystem::SeriesSource& s) {
        auto r = std::make_unique<eco::Ecosystem>(scene);
        ArchiveReader in(b.data(), b.size(), "run.h5");
        r->load_state(in, s);
        return r;
    };
    // Read back with its series, the state is the whole one, and runs on as the engine does.
    auto resumed = load(outside, series_of(e));
    CHECK(first_difference(checkpoint(*resumed), inside) == -1);
    resumed->run_year();
    e.run_year();
    CHECK(first_difference(checkpoint(*resumed), checkpoint(e)) == -1);
    // Without them, it is refused and says where they are.
    CHECK_THROWS_WITH(load(outside, {}), Catch::Contains("kept in the run file's /series"));
    CHECK_THROWS_AS(load(outside, {}), CheckpointError);
    // Every column, changed in one value or one row short, is refused by name.
    const auto bytes = run_file_checkpoint(e);
    int columns = 0;
    for (const char* table : {"daily", "yearly"}) {
        const Table& t = std::string(table) == "daily" ? e.daily() : e.yearly();
        for (std::size_t c = 0; c < t.names.size(); ++c, ++columns) {
            const std::string name = t.names[c];
            CAPTURE(table, name);
            const auto changed = [&](bool shorter) {
                return series_of(
                    e, [&, shorter](const std::string& tb, const std::string& col, auto& v) {
                        if (tb != table || col != name) return;
                        if (shorter)
                            v.pop_back();
                        else
                            v[v.size() / 2] = v[v.size() / 2] + 1.0;
                    });
            };
            const std::string where = std::string("/series/") + table + "/" + name;
            CHECK_THROWS_WITH(load(bytes, changed(false)),
                              Catch::Contains(where) && Catch::Contains("other values"));
            CHECK_THROWS_WITH(load(bytes, changed(true)),
                              Catch::Contains(where) && Catch::Contains("rows against"));
        }
    }
    CHECK(columns > 40);
}

TEST_CASE("resume: series that would not read back exactly from the run file stay in the "
          "checkpoint",
          "[eco][resume][checkpoint]") {
    // A run resumed from a checkpoint older than a column has NaN in that column's rows before
    // the resume, integer columns among them, and a run file stores integers: its checkpoint
    // then keeps such series itself, and reads without the run file's. Such a checkpoint is made
    // here by renaming, in a checkpoint's series, the integer column snags_fallen to a float
    // column's name of the same length (stems_per_ha), so that snags_fallen is missing from it.
    const auto scene = quickstart_scene(12);
    eco::Ecosystem e(scene);
    e.run_year();
    auto old = checkpoint(e);
    const std::string from = "snags_fallen", to = "stems_per_ha";
    const auto at = std::search(old.begin(), old.end(), from.begin(), from.end());
    REQUIRE(at != old.end());
    REQUIRE(std::search(at + 1, old.end(), from.begin(), from.end()) == old.end());
    std::copy(to.begin(), to.end(), at);
    eco::Ecosystem resumed(scene);
    ArchiveReader r(old.data(), old.size(), "older checkpoint");
    resumed.load_state(r);
    REQUIRE(std::isnan(resumed.yearly().column("snags_fallen").front()));
    const auto bytes = run_file_checkpoint(resumed);
    CHECK(first_difference(bytes, checkpoint(resumed)) == -1);
    eco::Ecosystem again(scene);
    ArchiveReader r2(bytes.data(), bytes.size(), "run.h5");
    CHECK_NOTHROW(again.load_state(r2));
    // Without the NaN, the same engine's series go to the run file.
    CHECK(run_file_checkpoint(e).size() < checkpoint(e).size());
}
