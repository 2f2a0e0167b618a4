// End-to-end runs of `ecoterra hydro ...` as a user types them.
#include "support/png_size.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

#include "ecoterra/json_util.hpp"
#include "ecoterra/terrain/io/raster_io.hpp"

#include <H5Cpp.h>
#include <catch2/catch.hpp>

#include <array>
#include <cstdio>
#include <fstream>
#include <sys/wait.h>

using namespace ecoterra;
using ecoterra::test::Run;
using ecoterra::test::run;
using ecoterra::test::TempDir;

namespace {
/// The first number on the last line.
double last_line_number(const std::string& out) {
    std::string s = out;
    while (!s.empty() && s.back() == '\n') s.pop_back();
    return std::stod(s.substr(s.rfind('\n') + 1));
}
} // namespace

TEST_CASE("hydro soil and et invocations work as written", "[cli][hydro]") {
    TempDir d;
    Run r = run(d, "hydro soil --sand 40 --silt 40 --clay 20 --json");
    REQUIRE(r.code == 0);
    const auto j = parse_json(r.out, "soil --json");
    CHECK(j["class"] == "loam");
    CHECK(j["porosity"].get<double>() == Approx(0.463));
    CHECK(j["field_capacity"].get<double>() == Approx(0.270));
    CHECK(j["wilting_point"].get<double>() == Approx(0.117));
    CHECK(j["ksat_m_per_s"].get<double>() == Approx(1.32e-2 / 3600));
    r = run(d, "hydro et --method fao56 --lat 50.8 --elev 100 --doy 187 --tmin 12.3 --tmax 21.5 "
               "--rhmin 63 --rhmax 84 --u2 2.078 --rs 22.07");
    REQUIRE(r.code == 0);
    CHECK(last_line_number(r.out) == Approx(3.88).margin(0.01));
    r = run(d, "hydro et --method penman-open-water --lat 50.8 --elev 100 --doy 187 --tmin 12.3 "
               "--tmax 21.5 --rhmin 63 --rhmax 84 --u2 2.078 --sunshine-hours 9.25");
    REQUIRE(r.code == 0);
    const double e0 = last_line_number(r.out);
    CHECK(e0 > 3.88); // open water evaporates more than the grass reference
    r = run(d, "hydro et --method fao56 --lat 50.8 --elev 100 --doy 187 --tmin 12.3 --tmax 21.5 "
               "--rhmin 63 --rhmax 84 --u2 2.078 --rs 22.07 --json");
    REQUIRE(r.code == 0);
    const auto e = parse_json(r.out, "et --json");
    for (const char* k :
         {"es_kpa", "ea_kpa", "delta_kpa_per_degc", "gamma_kpa_per_degc", "ra_mj_per_m2_day",
          "rso_mj_per_m2_day", "rnl_mj_per_m2_day", "rn_mj_per_m2_day"})
        CHECK(e.contains(k));
}

TEST_CASE("hydro pond writes depth and catchment ids with a closed budget", "[cli][hydro]") {
    TempDir d;
    REQUIRE(
        run(d,
            "terrain generate --method fbm --D 2.3 --size 128 --cell 1 --rms 2 --seed 3 -o dem.h5")
            .code == 0);
    const Run r = run(d, "hydro pond dem.h5 --depth-m 0.05 --routing d8 -o pond.h5");
    INFO(r.out);
    REQUIRE(r.code == 0);
    CHECK_THAT(r.out, Catch::Contains("left through edges"));
    H5::H5File f((d / "pond.h5").string(), H5F_ACC_RDONLY);
    for (const char* name : {"/surface_water_depth_m", "/catchment_id"}) {
        H5::DataSet ds = f.openDataSet(name);
        hsize_t dims[2];
        ds.getSpace().getSimpleExtentDims(dims);
        CHECK(dims[0] == 128);
        CHECK(dims[1] == 128);
    }
    double input = 0, stored = 0, lost = 0;
    H5::Group b = f.openGroup("/budget");
    b.openAttribute("input_m3").read(H5::PredType::NATIVE_DOUBLE, &input);
    b.openAttribute("stored_m3").read(H5::PredType::NATIVE_DOUBLE, &stored);
    b.openAttribute("left_through_edges_m3").read(H5::PredType::NATIVE_DOUBLE, &lost);
    CHECK(input == Approx(0.05 * 128 * 128));
    CHECK(stored + lost == Approx(input).epsilon(1e-12));
    // MFD routing sends water to the same depressions by other paths: same budget.
    REQUIRE(run(d, "hydro pond dem.h5 --depth-m 0.05 --routing mfd -o mfd.h5").code == 0);
    const Run bad = run(d, "hydro pond dem.h5 --depth-m -1 -o x.h5");
    CHECK(bad.code != 0);
    CHECK_THAT(bad.out, Catch::Contains("--depth-m"));
    const Run bad2 = run(d, "hydro pond dem.h5 --depth-m 0.1 --routing dinf -o x.h5");
    CHECK(bad2.code != 0);
    CHECK_THAT(bad2.out, Catch::Contains("--routing"));
    const Run bad3 = run(d, "hydro soil --sand 40 --silt 40 --clay 30");
    CHECK(bad3.code != 0);
    CHECK_THAT(bad3.out, Catch::Contains("110"));
}

