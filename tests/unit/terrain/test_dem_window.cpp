// Windows of DEMs on new grids (terrain::io::read_dem). The resampled values are checked against
// interpolations computed here from the source cells, over many seeded windows and cell sizes,
// on white-noise and smooth fields; reprojection against PROJ's inverse transformation; the
// whole against the gdalwarp program, the independent consumer of the same options.
#include "support/temp_dir.hpp"

#include "ecoterra/terrain/io/dem_window.hpp"
#include "ecoterra/terrain/io/raster_io.hpp"

#include <catch2/catch.hpp>
#include <ogr_srs_api.h>

#include <cmath>
#include <cstdlib>
#include <random>

using namespace ecoterra;
namespace tio = ecoterra::terrain::io;
using ecoterra::test::TempDir;

namespace {

/// A projected DEM (Olinda's UTM 25S system) of `nx` x `ny` cells of `cell` m: white noise,
/// or the plane 40 + 0.01 x - 0.02 y (relative to its corner) when `plane`.
RasterD source_dem(int nx, int ny, double cell, bool plane, std::uint64_t seed) {
    static const std::string wkt =
        tio::read_raster(test::data_dir() / "dem/olinda_dem_utm25s.tif").crs_wkt();
    RasterD z(GridSpec{nx, ny, cell, 288000.0, 9110000.0});
    z.set_crs_wkt(wkt);
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0, 50);
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i)
            z(i, j) = plane ? 40 + 0.01 * (i + 0.5) * cell - 0.02 * (j + 0.5) * cell : u(rng);
    return z;
}

/// Bilinear interpolation between the source's cell centres at (x, y); NaN within half a cell
/// of its edge.
double bilinear(const RasterD& s, double x, double y) {
    const double c = s.grid().col_of(x), r = s.grid().row_of(y);
    const int i = static_cast<int>(std::floor(c)), j = static_cast<int>(std::floor(r));
    if (i < 0 || j < 0 || i + 1 >= s.nx() || j + 1 >= s.ny()) return std::nan("");
    const double fx = c - i, fy = r - j;
    return (1 - fx) * (1 - fy) * s(i, j) + fx * (1 - fy) * s(i + 1, j) +
           (1 - fx) * fy * s(i, j + 1) + fx * fy * s(i + 1, j + 1);
}

} // namespace

TEST_CASE("DEM windows resample as bilinear interpolation of the source cells", "[io][dem]") {
    TempDir dir;
    std::mt19937_64 rng(20261126);
    int checked = 0;
    for (int trial = 0; trial < 24; ++trial) {
        const double cell = 30.0;
        const RasterD src = source_dem(40, 30, cell, false, 100 + trial);
        const auto path = dir.path() / ("src" + std::to_string(trial) + ".tif");
        tio::write_geotiff(src, path);
        // float32 in the file: compare with what the file holds
        const RasterD held = tio::read_raster(path);
        std::uniform_real_distribution<double> u(0, 1);
        tio::DemRequest req;
        req.path = path;
        req.resampling = "bilinear";
        req.cell_m = std::vector<double>{1, 2.5, 7, 13.3, 30}[trial % 5];
        const double x0 = 288000 + 2 * cell + u(rng) * 20 * cell;
        const double y0 = 9110000 + 2 * cell + u(rng) * 15 * cell;
        const double w = (0.5 + u(rng) * 5) * cell, h = (0.5 + u(rng) * 5) * cell;
        req.window.bounds = std::array<double, 4>{x0, y0, x0 + w, y0 + h};
        const tio::DemRead d = tio::read_dem(req);
        CAPTURE(trial, req.cell_m, x0, y0, w, h);
        REQUIRE(d.z.cell_size() == Approx(req.cell_m));
        CHECK(d.z.grid().origin_x_m == Approx(x0).epsilon(1e-12));
        CHECK(d.z.grid().origin_y_m == Approx(y0).epsilon(1e-12));
        CHECK(d.z.nx() == std::max(1L, std::lround(w / req.cell_m)));
        CHECK(d.z.ny() == std::max(1L, std::lround(h / req.cell_m)));
        CHECK(d.resampling == "bilinear");
        CHECK(d.record["no_data_cells"] == 0);
        for (int j = 0; j < d.z.ny(); ++j)
            for (int i = 0; i < d.z.nx(); ++i) {
                const double want = bilinear(held, d.z.grid().x_of(i), d.z.grid().y_of(j));
                REQUIRE(!std::isnan(want));
                REQUIRE(d.z(i, j) == Approx(want).margin(1e-6));
                ++checked;
            }
    }
    CHECK(checked > 10000);
}

