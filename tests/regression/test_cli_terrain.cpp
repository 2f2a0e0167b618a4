// End-to-end runs of `ecoterra terrain ...` as a user types them.
#include "support/png_size.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

#include "ecoterra/io/atomic_file.hpp"
#include "ecoterra/json_util.hpp"
#include "ecoterra/terrain/io/raster_io.hpp"

#include <catch2/catch.hpp>

#include <array>
#include <cstdio>
#include <fstream>
#include <sys/wait.h>

using namespace ecoterra;
using ecoterra::test::Run;
using ecoterra::test::run;
using ecoterra::test::TempDir;
using nlohmann::json;

namespace {

std::string slurp(const std::filesystem::path& p) {
    return io::read_text(p);
}
} // namespace

TEST_CASE("The issue's terrain invocations work as written", "[cli][regression][slow]") {
    TempDir d;
    const char* cmds[] = {
        "terrain generate --preset majhor2023 --d-high 2.45 --seed 7 -o mf.h5",
        ("terrain generate --method wm --D 2.45 --M 64 --G 1e-8 --gamma 1.5 --L 100.9 --size 1009 "
         "--cell 0.05 --seed 7 -o wm.h5"),
        "terrain generate --method variable --size 512 --cell 0.25 --seed 3 -o var.png",
        "terrain generate --method fbm --D 2.3 --size 1024 --cell 0.5 --seed 3 -o fbm.tif",
        "terrain analyze mf.h5 --json report.json --png pictures/",
        "terrain missions mf.h5 --count 20 --length 35 --border 5 --seed 1 -o missions.csv",
        "terrain convert mf.h5 mf.asc",
    };
    for (const char* c : cmds) {
        const Run r = run(d, c);
        INFO(c << "\n" << r.out);
        REQUIRE(r.code == 0);
        // Generation shows its progress; into a log (not a terminal) as whole lines, no '\r'.
        if (std::string(c).rfind("terrain generate --method wm", 0) == 0) {
            CHECK_THAT(r.out, Catch::Contains("generating terrain") && Catch::Contains("100 %"));
            CHECK(r.out.find('\r') == std::string::npos);
        }
    }
    const auto rep = parse_json(slurp(d / "report.json"), "report.json");
    for (const char* k :
         {"rms_m", "rms_detrended_m", "classes_pct", "fractal_dimension", "psd_slope"})
        CHECK(rep.contains(k));
    for (const char* k : {"low", "semi", "high"}) CHECK(rep["classes_pct"].contains(k));
    CHECK(rep["fractal_dimension_fit"]["value"] ==
          rep["fractal_dimension"]); // the metric and its fit
    CHECK(rep["fractal_dimension_fit"]["range_m"].size() == 2);
    const double total = rep["classes_pct"]["low"].get<double>() +
                         rep["classes_pct"]["semi"].get<double>() +
                         rep["classes_pct"]["high"].get<double>();
    CHECK(total == Approx(100.0));
    // Readable figures (title, colour bar or legend, scale bar): at least 600 px across whatever
    // the grid.
    for (const char* p : {"hillshade.png", "elevation.png", "slope.png", "gradient_classes.png",
                          "closed_classes.png"}) {
        INFO(p);
        CHECK(test::png_size(d / "pictures" / p).first >= 600);
        CHECK(test::png_size(d / "pictures" / p).second >= 600);
    }
    // 20 missions plus a header.
    const std::string csv = slurp(d / "missions.csv");
    CHECK(std::count(csv.begin(), csv.end(), '\n') == 21);
    CHECK(csv.rfind("id,start_x_m,start_y_m,goal_x_m,goal_y_m,heading_deg", 0) == 0);
    // The converted ASCII grid holds the same heights as the HDF5 file.
    const auto a = terrain::io::read_raster(d / "mf.h5");
    const auto b = terrain::io::read_raster(d / "mf.asc");
    CHECK(b(500, 321) == Approx(a(500, 321)).margin(1e-5));
    CHECK(a.nx() == 1009);
    CHECK(a.cell_size() == Approx(0.05));
    CHECK(std::filesystem::exists(d / "var.png.json"));
}

