#include "support/temp_dir.hpp"

#include "ecoterra/io/atomic_file.hpp"
#include "ecoterra/json_util.hpp"
#include "ecoterra/terrain/io/raster_io.hpp"

#include <catch2/catch.hpp>

#include <fstream>

using namespace ecoterra;
using namespace ecoterra::terrain;
namespace tio = ecoterra::terrain::io;
using ecoterra::test::TempDir;

namespace {
RasterD sample_raster(bool with_nodata) {
    const GridSpec g{37, 23, 0.5, 1000.0, 2000.0};
    RasterD z(g);
    for (int j = 0; j < g.ny; ++j)
        for (int i = 0; i < g.nx; ++i) z(i, j) = 120.0 + 0.3 * i - 0.7 * j + 0.01 * i * j;
    if (with_nodata) z(5, 7) = std::nan("");
    return z;
}

void check_same(const RasterD& a, const RasterD& b, double tol) {
    REQUIRE(a.nx() == b.nx());
    REQUIRE(a.ny() == b.ny());
    CHECK(a.cell_size() == Approx(b.cell_size()));
    CHECK(a.grid().origin_x_m == Approx(b.grid().origin_x_m));
    CHECK(a.grid().origin_y_m == Approx(b.grid().origin_y_m));
    for (int j = 0; j < a.ny(); ++j)
        for (int i = 0; i < a.nx(); ++i) {
            if (std::isnan(a(i, j))) {
                CHECK(std::isnan(b(i, j)));
                continue;
            }
            CHECK(b(i, j) == Approx(a(i, j)).margin(tol));
        }
}
} // namespace

TEST_CASE("Raster formats round-trip with georeference and NODATA", "[io]") {
    TempDir dir;
    const RasterD z = sample_raster(true);
    SECTION("HDF5") {
        tio::write_raster(z, dir / "a.h5");
        check_same(z, tio::read_raster(dir / "a.h5"), 1e-4);
    }
    SECTION("ESRI ASCII") {
        tio::write_raster(z, dir / "a.asc");
        check_same(z, tio::read_raster(dir / "a.asc"), 1e-6);
        // The first data row is the north edge.
        std::ifstream in(dir / "a.asc");
        std::string line;
        for (int k = 0; k < 7; ++k) std::getline(in, line);
        CHECK(std::stod(line) == Approx(z(0, z.ny() - 1)));
    }
    SECTION("GeoTIFF") {
        tio::write_raster(z, dir / "a.tif");
        check_same(z, tio::read_raster(dir / "a.tif"), 1e-4);
    }
    SECTION("16-bit PNG with sidecar") {
        tio::write_raster(z, dir / "a.png");
        REQUIRE(std::filesystem::exists(dir / "a.png.json"));
        const auto s = stats(z);
        check_same(z, tio::read_raster(dir / "a.png"), (s.max - s.min) / 65534.0);
        const auto side = parse_json(ecoterra::io::read_text(dir / "a.png.json"), "sidecar");
        CHECK(side["unreal"]["z_scale_percent"].get<double>() == Approx((s.max - s.min) / 5.12));
        CHECK(side["unreal"]["xy_scale_percent"].get<double>() == Approx(50.0));
    }
    SECTION("OBJ") {
        tio::write_raster(z, dir / "a.obj");
        check_same(z, tio::read_raster(dir / "a.obj"), 1e-6);
    }
}

TEST_CASE("The paper's Unreal Z scale follows from the PNG sidecar", "[io]") {
    TempDir dir;
    RasterD z(GridSpec{1009, 2, 0.05, 0, 0}, 0.0);
    z(3, 1) = 3.84; // 3.84 m of relief at Z scale 0.75 %
    tio::write_png16(z, dir / "p.png", {});
    const auto side = parse_json(ecoterra::io::read_text(dir / "p.png.json"), "sidecar");
    CHECK(side["unreal"]["z_scale_percent"].get<double>() == Approx(0.75));
    CHECK(side["unreal"]["xy_scale_percent"].get<double>() == Approx(5.0));
    CHECK(tio::is_unreal_landscape_size(1009));
    CHECK(tio::is_unreal_landscape_size(2017));
    CHECK(tio::is_unreal_landscape_size(8129));
    CHECK_FALSE(tio::is_unreal_landscape_size(1024));
}

