// `ecoterra mobility` as a user runs it: the issue's invocations, the report's keys against the
// stand, determinism across seeds and thread counts, and bad input.
#include "support/run_cli.hpp"
#include "support/scenes.hpp"

#include "ecoterra/analyses/analyses.hpp"
#include "ecoterra/error.hpp"
#include "ecoterra/hydro/soil_strength.hpp"
#include "ecoterra/io/atomic_file.hpp"
#include "ecoterra/mobility/map.hpp"
#include "ecoterra/mobility/stand.hpp"
#include "ecoterra/mobility/traverse.hpp"
#include "ecoterra/random.hpp"
#include "ecoterra/run/run_reader.hpp"
#include "ecoterra/terrain/io/raster_io.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>
#include <numbers>
#include <omp.h>

using namespace ecoterra;
using namespace ecoterra::mobility;
using nlohmann::json;

namespace {

json read_json(const std::filesystem::path& p) {
    return json::parse(io::read_text(p));
}

RasterD flat(double side_m, double cell_m) {
    const int n = static_cast<int>(side_m / cell_m);
    return RasterD(GridSpec{n, n, cell_m, 0.0, 0.0}, 0.0);
}

} // namespace

TEST_CASE("mobility: a stand's report, on any number of threads", "[mobility][stand]") {
    const Vehicle v = load_vehicle(test::data_dir() / "vehicles/mrzr4.json");
    const RasterD dem = flat(100, 1);
    StandLinesOptions opt;
    opt.lines = 40;
    // No stems: every line at the top speed, no basal area.
    const auto empty = analyse_stand(v, {}, dem, opt);
    CHECK(empty.nogo_fraction == 0);
    CHECK(empty.smg_mean_m_per_s == Approx(v.top_speed_m_per_s));
    CHECK(empty.basal_area_m2_per_ha == 0);
    // 400 stems of 20 cm on 1 ha: basal area 400 pi 0.01 = 12.57 m2/ha; thin ones below breast
    // height do not count.
    std::vector<StandStem> stems;
    Rng rng(3, "test");
    for (int k = 0; k < 400; ++k)
        stems.push_back({rng.uniform(0, 100), rng.uniform(0, 100), 0.2, 18});
    for (int k = 0; k < 100; ++k) stems.push_back({rng.uniform(0, 100), rng.uniform(0, 100), 0, 1});
    const auto m = analyse_stand(v, stems, dem, opt);
    CHECK(m.basal_area_m2_per_ha == Approx(400 * std::numbers::pi * 0.01));
    CHECK(m.trees == 400);
    CHECK(m.smg_mean_m_per_s < empty.smg_mean_m_per_s);
    CHECK(m.detour_fraction > 0);
    const json j = analyses::mobility_json(m, v);
    for (const char* k : {"smg_mean_m_per_s", "smg_median_m_per_s", "nogo_fraction", "lines",
                          "basal_area_m2_per_ha", "basal_area_ft2_per_acre"})
        CHECK(j.contains(k));
    CHECK(j["lines"].size() == 40);
    // The same on one thread as on two.
    const int threads = omp_get_max_threads();
    omp_set_num_threads(1);
    const json one = analyses::mobility_json(analyse_stand(v, stems, dem, opt), v);
    omp_set_num_threads(std::max(2, threads));
    const json two = analyses::mobility_json(analyse_stand(v, stems, dem, opt), v);
    omp_set_num_threads(threads);
    CHECK(one == two);
    CHECK(one == j);
    // Transects: parallel lines west to east.
    opt.layout = LineLayout::transects;
    const auto t = analyse_stand(v, stems, dem, opt);
    for (const auto& l : t.lines) CHECK(l.a.y_m == l.b.y_m);
    // Stems that miss the terrain, lines longer than it.
    std::vector<StandStem> away{{500, 500, 0.2, 10}};
    CHECK_THROWS_WITH(analyse_stand(v, away, dem, opt), Catch::Contains("none of the 1 stems"));
    opt.length_m = 500;
    CHECK_THROWS_WITH(analyse_stand(v, stems, dem, opt), Catch::Contains("longer than"));
}