TEST_CASE("Generation is deterministic across runs and thread counts", "[cli][determinism]") {
    TempDir d;
    for (const char* m :
         {"multifractal --size 129 --cell 0.05", "gaussian --size 100", "variable --size 100",
          "fbm --size 64", "perlin --size 100", "wm --size 100 --cell 0.05"}) {
        const std::string base =
            std::string("terrain generate --force --method ") + m + " --seed 5 -o ";
        REQUIRE(run(d, base + "a.asc", "OMP_NUM_THREADS=1").code == 0);
        REQUIRE(run(d, base + "b.asc", "OMP_NUM_THREADS=2").code == 0);
        INFO(m);
        CHECK(slurp(d / "a.asc") == slurp(d / "b.asc"));
    }
}

TEST_CASE("Bad input: clear errors, non-zero exit, earlier output kept", "[cli][errors]") {
    TempDir d;
    REQUIRE(run(d, "terrain generate --method fbm --size 64 --seed 1 -o keep.asc").code == 0);
    const std::string before = slurp(d / "keep.asc");
    struct Case {
        const char* args;
        const char* expect;
    };
    const Case cases[] = {
        {"terrain generate --method wm --D 3.5 --size 32 -o keep.asc --force", "3.5"},
        {"terrain generate --method wm --gamma 1 --size 32 -o keep.asc --force", "gamma"},
        {"terrain generate --method wm --size 0 -o keep.asc --force", "size"},
        {"terrain generate --method fbm --cell -1 -o keep.asc --force", "cell_size_m"},
        {"terrain generate --method perlinn -o keep.asc --force", "did you mean 'perlin'"},
        {"terrain generate --method perlin --D 2.5 -o keep.asc --force", "--D does not apply"},
        {"terrain generate --method fbm --size 64 -o keep.xyz", "unknown raster format"},
        {"terrain generate --method fbm --size 64 -o nodir/out.asc", "does not exist"},
        {"terrain generate --method fbm --size 1048576 -o keep.asc --force", "GiB"},
        {"terrain generate --method fbm --bogus 1 -o keep.asc --force", "bogus"},
        {"terrain analyze missing.h5", "missing.h5"},
        {"terrain generate --config missing.json -o keep.asc --force", "missing.json"},
    };
    for (const auto& c : cases) {
        const Run r = run(d, c.args);
        INFO(c.args << "\n" << r.out);
        CHECK(r.code != 0);
        CHECK_THAT(r.out, Catch::Contains(c.expect));
        CHECK(r.out.find("terminate") == std::string::npos);
    }
    // Even with --force, bad input replaces nothing; without it an existing output is refused.
    CHECK(slurp(d / "keep.asc") == before);
    const Run exists = run(d, "terrain generate --method fbm --size 64 --seed 2 -o keep.asc");
    CHECK(exists.code == 2);
    CHECK_THAT(exists.out, Catch::Contains("-o keep.asc: the file exists; give --force"));
    CHECK(slurp(d / "keep.asc") == before);
    {
        std::ofstream(d / "nodata.asc") << "ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\n"
                                           "cellsize 1\nNODATA_value -9999\n-9999 -9999\n"
                                           "-9999 -9999\n";
        std::ofstream(d / "bad.json")
            << "{\"method\": \"wm\", \"params\": {\"D\": 2.4, \"Gm\": 1}}";
    }
    Run r = run(d, "terrain analyze nodata.asc");
    CHECK(r.code != 0);
    CHECK_THAT(r.out, Catch::Contains("nodata.asc") && Catch::Contains("NODATA"));
    r = run(d, "terrain generate --config bad.json -o x.h5");
    CHECK(r.code != 0);
    CHECK_THAT(r.out, Catch::Contains("params.Gm") && Catch::Contains("params.G_m"));
}

TEST_CASE("A JSON specification gives the same terrain as the flags", "[cli]") {
    TempDir d;
    std::ofstream(d / "spec.json")
        << R"({"method": "wm", "size": 64, "cell_size_m": 0.05, "seed": 3,
               "params": {"D": 2.3, "M": 16, "G_m": 1e-6}})";
    REQUIRE(run(d, "terrain generate --config spec.json -o a.asc").code == 0);
    REQUIRE(run(d, "terrain generate --method wm --size 64 --cell 0.05 --seed 3 --D 2.3 --M 16 "
                   "--G 1e-6 -o b.asc")
                .code == 0);
    CHECK(slurp(d / "a.asc") == slurp(d / "b.asc"));
    const Run help = run(d, "terrain generate --help");
    CHECK(help.code == 0);
    CHECK_THAT(help.out, Catch::Contains("m per pixel") && Catch::Contains("--relief"));
}