TEST_CASE("DEM windows: cubic keeps a plane, average gives block means, nearest copies",
          "[io][dem]") {
    TempDir dir;
    const RasterD plane = source_dem(30, 20, 10.0, true, 1);
    const auto ppath = dir.path() / "plane.tif";
    tio::write_geotiff(plane, ppath);
    for (const double cell : {0.5, 1.0, 3.0, 10.0}) {
        tio::DemRequest req;
        req.path = ppath;
        req.cell_m = cell;
        req.window.bounds = std::array<double, 4>{288050, 9110040, 288210, 9110150};
        const tio::DemRead d = tio::read_dem(req);
        CHECK(d.resampling == "cubic"); // auto, refining or keeping the cell
        for (int j = 0; j < d.z.ny(); ++j)
            for (int i = 0; i < d.z.nx(); ++i) {
                const double x = d.z.grid().x_of(i) - 288000, y = d.z.grid().y_of(j) - 9110000;
                REQUIRE(d.z(i, j) == Approx(40 + 0.01 * x - 0.02 * y).margin(1e-4));
            }
    }
    const RasterD noise = source_dem(36, 24, 5.0, false, 7);
    const auto npath = dir.path() / "noise.tif";
    tio::write_geotiff(noise, npath);
    const RasterD held = tio::read_raster(npath);
    for (const int k : {2, 3, 4}) {
        tio::DemRequest req;
        req.path = npath;
        req.cell_m = 5.0 * k;
        req.window.pixels = std::array<double, 4>{0, 0, 36.0 - 36 % k, 24.0 - 24 % k};
        const tio::DemRead d = tio::read_dem(req);
        CHECK(d.resampling == "average"); // auto, coarsening
        REQUIRE(d.z.nx() == 36 / k);
        for (int j = 0; j < d.z.ny(); ++j)
            for (int i = 0; i < d.z.nx(); ++i) {
                // pixel rows count from the north: the window's south row is row 24 - 24 % k
                const int j0 = 24 % k + j * k;
                double sum = 0;
                for (int b = 0; b < k; ++b)
                    for (int a = 0; a < k; ++a) sum += held(i * k + a, j0 + b);
                REQUIRE(d.z(i, j) == Approx(sum / (k * k)).margin(1e-4));
            }
    }
    tio::DemRequest req;
    req.path = npath;
    req.resampling = "nearest";
    req.window.pixels = std::array<double, 4>{3, 5, 10, 7};
    const tio::DemRead d = tio::read_dem(req);
    REQUIRE(d.z.nx() == 10);
    REQUIRE(d.z.ny() == 7);
    CHECK(d.z.cell_size() == 5.0);
    for (int j = 0; j < 7; ++j)
        for (int i = 0; i < 10; ++i) REQUIRE(d.z(i, j) == held(3 + i, 24 - 5 - 7 + j));
    // The same pixels as bounds give the same raster.
    tio::DemRequest by_bounds = req;
    by_bounds.window.pixels.reset();
    by_bounds.window.bounds = std::array<double, 4>{288015, 9110060, 288065, 9110095};
    const tio::DemRead e = tio::read_dem(by_bounds);
    REQUIRE(e.z.grid() == d.z.grid());
    for (std::int64_t k = 0; k < d.z.size(); ++k) REQUIRE(e.z.data()[k] == d.z.data()[k]);
}