TEST_CASE("mobility: the issue's invocations work as written", "[mobility][cli]") {
    test::TempDir dir;
    // 15 years: trees have died, and some of their snags have fallen.
    std::ofstream(dir / "scene.json") << test::small_scene(15).dump(2);
    REQUIRE(test::run(dir, "run scene.json -o run.h5 --no-pictures").code == 0);
    const std::string veh = (test::data_dir() / "vehicles/mrzr4.json").string();
    // Firm, dry ground (--no-soil): the stem lists below carry no soil to compare with.
    auto r = test::run(dir, "mobility run.h5 --vehicle " + veh +
                                " --lines 50 --length 20 --seed 1 --json smg.json --no-soil");
    INFO(r.out);
    REQUIRE(r.code == 0);
    const json a = read_json(dir / "smg.json");
    // Pictures by default beside the JSON: the lines over the stem map and the SMG histogram.
    for (const char* png : {"smg_lines.png", "smg_histogram.png"})
        CHECK(std::filesystem::file_size(dir / "smg.pictures" / png) > 1000);
    CHECK(a["lines"].size() == 50);
    CHECK(a["smg_mean_m_per_s"].get<double>() > 0);
    CHECK(a["smg_mean_m_per_s"].get<double>() <= 22.3 + 1e-9);
    CHECK(a["snags"].get<int>() > 0);
    CHECK(a["logs"].get<int>() > 0);
    CHECK(a["source"]["deadwood_included"] == true);
    // The living stand alone is no slower.
    r = test::run(dir, "mobility run.h5 --vehicle " + veh +
                           " --lines 50 --length 20 --seed 1 --json live.json --no-deadwood "
                           "--no-soil");
    REQUIRE(r.code == 0);
    const json live = read_json(dir / "live.json");
    CHECK(live["logs"] == 0);
    CHECK(live["snags"] == 0);
    CHECK(live["smg_mean_m_per_s"].get<double>() >= a["smg_mean_m_per_s"].get<double>());
    // The exported stems and dead wood over the run's own terrain (generated again from its
    // specification) give the same figures.
    REQUIRE(test::run(dir, "export vegetation run.h5 -o stems.csv").code == 0);
    REQUIRE(test::run(dir, "export deadwood run.h5 -o dead.csv").code == 0);
    REQUIRE(test::run(dir, "terrain generate --method fbm --D 2.3 --size 20 --cell 2 --rms 0.8 "
                           "--seed 5 -o dem.h5")
                .code == 0);
    r = test::run(dir, "mobility --stems stems.csv --deadwood dead.csv --dem dem.h5 --vehicle " +
                           veh + " --lines 50 --length 20 --seed 1 --json smg2.json --no-pictures");
    INFO(r.out);
    REQUIRE(r.code == 0);
    const json b = read_json(dir / "smg2.json");
    CHECK(b["basal_area_m2_per_ha"].get<double>() ==
          Approx(a["basal_area_m2_per_ha"].get<double>()).epsilon(1e-6));
    CHECK(b["smg_mean_m_per_s"].get<double>() ==
          Approx(a["smg_mean_m_per_s"].get<double>()).epsilon(1e-6));
    CHECK(b["nogo_fraction"] == a["nogo_fraction"]);
    for (const char* k : {"snags", "logs"}) CHECK(b[k] == a[k]);
    CHECK(b["log_crossings_per_100m"].get<double>() ==
          Approx(a["log_crossings_per_100m"].get<double>()).epsilon(1e-6));
    CHECK_FALSE(std::filesystem::exists(dir / "smg2.pictures"));
    // Bad input: exit 2, a message naming the file, and nothing written.
    std::ofstream(dir / "bad.csv") << "x_m,y_m,dbh_cm\n1,2,-3\n";
    r = test::run(dir,
                  "mobility --stems bad.csv --dem dem.h5 --vehicle " + veh + " --json out.json");
    CHECK(r.code == 2);
    CHECK_THAT(r.out, Catch::Contains("bad.csv line 2") && Catch::Contains("negative"));
    CHECK_FALSE(std::filesystem::exists(dir / "out.json"));
    r = test::run(dir, "mobility run.h5 --stems stems.csv --vehicle " + veh);
    CHECK(r.code == 2);
    r = test::run(dir, "mobility run.h5 --deadwood dead.csv --vehicle " + veh);
    CHECK(r.code == 2);
    CHECK_THAT(r.out, Catch::Contains("--deadwood goes with --stems"));
    std::ofstream(dir / "bad_dead.csv")
        << io::read_text(dir / "dead.csv").substr(0, io::read_text(dir / "dead.csv").find('\n'))
        << "\n1,0,0,3,1,1,2,1,1,0,5,1,0.3,10,-4,0,0.3,0.2,1,1,x\n";
    r = test::run(dir,
                  "mobility --stems stems.csv --deadwood bad_dead.csv --dem dem.h5 --vehicle " +
                      veh + " --json out.json");
    CHECK(r.code == 2);
    CHECK_THAT(r.out, Catch::Contains("bad_dead.csv line 2") && Catch::Contains("negative"));
    CHECK_FALSE(std::filesystem::exists(dir / "out.json"));
    std::ofstream(dir / "car.json") << R"({"mass_kg": 100, "width_m": 0, "length_m": 2,
        "tractive_force_n": [[0, 100], [1, 0]]})";
    r = test::run(dir, "mobility run.h5 --vehicle car.json");
    CHECK(r.code == 2);
    CHECK_THAT(r.out, Catch::Contains("car.json") && Catch::Contains("width_m"));
}