TEST_CASE("terrain analyze of a DEM with no-data outside its footprint counts only its cells",
          "[cli][nodata]") {
    // Luxembourg's DEM: 4316 valid cells of 8658 after reprojection. The closing used to count
    // the outside as high roughness (52 % low, 48 % high, 8284 cells counted).
    TempDir d;
    const Run r =
        run(d, "terrain analyze " + (test::data_dir() / "dem/luxembourg_elev.tif").string() +
                   " --json a.json --border 0");
    INFO(r.out);
    REQUIRE(r.code == 0);
    const auto j = nlohmann::json::parse(slurp(d / "a.json"));
    const auto valid = j["elevation_m"]["valid_cells"].get<std::int64_t>();
    CHECK(valid == 4316);
    CHECK(j["classes_pct"]["cells_counted"].get<std::int64_t>() == valid);
    CHECK(j["closed_classes_pct"]["cells_counted"].get<std::int64_t>() == valid);
    CHECK(j["closed_classes_pct"]["low"].get<double>() == Approx(100));
    CHECK_THAT(r.out, Catch::Contains("closed classes   low 100.00 %"));
}

TEST_CASE("analyze says which vehicle-scale figures a coarse DEM cannot give", "[terrain][dem]") {
    test::TempDir dir;
    const std::string lux = (test::data_dir() / "dem/luxembourg_elev.tif").string();
    auto r = test::run(dir, "terrain analyze " + lux + " --json a.json");
    INFO(r.out);
    REQUIRE(r.code == 0);
    CHECK_THAT(r.out, Catch::Contains("n/a detrended (3 m window), n/a band-limited (< 3 m)"));
    CHECK_THAT(r.out, Catch::Contains("note: cells of 772 m are too coarse for the vehicle-scale "
                                      "figures"));
    const json j = json::parse(io::read_text(dir / "a.json"));
    CHECK(j["rms_detrended_m"].is_null());
    CHECK(j["rms_band_limited_m"].is_null());
    CHECK(j["notes"].size() == 1);
    // Windows of two cells or more give the figures again, and no note about them.
    r = test::run(dir, "terrain analyze " + lux +
                           " --detrend-window 2000 --band-cutoff 2000 --json b.json --force");
    CHECK(r.code == 0);
    const json b = json::parse(io::read_text(dir / "b.json"));
    CHECK(b["rms_detrended_m"].get<double>() > 0);
    CHECK(b["rms_band_limited_m"].get<double>() > 0);
    // A window of the DEM resampled to 1 m: the figures are measured, and no note.
    r = test::run(dir, "terrain convert " +
                           (test::data_dir() / "dem/olinda_dem_utm25s.tif").string() +
                           " olinda_1m.tif --centre 293770,9115766 --size 200,150 --cell 1");
    INFO(r.out);
    REQUIRE(r.code == 0);
    CHECK_THAT(r.out, Catch::Contains("200 x 150 cells of 1 m by GDAL's warper (cubic)"));
    r = test::run(dir, "terrain analyze olinda_1m.tif --json c.json");
    CHECK(r.code == 0);
    CHECK_THAT(r.out, !Catch::Contains("note:"));
    const json c = json::parse(io::read_text(dir / "c.json"));
    CHECK(c["rms_detrended_m"].is_number());
    CHECK(c["notes"].empty());
    r = test::run(dir, "terrain convert olinda_1m.tif x.tif --size 10");
    CHECK(r.code == 2);
    CHECK_THAT(r.out, Catch::Contains("--size: only with --centre"));
    r = test::run(dir, "terrain convert olinda_1m.tif x.tif --bounds 1,2,3");
    CHECK(r.code == 2);
    CHECK_THAT(r.out, Catch::Contains("--bounds: give 4 numbers"));
}