TEST_CASE("DEM windows by centre and size, and files in every format", "[io][dem]") {
    TempDir dir;
    const RasterD src = source_dem(50, 50, 20.0, true, 3);
    for (const char* name : {"dem.tif", "dem.asc", "dem.h5"}) {
        const auto path = dir.path() / name;
        tio::write_raster(src, path);
        tio::DemRequest req;
        req.path = path;
        req.cell_m = 1;
        req.window.centre = std::array<double, 2>{288500, 9110400};
        req.window.size_m = {101, 60};
        const tio::DemRead d = tio::read_dem(req);
        CAPTURE(name);
        REQUIRE(d.z.nx() == 101);
        REQUIRE(d.z.ny() == 60);
        CHECK(d.z.grid().origin_x_m + 0.5 * d.z.grid().width_m() == Approx(288500));
        CHECK(d.z.grid().origin_y_m + 0.5 * d.z.grid().height_m() == Approx(9110400));
        const double mid = d.z(50, 30);
        CHECK(mid == Approx(40 + 0.01 * 500 - 0.02 * 400.5).margin(1e-3));
    }
}

TEST_CASE("A geographic DEM's window lands where PROJ puts it, in its UTM zone", "[io][dem]") {
    tio::DemRequest req;
    req.path = test::data_dir() / "dem/luxembourg_elev.tif";
    req.cell_m = 2;
    req.window.centre = std::array<double, 2>{6.13, 49.61};
    req.window.size_m = {120, 80};
    const tio::DemRead d = tio::read_dem(req);
    CHECK(d.crs == "EPSG:32632");
    CHECK(d.record["epsg"] == 32632);
    CHECK(d.record["reprojected"] == true);
    REQUIRE(d.z.nx() == 60);
    REQUIRE(d.z.ny() == 40);
    // Back to degrees with PROJ: the window's centre is the requested point.
    OGRSpatialReferenceH utm = OSRNewSpatialReference(nullptr),
                         wgs = OSRNewSpatialReference(nullptr);
    REQUIRE(OSRImportFromEPSG(utm, 32632) == OGRERR_NONE);
    REQUIRE(OSRImportFromEPSG(wgs, 4326) == OGRERR_NONE);
    OSRSetAxisMappingStrategy(utm, OAMS_TRADITIONAL_GIS_ORDER);
    OSRSetAxisMappingStrategy(wgs, OAMS_TRADITIONAL_GIS_ORDER);
    OGRCoordinateTransformationH ct = OCTNewCoordinateTransformation(utm, wgs);
    double x = d.z.grid().origin_x_m + 60, y = d.z.grid().origin_y_m + 40;
    REQUIRE(OCTTransform(ct, 1, &x, &y, nullptr));
    CHECK(x == Approx(6.13).margin(1e-7));
    CHECK(y == Approx(49.61).margin(1e-7));
    OCTDestroyCoordinateTransformation(ct);
    OSRDestroySpatialReference(utm);
    OSRDestroySpatialReference(wgs);
    for (std::int64_t k = 0; k < d.z.size(); ++k) {
        REQUIRE(d.z.data()[k] >= 141); // the source's range
        REQUIRE(d.z.data()[k] <= 547);
    }
}

TEST_CASE("DEM windows agree with the gdalwarp program", "[io][dem]") {
    // gdal-bin is one of the packages scripts/install-deps.sh installs.
    REQUIRE(std::system("gdalwarp --version > /dev/null 2>&1") == 0);
    TempDir dir;
    struct Case {
        std::string file, crs_args;
        tio::DemRequest req;
    };
    std::vector<Case> cases(3);
    cases[0].file = "dem/olinda_dem_utm25s.tif";
    cases[0].req.window.bounds = std::array<double, 4>{290000, 9114000, 290300, 9114200};
    cases[0].req.cell_m = 2;
    cases[1].file = "dem/olinda_dem_utm25s.tif";
    cases[1].req.window.bounds = std::array<double, 4>{289000, 9112000, 297000, 9119000};
    cases[1].req.cell_m = 250;
    cases[2].file = "dem/luxembourg_elev.tif";
    cases[2].req.window.bounds = std::array<double, 4>{6.0, 49.6, 6.02, 49.62};
    cases[2].req.cell_m = 10;
    cases[2].crs_args = " -t_srs EPSG:32632";
    for (auto& c : cases) {
        c.req.path = test::data_dir() / c.file;
        const tio::DemRead d = tio::read_dem(c.req);
        const auto& b = d.record["bounds_m"];
        const auto out = dir.path() / "gdalwarp.tif";
        std::filesystem::remove(out);
        char cmd[1024];
        std::snprintf(cmd, sizeof cmd,
                      "gdalwarp -q -te %.10g %.10g %.10g %.10g -ts %d %d -r %s -ot Float64 "
                      "-dstnodata nan -et 0%s '%s' '%s'",
                      b[0].get<double>(), b[1].get<double>(), b[2].get<double>(),
                      b[3].get<double>(), d.z.nx(), d.z.ny(), d.resampling.c_str(),
                      c.crs_args.c_str(), c.req.path.c_str(), out.c_str());
        REQUIRE(std::system(cmd) == 0);
        const RasterD g = tio::read_raster(out);
        CAPTURE(c.file, d.resampling);
        REQUIRE(g.grid().nx == d.z.nx());
        REQUIRE(g.grid().ny == d.z.ny());
        CHECK(g.cell_size() == Approx(d.z.cell_size()));
        for (std::int64_t k = 0; k < g.size(); ++k)
            REQUIRE(g.data()[k] == Approx(d.z.data()[k]).margin(1e-3)); // float32 in the file
    }
}