TEST_CASE("mobility: a windthrown stand is slower than the same stand before the storm",
          "[mobility][cli][windthrow]") {
    test::TempDir dir;
    auto scene = test::small_scene(14);
    scene["vegetation"]["windthrow"] = {
        {"storms", {{{"year", 14}, {"wind_m_per_s", 28}, {"from_deg", 200}}}}};
    std::ofstream(dir / "scene.json") << scene.dump(2);
    REQUIRE(test::run(dir, "run scene.json -o run.h5 --no-pictures").code == 0);
    const std::string veh = (test::data_dir() / "vehicles/mrzr4.json").string();
    auto smg = [&](const std::string& snapshot, const std::string& out) {
        const auto r = test::run(dir, "mobility run.h5 --snapshot " + snapshot + " --vehicle " +
                                          veh + " --lines 100 --length 20 --seed 3 --json " + out +
                                          " --no-pictures --no-soil");
        INFO(r.out);
        REQUIRE(r.code == 0);
        return read_json(dir / out);
    };
    const json before = smg("-2", "before.json"), after = smg("-1", "after.json");
    // The storm felled trees: fewer stand, more lie (logs and root plates), and the vehicle
    // meets more it cannot climb.
    CHECK(after["trees"].get<double>() < before["trees"].get<double>());
    CHECK(after["logs"].get<double>() > before["logs"].get<double>());
    CHECK(after["logs_avoided_per_line"].get<double>() >
          before["logs_avoided_per_line"].get<double>());
    CHECK(after["smg_mean_m_per_s"].get<double>() < before["smg_mean_m_per_s"].get<double>());
    // The exported lists (with snapped stems and root plates) give the same figures.
    REQUIRE(test::run(dir, "export vegetation run.h5 -o stems.csv").code == 0);
    REQUIRE(test::run(dir, "export deadwood run.h5 -o dead.csv").code == 0);
    const std::string dead = io::read_text(dir / "dead.csv");
    CHECK(dead.find(",4,7,") != std::string::npos); // a root plate of an uprooted tree
    REQUIRE(test::run(dir, "terrain generate --method fbm --D 2.3 --size 20 --cell 2 --rms 0.8 "
                           "--seed 5 -o dem.h5")
                .code == 0);
    const auto r = test::run(dir, "mobility --stems stems.csv --deadwood dead.csv --dem dem.h5 "
                                  "--vehicle " +
                                      veh +
                                      " --lines 100 --length 20 --seed 3 --json csv.json "
                                      "--no-pictures");
    INFO(r.out);
    REQUIRE(r.code == 0);
    const json c = read_json(dir / "csv.json");
    CHECK(c["smg_mean_m_per_s"].get<double>() ==
          Approx(after["smg_mean_m_per_s"].get<double>()).epsilon(1e-6));
    for (const char* k : {"snags", "logs"}) CHECK(c[k] == after[k]);
}

