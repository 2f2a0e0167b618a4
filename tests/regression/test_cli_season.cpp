// `ecoterra mobility map --season`: a run's year replayed day by day is the run's own year (the
// last day's ground is the snapshot's), from a snapshot checkpoint or from the start alike.
#include "support/run_cli.hpp"
#include "support/scenes.hpp"

#include "ecoterra/io/atomic_file.hpp"
#include "ecoterra/run/run_reader.hpp"
#include "ecoterra/run/season.hpp"
#include "ecoterra/terrain/io/raster_io.hpp"

#include <catch2/catch.hpp>

#include <fstream>

using namespace ecoterra;
using nlohmann::json;

TEST_CASE("mobility map --season: a year replayed day by day is the run's own year",
          "[mobility][map][season][cli]") {
    test::TempDir dir;
    auto scene = test::small_scene(6);
    scene["simulation"]["snapshot_interval_years"] = 2;
    std::ofstream(dir / "plain.json") << scene.dump(2);
    scene["simulation"]["snapshot_checkpoints"] = true;
    std::ofstream(dir / "kept.json") << scene.dump(2);
    REQUIRE(test::run(dir, "run plain.json -o plain.h5 --no-pictures").code == 0);
    REQUIRE(test::run(dir, "run kept.json -o kept.h5 --no-pictures").code == 0);
    const RasterD terrain = run::read_run_terrain(dir / "plain.h5");
    // The replayed year's last day holds the ground of the snapshot at its end.
    for (const int year : {4, 6}) {
        CAPTURE(year);
        RasterD last_rci;
        int days = 0, from = -1;
        run::replay_season(
            dir / "kept.h5", year, [&](const run::SeasonStand& s) { from = s.replayed_from; },
            [&](const run::SeasonDay& d) {
                ++days;
                last_rci = *d.rci_kpa;
            });
        CHECK(days == 365);
        CHECK(from == year - 2); // the snapshot checkpoint two years before
        const RasterD snap =
            run::read_snapshot_raster(dir / "kept.h5", run::snapshot_of_year(dir / "kept.h5", year),
                                      "rating_cone_index_kpa", terrain.grid());
        for (int j = 0; j < snap.ny(); ++j)
            for (int i = 0; i < snap.nx(); ++i)
                CHECK(last_rci(i, j) == Approx(snap(i, j)).epsilon(1e-6)); // float32 on disk
    }
    // The CLI: the same days whether replayed from the start or from a snapshot checkpoint.
    const std::string veh = (test::data_dir() / "vehicles/mrzr4.json").string();
    auto r = test::run(dir, "mobility map plain.h5 --vehicle " + veh + " --season --year 5 -o a");
    INFO(r.out);
    REQUIRE(r.code == 0);
    CHECK_THAT(r.out, Catch::Contains("replayed from year 0"));
    r = test::run(dir, "mobility map kept.h5 --vehicle " + veh +
                           " --season --year 5 -o b --no-pictures");
    REQUIRE(r.code == 0);
    CHECK_THAT(r.out, Catch::Contains("replayed from year 4"));
    const json a = json::parse(io::read_text(dir / "a/summary.json"));
    const json b = json::parse(io::read_text(dir / "b/summary.json"));
    CHECK(a["days"].size() == 365);
    CHECK(a["days"] == b["days"]);
    for (const char* f :
         {"go_share_of_days.tif", "speed_median_m_per_s.tif", "speed_p10_m_per_s.tif"}) {
        const RasterD x = terrain::io::read_raster(dir / "a" / f);
        CHECK(x.nx() == terrain.nx());
    }
    for (const char* png : {"season_go_share.png", "season_daily.png"})
        CHECK(std::filesystem::file_size(dir / "a" / png) > 1000);
    // The 10th percentile never exceeds the median.
    const RasterD p10 = terrain::io::read_raster(dir / "a/speed_p10_m_per_s.tif");
    const RasterD med = terrain::io::read_raster(dir / "a/speed_median_m_per_s.tif");
    for (int j = 0; j < p10.ny(); ++j)
        for (int i = 0; i < p10.nx(); ++i) CHECK(p10(i, j) <= med(i, j) + 1e-6);
    // A year outside the run; --year without a snapshot of it; --season with a stem list.
    r = test::run(dir, "mobility map plain.h5 --vehicle " + veh + " --season --year 9 -o c");
    CHECK(r.code == 2);
    CHECK_THAT(r.out, Catch::Contains("year 9 is outside the run") && Catch::Contains("1-6"));
    CHECK_FALSE(std::filesystem::exists(dir / "c"));
    r = test::run(dir, "mobility map plain.h5 --vehicle " + veh + " --year 3 -o c");
    CHECK(r.code == 2);
    CHECK_THAT(r.out, Catch::Contains("no snapshot of year 3"));
    r = test::run(dir, "mobility map plain.h5 --vehicle " + veh + " --year 4 -o c --no-pictures");
    CHECK(r.code == 0);
}