TEST_CASE("Gazebo PNGs are square with side 2^n + 1", "[io]") {
    TempDir dir;
    CHECK(tio::gazebo_side_for(513) == 513);
    CHECK(tio::gazebo_side_for(514) == 1025);
    CHECK(tio::gazebo_side_for(100) == 129);
    RasterD z(GridSpec{100, 100, 0.5, 0, 0});
    for (int j = 0; j < 100; ++j)
        for (int i = 0; i < 100; ++i) z(i, j) = 0.1 * i + 0.05 * j;
    std::vector<std::string> warn;
    tio::WriteOptions wo;
    wo.warnings = &warn;
    tio::write_raster(z, dir / "t.gazebo.png", wo);
    const RasterD back = tio::read_raster(dir / "t.gazebo.png");
    CHECK(back.nx() == 129);
    CHECK(back.ny() == 129);
    CHECK_FALSE(warn.empty());
    // The plane survives resampling: same corners.
    CHECK(back(0, 0) == Approx(z(0, 0)).margin(1e-3));
    CHECK(back(128, 128) == Approx(z(99, 99)).margin(1e-3));
    RasterD oblong(GridSpec{100, 50, 0.5, 0, 0}, 1.0);
    oblong(0, 0) = 2.0;
    CHECK_THROWS_WITH(tio::write_raster(oblong, dir / "o.gazebo.png"), Catch::Contains("square"));
}

TEST_CASE("Real DEMs from Debian packages read with their georeference", "[io][data]") {
    std::vector<std::string> none;
    const RasterD olinda = tio::read_raster(test::data_dir() / "dem/olinda_dem_utm25s.tif", &none);
    CHECK(none.empty()); // UTM: metres
    CHECK(olinda.nx() == 111);
    CHECK(olinda.ny() == 111);
    CHECK(olinda.cell_size() == Approx(89.994).epsilon(1e-4));
    const auto so = stats(olinda);
    CHECK(so.min == Approx(-1.0).margin(0.5));
    CHECK(so.max == Approx(88.0).margin(1.0));
    CHECK(so.mean == Approx(21.67).margin(0.05));
    std::vector<std::string> warn;
    const RasterD lux = tio::read_raster(test::data_dir() / "dem/luxembourg_elev.tif", &warn);
    // Geographic (0.00833 degrees, 95 x 90 cells, 4608 valid): reprojected to metres in the
    // UTM zone of its centre (6.1 E, 49.8 N: zone 32N). A degree of longitude there is
    // 111.3 cos(49.8 deg) = 71.9 km, of latitude 111.2 km: the cells are 600 to 927 m.
    REQUIRE(warn.size() == 1);
    CHECK_THAT(warn[0], Catch::Contains("reprojected") && Catch::Contains("UTM zone 32N"));
    CHECK_THAT(lux.crs_wkt(), Catch::Contains("UTM zone 32N"));
    CHECK(lux.cell_size() > 600);
    CHECK(lux.cell_size() < 927);
    // The footprint keeps its area: 4608 cells of 0.00833^2 degrees.
    const double area_km2 = 4608 * (0.0083333 * 71.9) * (0.0083333 * 111.2);
    const auto sl = stats(lux);
    CHECK(sl.valid * lux.cell_size() * lux.cell_size() / 1e6 == Approx(area_km2).epsilon(0.08));
    // Bilinear values stay within the source's range (141 .. 547 m; NoData -32768 became NaN).
    CHECK(sl.min >= 141);
    CHECK(sl.max <= 547);
    CHECK(sl.max > 500);
}