TEST_CASE("soil strength: a snapshot holds the rating cone index of its critical layer's water",
          "[mobility][soil][cli]") {
    test::TempDir dir;
    std::ofstream(dir / "scene.json") << test::small_scene(2).dump(2);
    REQUIRE(test::run(dir, "run scene.json -o run.h5 --no-pictures").code == 0);
    const RasterD terrain = run::read_run_terrain(dir / "run.h5");
    const RasterD theta =
        run::read_snapshot_raster(dir / "run.h5", -1, "critical_layer_moisture", terrain.grid());
    // The critical layer is not the root zone: after two years they differ somewhere.
    const RasterD root =
        run::read_snapshot_raster(dir / "run.h5", -1, "soil_moisture", terrain.grid());
    double most = 0;
    for (std::int64_t k = 0; k < root.size(); ++k)
        most = std::max(most, std::abs(root.data()[k] - theta.data()[k]));
    CHECK(most > 1e-3);
    const RasterD rci =
        run::read_snapshot_raster(dir / "run.h5", -1, "rating_cone_index_kpa", terrain.grid());
    // The small scene's uniform soil: 15 % sand, 70 % silt, 15 % clay, a silt loam.
    const auto tex = hydro::classify_texture(15, 70, 15);
    for (int j = 0; j < theta.ny(); ++j)
        for (int i = 0; i < theta.nx(); ++i)
            CHECK(rci(i, j) ==
                  Approx(hydro::rating_cone_index_kpa(tex, theta(i, j))).epsilon(1e-5));
    // `ecoterra mobility` applies it for the MRZR (the report says against what), for the Husky
    // (outside the regressions) by Brixius's traction alone, and --no-soil leaves it out.
    const std::string mrzr = (test::data_dir() / "vehicles/mrzr4.json").string();
    const std::string husky = (test::data_dir() / "vehicles/husky_a200.json").string();
    auto r = test::run(dir, "mobility run.h5 --vehicle " + mrzr +
                                " --lines 20 --length 15 --json s.json --no-pictures");
    REQUIRE(r.code == 0);
    CHECK_THAT(r.out, Catch::Contains("soil: rating cone index") && Catch::Contains("VCI1 98"));
    // The shipped file gives every mobility-index key but the engine's power: said so.
    CHECK_THAT(r.out,
               Catch::Contains("gives no engine_power_kw") && !Catch::Contains("tyre_width_m"));
    CHECK(read_json(dir / "s.json")["source"]["soil_strength_applied"] == true);
    // Taking the slowing apart: only the overridden stems, or a clear error for a wrong name.
    r = test::run(dir, "mobility run.h5 --vehicle " + mrzr +
                           " --lines 20 --length 15 --effects override_only --json o.json "
                           "--no-pictures");
    REQUIRE(r.code == 0);
    const json only = read_json(dir / "o.json");
    CHECK(only["effects"] == "override_only");
    for (const auto& l : only["lines"]) CHECK(l["stems_avoided"] == 0);
    r = test::run(dir, "mobility run.h5 --vehicle " + mrzr + " --effects sideways --no-pictures");
    CHECK(r.code == 2);
    CHECK_THAT(r.out, Catch::Contains("--effects must be both, override_only or avoidance_only, "
                                      "got 'sideways'"));
    r = test::run(dir, "mobility run.h5 --vehicle " + husky + " --lines 20 --length 15");
    REQUIRE(r.code == 0);
    CHECK_THAT(r.out, Catch::Contains("no VCI1") && Catch::Contains("Brixius"));
    r = test::run(dir, "mobility run.h5 --vehicle " + mrzr +
                           " --lines 20 --length 15 --json n.json --no-pictures --no-soil");
    REQUIRE(r.code == 0);
    const json n = read_json(dir / "n.json");
    CHECK(n["source"]["soil_strength_applied"] == false);
    // A small scene's silt loam after two years is far firmer than the MRZR needs: no line is
    // NO-GO for the soil, and its motion resistance costs the MRZR a little speed.
    const json s = read_json(dir / "s.json");
    CHECK(s["nogo_fraction"] == n["nogo_fraction"]);
    CHECK(s["smg_mean_m_per_s"].get<double>() < n["smg_mean_m_per_s"].get<double>());
    CHECK(s["smg_mean_m_per_s"].get<double>() > 0.9 * n["smg_mean_m_per_s"].get<double>());
}