TEST_CASE("DEM window errors name the file, key and value", "[io][dem][errors]") {
    TempDir dir;
    const auto path = dir.path() / "dem.tif";
    tio::write_geotiff(source_dem(20, 20, 10.0, true, 1), path);
    auto fails = [&](auto edit, const std::string& words) {
        tio::DemRequest req;
        req.path = path;
        edit(req);
        CAPTURE(words);
        CHECK_THROWS_WITH(tio::read_dem(req), Catch::Contains(words));
    };
    fails(
        [](tio::DemRequest& r) {
            r.window.bounds = std::array<double, 4>{288100, 9110000, 288300, 9110100};
        },
        "terrain.window [288100, 9110000, 288300, 9110100] reaches outside");
    fails(
        [](tio::DemRequest& r) {
            r.window.bounds = std::array<double, 4>{288100, 9110000, 288050, 9110100};
        },
        "terrain.window.bounds = [288100, 9110000, 288050, 9110100]: give [x_min");
    fails(
        [](tio::DemRequest& r) {
            r.window.pixels = std::array<double, 4>{15, 0, 10, 5};
        },
        "terrain.window.pixels = [15, 0, 10, 5]: give [column, row, columns, rows] within the "
        "DEM's 20 x 20");
    fails(
        [](tio::DemRequest& r) {
            r.window.centre = std::array<double, 2>{288100, 9110100};
            r.window.size_m = {-5, 10};
        },
        "positive width");
    fails([](tio::DemRequest& r) { r.resampling = "sinc"; },
          "terrain.resampling = 'sinc': not a method");
    fails([](tio::DemRequest& r) { r.cell_m = -1; }, "terrain.cell_m = -1");
    fails([](tio::DemRequest& r) { r.crs = "EPSG:4326"; }, "is geographic (degrees)");
    fails([](tio::DemRequest& r) { r.crs = "not a crs"; },
          "terrain.crs = 'not a crs': not a coordinate system");
    fails([](tio::DemRequest& r) { r.cell_m = 1e-4; },
          "the window would hold 2000000 x 2000000 cells");
    fails([&](tio::DemRequest& r) { r.path = dir.path() / "missing.tif"; },
          "missing.tif: no such file");
    fails([](tio::DemRequest& r) { r.crs = "EPSG:2227"; }, "counts in units of 0.3048");
}

TEST_CASE("A DEM window over NODATA says how many cells have no data", "[io][dem]") {
    TempDir dir;
    RasterD src = source_dem(20, 20, 10.0, true, 1);
    for (int j = 0; j < 20; ++j)
        for (int i = 0; i < 5; ++i) src(i, j) = std::nan("");
    const auto path = dir.path() / "dem.tif";
    tio::write_geotiff(src, path);
    tio::DemRequest req;
    req.path = path;
    req.resampling = "nearest";
    req.window.pixels = std::array<double, 4>{0, 0, 10, 10};
    std::vector<std::string> notes;
    const tio::DemRead d = tio::read_dem(req, &notes);
    CHECK(d.record["no_data_cells"] == 50);
    REQUIRE(notes.size() == 1);
    CHECK_THAT(notes[0], Catch::Contains("50 of 100 cells of the window have no data"));
    req.window.pixels = std::array<double, 4>{0, 0, 5, 10};
    CHECK_THROWS_WITH(tio::read_dem(req), Catch::Contains("every cell is NODATA"));
}