TEST_CASE("hydro run writes snapshots and a budget that closes", "[cli][hydro]") {
    TempDir d;
    std::ofstream(d / "scene.json") << R"({
      "terrain": {"generate": {"method": "fbm", "size": 24, "cell_size_m": 2.0, "seed": 2,
                               "params": {"D": 2.3, "rms_m": 1.0}}},
      "soil": {"uniform": {"sand_pct": 40, "silt_pct": 40, "clay_pct": 20}},
      "vegetation": {"density": 0.5},
      "climate": {"preset": "humid_subtropical"},
      "hydrology": {"groundwater": true, "initial_water_table_depth_m": 2},
      "simulation": {"years": 1, "seed": 3, "snapshot_interval_days": 30}
    })";
    const Run r = run(d, "hydro run scene.json -o out.h5 --set simulation.years=1 --png pics");
    INFO(r.out);
    REQUIRE(r.code == 0);
    CHECK_THAT(r.out, Catch::Contains("cumulative residual"));
    H5::H5File f((d / "out.h5").string(), H5F_ACC_RDONLY);
    // 365 / 30 = 12 snapshots plus the last day.
    CHECK(f.nameExists("/snapshots/0012/soil_moisture"));
    CHECK(f.nameExists("/snapshots/0012/water_table_depth_m"));
    CHECK(f.nameExists("/soil/texture_class"));
    H5::DataSet rain = f.openDataSet("/series/daily/rain_mm");
    hsize_t n = 0;
    rain.getSpace().getSimpleExtentDims(&n);
    CHECK(n == 365);
    double rel = 1;
    f.openGroup("/series/daily")
        .openAttribute("cumulative_residual_relative")
        .read(H5::PredType::NATIVE_DOUBLE, &rel);
    CHECK(rel < 1e-9);
    for (const char* p : {"hillshade.png", "soil_moisture.png", "surface_water_depth.png"}) {
        INFO(p);
        CHECK(test::png_size(d / "pics" / p).first >= 600);
    }
    // Bad input: unknown keys, wrong types, a missing file; earlier output kept.
    const auto before = std::filesystem::file_size(d / "out.h5");
    Run bad = run(d, "hydro run scene.json -o out.h5 --set hydrology.groundwatr=true");
    CHECK(bad.code != 0);
    CHECK_THAT(bad.out, Catch::Contains("scene.json") && Catch::Contains("hydrology.groundwatr") &&
                            Catch::Contains("did you mean"));
    bad = run(d, "hydro run scene.json -o out.h5 --set soil.uniform.clay_pct=50");
    CHECK(bad.code != 0);
    CHECK_THAT(bad.out, Catch::Contains("sand + silt + clay"));
    bad = run(d, "hydro run missing.json -o out.h5");
    CHECK(bad.code != 0);
    CHECK_THAT(bad.out, Catch::Contains("missing.json"));
    bad = run(d, "hydro run scene.json -o out.h5 --force --set hydrology.aquifer_cell_factor=5");
    CHECK(bad.code == 2);
    CHECK_THAT(bad.out,
               Catch::Contains("hydrology.aquifer_cell_factor = 5") && Catch::Contains("24 x 24"));
    CHECK(std::filesystem::file_size(d / "out.h5") == before);
    // A divisor runs, on 4 x 4 aquifer cells of 6 x 6 terrain cells, and closes its budget.
    const Run coarse =
        run(d, "hydro run scene.json -o coarse.h5 --set hydrology.aquifer_cell_factor=6");
    INFO(coarse.out);
    REQUIRE(coarse.code == 0);
    H5::H5File fc((d / "coarse.h5").string(), H5F_ACC_RDONLY);
    fc.openGroup("/series/daily")
        .openAttribute("cumulative_residual_relative")
        .read(H5::PredType::NATIVE_DOUBLE, &rel);
    CHECK(rel < 1e-9);
}

TEST_CASE("The quickstart hydrology scene runs as written", "[cli][hydro]") {
    TempDir d;
    const std::string scene = (test::data_dir() / "scenes" / "hydro_quickstart.json").string();
    const Run r = run(d, "hydro run '" + scene + "' -o hydro.h5");
    INFO(r.out);
    REQUIRE(r.code == 0);
    CHECK(std::filesystem::exists(d / "hydro.h5"));
}