TEST_CASE("Malformed and missing files give errors naming the file", "[io][errors]") {
    TempDir dir;
    CHECK_THROWS_WITH(tio::read_raster(dir / "none.h5"),
                      Catch::Contains("none.h5") && Catch::Contains("no such file"));
    {
        std::ofstream(dir / "short.asc") << "ncols 3\nnrows 2\nxllcorner 0\nyllcorner 0\n"
                                            "cellsize 1\n1 2 3\n4 5\n";
        std::ofstream(dir / "word.asc") << "ncols 2\nnrows 1\nxllcorner 0\nyllcorner 0\n"
                                           "cellsize 1\n1 abc\n";
        std::ofstream(dir / "nocell.asc") << "ncols 2\nnrows 1\nxllcorner 0\nyllcorner 0\n1 2\n";
        std::ofstream(dir / "nodata.asc") << "ncols 2\nnrows 1\nxllcorner 0\nyllcorner 0\n"
                                             "cellsize 1\nnodata_value -1\n-1 -1\n";
        std::ofstream(dir / "fake.png") << "not a png";
        std::ofstream(dir / "fake.h5") << "not hdf5";
        std::ofstream(dir / "fake.tif") << "not a tiff";
    }
    CHECK_THROWS_WITH(tio::read_raster(dir / "short.asc"),
                      Catch::Contains("short.asc") && Catch::Contains("ends early"));
    CHECK_THROWS_WITH(tio::read_raster(dir / "word.asc"),
                      Catch::Contains("word.asc") && Catch::Contains("abc"));
    CHECK_THROWS_WITH(tio::read_raster(dir / "nocell.asc"), Catch::Contains("cellsize"));
    CHECK_THROWS_WITH(tio::read_raster(dir / "nodata.asc"), Catch::Contains("NODATA"));
    CHECK_THROWS_WITH(tio::read_raster(dir / "fake.png"), Catch::Contains("not a PNG"));
    CHECK_THROWS_WITH(tio::read_raster(dir / "fake.h5"), Catch::Contains("not an HDF5"));
    CHECK_THROWS_WITH(tio::read_raster(dir / "fake.tif"), Catch::Contains("fake.tif"));
    CHECK_THROWS_WITH(tio::format_from_path("x.xyz"), Catch::Contains(".xyz"));
    // Cell counts are whole numbers that fit a grid (fuzzing found 2e116 rows cast to int).
    for (const std::string count : {"2.5", "0", "-3", "1e116", "2147483648"}) {
        CAPTURE(count);
        std::ofstream(dir / "count.asc")
            << "ncols 2\nnrows " << count << "\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2\n";
        CHECK_THROWS_WITH(tio::read_raster(dir / "count.asc"),
                          Catch::Contains("count.asc") && Catch::Contains("nrows") &&
                              Catch::Contains("whole number of cells") && Catch::Contains(count));
    }
}

TEST_CASE("A failed write never damages an existing output", "[io][errors]") {
    TempDir dir;
    const RasterD z = sample_raster(false);
    tio::write_raster(z, dir / "keep.h5");
    const auto before = std::filesystem::file_size(dir / "keep.h5");
    RasterD empty(GridSpec{4, 4, 1.0, 0, 0}, std::nan(""));
    CHECK_THROWS(tio::write_raster(empty, dir / "keep.h5"));
    CHECK(std::filesystem::file_size(dir / "keep.h5") == before);
    check_same(z, tio::read_raster(dir / "keep.h5"), 1e-4);
    CHECK_THROWS_WITH(tio::write_raster(z, dir / "missing/x.h5"),
                      Catch::Contains("does not exist"));
    // No temporary files are left behind.
    int files = 0;
    for (const auto& e : std::filesystem::directory_iterator(dir.path())) (void)e, ++files;
    CHECK(files == 1);
}

TEST_CASE("Strict JSON keys suggest the nearest known key", "[json][errors]") {
    const auto j = nlohmann::json::parse(R"({"relif_m": 3})");
    CHECK_THROWS_WITH(require_known_keys(j, {"relief_m", "seed"}, "params"),
                      Catch::Contains("params.relif_m") && Catch::Contains("params.relief_m"));
    const auto k = nlohmann::json::parse(R"({"seed": -1, "x": "a"})");
    CHECK_THROWS_WITH(get_integer(k, "seed", 0, "", 0), Catch::Contains("seed = -1"));
    CHECK_THROWS_WITH(get_number(k, "x", 0, "p"), Catch::Contains("p.x must be a number"));
    CHECK_THROWS_WITH(parse_json("{", "scene.json"), Catch::Contains("scene.json"));
}