TEST_CASE("terrain traverse: the issue's invocation works as written", "[mobility][cli][slow]") {
    test::TempDir dir;
    REQUIRE(test::run(dir, "terrain generate --method fbm --D 2.3 --size 1000 --cell 0.05 "
                           "--rms 0.1 --seed 2 -o mf.h5")
                .code == 0);
    REQUIRE(test::run(dir, "terrain missions mf.h5 --count 6 -o missions.csv").code == 0);
    const std::string veh = (test::data_dir() / "vehicles/husky_a200.json").string();
    auto r = test::run(dir, "terrain traverse mf.h5 --vehicle " + veh +
                                " --missions missions.csv --json traverse.json");
    INFO(r.out);
    REQUIRE(r.code == 0);
    const json t = read_json(dir / "traverse.json");
    CHECK(std::filesystem::file_size(dir / "traverse.pictures" / "missions.png") > 1000);
    REQUIRE(t["records"].size() == 6);
    int ok = 0;
    for (const auto& rec : t["records"]) {
        ok += rec["success"].get<bool>();
        CHECK((rec["success"].get<bool>() ? rec.contains("time_s") : rec.contains("failure")));
    }
    CHECK(t["success_rate"].get<double>() == Approx(ok / 6.0));
    // Each record names its mission's start and goal, so that it can be replayed elsewhere.
    const auto missions = mobility::read_missions_csv(dir / "missions.csv");
    for (std::size_t k = 0; k < missions.size(); ++k) {
        CHECK(t["records"][k]["start_m"][0].get<double>() == missions[k].start_x_m);
        CHECK(t["records"][k]["goal_m"][1].get<double>() == missions[k].goal_y_m);
    }
    // Planned missions without a file, and bad input.
    r = test::run(dir, "terrain traverse mf.h5 --vehicle " + veh + " --count 4");
    CHECK(r.code == 0);
    CHECK_THAT(r.out, Catch::Contains("of 4 missions"));
    std::ofstream(dir / "far.csv") << "id,start_x_m,start_y_m,goal_x_m,goal_y_m\n1,10,10,90,10\n";
    r = test::run(dir, "terrain traverse mf.h5 --vehicle " + veh + " --missions far.csv");
    CHECK(r.code == 2);
    CHECK_THAT(r.out, Catch::Contains("far.csv") && Catch::Contains("leaves the terrain"));
}

