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

namespace {

/// Two calendar years of observed weather: mild and nearly dry, but for a week of 80 mm a day
/// from day 150 of the second year.
std::string wet_week_csv() {
    std::string s = "date,tmin_c,tmax_c,rain_mm\n";
    const int month_days[12] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
    int doy = 0;
    for (const int year : {2021, 2022})
        for (int m = 0; m < 12; ++m)
            for (int d = 1; d <= month_days[m]; ++d) {
                ++doy;
                const int day = doy - (year == 2022 ? 365 : 0);
                const bool wet = year == 2022 && day >= 150 && day < 157;
                char row[64];
                std::snprintf(row, sizeof row, "%d-%02d-%02d,14,26,%s\n", year, m + 1, d,
                              wet ? "80" : (d % 10 == 0 ? "3" : "0"));
                s += row;
            }
    return s;
}

} // namespace

TEST_CASE("mobility map --season: after a week of heavy rain a heavy truck bogs down on flat "
          "loam and drives again as it dries, never on sand, and the light MRZR only slows",
          "[mobility][map][season][cli][soil]") {
    test::TempDir dir;
    std::ofstream(dir / "weather.csv") << wet_week_csv();
    // 30 t on three axles of 1 m tyres 0.3 m wide: VCI1 ~510 kPa (docs/mobility.md s9).
    std::ofstream(dir / "truck.json") << R"({"name": "30 t truck", "mass_kg": 30000,
        "width_m": 2.5, "length_m": 8, "wheelbase_m": 5, "track_m": 2.0, "wheel_radius_m": 0.5,
        "ground_clearance_m": 0.4, "tyre_width_m": 0.3, "axles": 3, "tyres_per_axle": 2,
        "tractive_force_n": [[0, 150000], [10, 150000], [25, 0]], "top_speed_m_per_s": 20})";
    auto season = [&](const std::string& name, double sand, double silt, double clay,
                      const std::string& vehicle) {
        auto scene = test::small_scene(2);
        scene["terrain"]["generate"]["params"]["rms_m"] = 0.005; // flat
        scene["soil"]["uniform"] = {
            {"sand_pct", sand}, {"silt_pct", silt}, {"clay_pct", clay}, {"ph", 6.2}};
        scene["climate"] = {{"preset", "humid_subtropical"}, {"csv", "weather.csv"}};
        scene["vegetation"]["initial"] = "bare";
        std::ofstream(dir / (name + ".json")) << scene.dump(2);
        if (!std::filesystem::exists(dir / (name + ".h5")))
            REQUIRE(test::run(dir, "run " + name + ".json -o " + name + ".h5 --no-pictures").code ==
                    0);
        const auto r = test::run(dir, "mobility map " + name + ".h5 --vehicle " + vehicle +
                                          " --season --year 2 --no-pictures -o " + name + "_" +
                                          std::filesystem::path(vehicle).stem().string());
        INFO(r.out);
        REQUIRE(r.code == 0);
        return json::parse(
            io::read_text(dir / (name + "_" + std::filesystem::path(vehicle).stem().string()) /
                          "summary.json"))["days"];
    };
    const json loam = season("loam", 40, 40, 20, "truck.json");
    REQUIRE(loam.size() == 365);
    auto go = [](const json& days, int doy) {
        return days[static_cast<std::size_t>(doy - 1)]["go_share_of_cell_headings"].get<double>();
    };
    CHECK(go(loam, 140) == 1); // dry: GO everywhere
    double worst = 1;
    int first_nogo = 0, back = 0;
    for (int d = 150; d <= 365; ++d) {
        worst = std::min(worst, go(loam, d));
        if (!first_nogo && go(loam, d) < 1) first_nogo = d;
        if (first_nogo && !back && go(loam, d) == 1) back = d;
    }
    CHECK(worst == 0);        // the whole flat field bogs down
    CHECK(first_nogo >= 150); // after the rain began, not before
    CHECK(first_nogo <= 157);
    CHECK(back > first_nogo); // and drives again as it dries
    // The soil's median rating cone index falls with the rain and recovers.
    auto rci = [&](const json& days, int doy) {
        return days[static_cast<std::size_t>(doy - 1)]["rating_cone_index_median_kpa"]
            .get<double>();
    };
    CHECK(rci(loam, 157) < rci(loam, 140));
    CHECK(rci(loam, back) > rci(loam, 157));
    // Sand firms as it wets (Sullivan & Anderson): the truck goes all year. Clay, at the same
    // rain, bogs it down.
    const json sand = season("sand", 92, 5, 3, "truck.json");
    for (int d = 1; d <= 365; ++d) CHECK(go(sand, d) == 1);
    const json clay = season("clay", 20, 20, 60, "truck.json");
    double clay_worst = 1;
    for (int d = 150; d <= 365; ++d) clay_worst = std::min(clay_worst, go(clay, d));
    CHECK(go(clay, 140) == 1);
    CHECK(clay_worst < 1);
    // The MRZR (VCI1 98 kPa) never bogs down in loam, but the wet soil slows it.
    const json light =
        season("loam", 40, 40, 20, (test::data_dir() / "vehicles/mrzr4.json").string());
    for (int d = 1; d <= 365; ++d) CHECK(go(light, d) == 1);
    CHECK(light[156]["mean_speed_m_per_s"].get<double>() <
          light[139]["mean_speed_m_per_s"].get<double>());
}