TEST_CASE("mobility map: the issue's invocations work as written, GDAL reads the layers, and "
          "bad input is refused with nothing written",
          "[mobility][map][cli]") {
    test::TempDir dir;
    std::ofstream(dir / "scene.json") << test::small_scene(6).dump(2);
    REQUIRE(test::run(dir, "run scene.json -o run.h5 --no-pictures").code == 0);
    const std::string veh = (test::data_dir() / "vehicles/mrzr4.json").string();
    auto r = test::run(dir, "mobility map run.h5 --vehicle " + veh + " -o map");
    INFO(r.out);
    REQUIRE(r.code == 0);
    CHECK_THAT(r.out, Catch::Contains("cell-headings") && Catch::Contains("limiting factor"));
    const json s = read_json(dir / "map/summary.json");
    const RasterD terrain = run::read_run_terrain(dir / "run.h5");
    CHECK(s["cells"]["nx"] == terrain.nx());
    CHECK(s["headings_deg"].size() == 8);
    CHECK(s["source"]["soil_strength_applied"] == true);
    CHECK(s["source"]["standing_water_applied"] == true);
    for (const char* png : {"speed.png", "limiting_factor.png"})
        CHECK(std::filesystem::file_size(dir / "map" / png) > 1000);
    // Every layer the summary lists is a GeoTIFF GDAL reads, on the map's grid.
    for (const auto& l : s["layers"]) {
        const RasterD x = terrain::io::read_raster(dir / "map" / l["file"].get<std::string>());
        CHECK(x.nx() == terrain.nx());
        CHECK(x.grid().cell_size_m == Approx(terrain.grid().cell_size_m));
    }
    const RasterD mean = terrain::io::read_raster(dir / "map/speed_mean_m_per_s.tif");
    double sum = 0;
    for (int j = 0; j < mean.ny(); ++j)
        for (int i = 0; i < mean.nx(); ++i) sum += mean(i, j);
    CHECK(sum / static_cast<double>(mean.nx() * mean.ny()) ==
          Approx(s["mean_speed_m_per_s"].get<double>()).epsilon(1e-6));
    // The fastest route over it: the time is what the JSON says, with a picture beside.
    r = test::run(dir, "mobility route map --from 3,3 --to 30,35 --json route.json");
    INFO(r.out);
    REQUIRE(r.code == 0);
    const json route = read_json(dir / "route.json");
    CHECK(route["found"] == true);
    CHECK(route["time_s"].get<double>() > 0);
    CHECK(route["smg_m_per_s"].get<double>() <= s["top_speed_m_per_s"].get<double>() + 1e-9);
    CHECK(std::filesystem::file_size(dir / "route.png") > 1000);
    r = test::run(dir, "mobility route map --from 3 --to 30,35");
    CHECK(r.code == 2);
    CHECK_THAT(r.out, Catch::Contains("--from '3' is not X,Y"));
    // Coarser cells and more headings; the same map again needs --force.
    r = test::run(dir, "mobility map run.h5 --vehicle " + veh + " -o map --cell " +
                           std::to_string(2 * terrain.grid().cell_size_m) +
                           " --headings 16 --no-pictures");
    CHECK(r.code == 2);
    CHECK_THAT(r.out, Catch::Contains("map"));
    r = test::run(dir, "mobility map run.h5 --vehicle " + veh + " -o map2 --cell " +
                           std::to_string(2 * terrain.grid().cell_size_m) +
                           " --headings 16 --no-pictures");
    INFO(r.out);
    REQUIRE(r.code == 0);
    const json s2 = read_json(dir / "map2/summary.json");
    CHECK(s2["cells"]["nx"] == terrain.nx() / 2);
    CHECK(s2["headings_deg"].size() == 16);
    CHECK_FALSE(std::filesystem::exists(dir / "map2/speed.png"));
    // A stem list over a DEM with its own soil water and standing water.
    REQUIRE(test::run(dir, "export vegetation run.h5 -o stems.csv").code == 0);
    terrain::io::write_raster(terrain, dir / "dem.tif");
    RasterD theta(terrain.grid(), 0.44), water(terrain.grid(), 0.0);
    water(3, 3) = 0.5; // deeper than the MRZR's fording depth (its clearance, 0.3 m)
    terrain::io::write_geotiff(theta, dir / "m.tif", "m3/m3");
    terrain::io::write_geotiff(water, dir / "w.tif", "m");
    r = test::run(dir, "mobility map --dem dem.tif --stems stems.csv --soil-moisture m.tif "
                       "--texture loam --water-depth w.tif --vehicle " +
                           veh + " -o map3 --no-pictures");
    INFO(r.out);
    REQUIRE(r.code == 0);
    const RasterD lim = terrain::io::read_raster(dir / "map3/limiting_factor.tif");
    CHECK(lim(3, 3) == static_cast<double>(Limit::water));
    const RasterD rci = terrain::io::read_raster(dir / "map3/rating_cone_index_kpa.tif");
    CHECK(rci(0, 0) ==
          Approx(hydro::rating_cone_index_kpa(hydro::Texture::loam, 0.44)).epsilon(1e-6));
    // Bad input: a moisture raster that does not cover the DEM, a cell finer than the
    // terrain's, a snapshot outside the run: exit 2, the file and value named, nothing written.
    RasterD small(GridSpec{4, 4, terrain.grid().cell_size_m, 0.0, 0.0}, 0.3);
    terrain::io::write_geotiff(small, dir / "small.tif", "m3/m3");
    r = test::run(dir, "mobility map --dem dem.tif --stems stems.csv --soil-moisture small.tif "
                       "--texture loam --vehicle " +
                           veh + " -o bad1");
    CHECK(r.code == 2);
    CHECK_THAT(r.out, Catch::Contains("small.tif") && Catch::Contains("does not cover the DEM"));
    CHECK_FALSE(std::filesystem::exists(dir / "bad1"));
    r = test::run(dir, "mobility map run.h5 --vehicle " + veh + " -o bad2 --cell 0.5");
    CHECK(r.code == 2);
    CHECK_THAT(r.out, Catch::Contains("cell = 0.5") && Catch::Contains("finer"));
    CHECK_FALSE(std::filesystem::exists(dir / "bad2"));
    r = test::run(dir, "mobility map run.h5 --vehicle " + veh + " -o bad3 --snapshot 99");
    CHECK(r.code == 2);
    CHECK_THAT(r.out, Catch::Contains("snapshot"));
    CHECK_FALSE(std::filesystem::exists(dir / "bad3"));
    r = test::run(dir, "mobility map --dem dem.tif --stems stems.csv --soil-moisture m.tif "
                       "--texture loamy --vehicle " +
                           veh + " -o bad4");
    CHECK(r.code == 2);
    CHECK_THAT(r.out, Catch::Contains("loamy"));
    std::ofstream(dir / "tyre.json") << R"({"mass_kg": 100, "width_m": 1, "length_m": 2,
        "tyre_width_m": -1, "tractive_force_n": [[0, 100], [1, 0]]})";
    r = test::run(dir, "mobility map run.h5 --vehicle tyre.json -o bad5");
    CHECK(r.code == 2);
    CHECK_THAT(r.out, Catch::Contains("tyre.json") && Catch::Contains("tyre_width_m"));
    CHECK_FALSE(std::filesystem::exists(dir / "bad5"));
}
