#include "ecoterra/random.hpp"
#include "ecoterra/raster.hpp"

#include <catch2/catch.hpp>

using namespace ecoterra;

TEST_CASE("GridSpec converts between cells and world coordinates", "[raster]") {
    const GridSpec g{10, 5, 2.0, 100.0, -50.0};
    CHECK(g.x_of(0) == Approx(101.0));
    CHECK(g.y_of(4) == Approx(-41.0));
    CHECK(g.col_of(g.x_of(7)) == Approx(7.0));
    CHECK(g.row_of(g.y_of(3)) == Approx(3.0));
    CHECK(g.width_m() == Approx(20.0));
    CHECK(g.height_m() == Approx(10.0));
    CHECK(g.contains(9, 4));
    CHECK_FALSE(g.contains(10, 0));
    CHECK_FALSE(g.contains(0, -1));
    CHECK(g.contains_point(100.0, -50.0));
    CHECK_FALSE(g.contains_point(99.99, -45.0));
}

TEST_CASE("GridSpec rejects empty grids and bad cell sizes", "[raster][errors]") {
    CHECK_THROWS_WITH((GridSpec{0, 5, 1.0, 0, 0}.validate("test grid")),
                      Catch::Contains("test grid") && Catch::Contains("nx=0"));
    CHECK_THROWS_WITH((GridSpec{5, 5, -1.0, 0, 0}.validate("g")), Catch::Contains("-1"));
    CHECK_THROWS_AS((GridSpec{5, 5, std::nan(""), 0, 0}.validate("g")), InputError);
}

TEST_CASE("Raster rows run south to north", "[raster]") {
    RasterD r(GridSpec{3, 2, 1.0, 0, 0}, 0.0);
    r(2, 1) = 5.0; // column 2, northern row
    CHECK(r.row(1)[2] == 5.0);
    CHECK(r.array()(1, 2) == 5.0);
    auto [i, j] = r.cell_at(2.5, 1.5);
    CHECK(i == 2);
    CHECK(j == 1);
    CHECK(r.cell_at(3.5, 0.5)[0] == -1);
}

TEST_CASE("Bilinear sampling is exact on a plane and NaN outside or next to NODATA", "[raster]") {
    const GridSpec g{8, 6, 0.5, 10.0, 20.0};
    RasterD r(g);
    for (int j = 0; j < g.ny; ++j)
        for (int i = 0; i < g.nx; ++i) r(i, j) = 3.0 + 2.0 * g.x_of(i) - 0.5 * g.y_of(j);
    Rng rng(3);
    for (int k = 0; k < 50; ++k) {
        const double x = rng.uniform(g.x_of(0), g.x_of(g.nx - 1));
        const double y = rng.uniform(g.y_of(0), g.y_of(g.ny - 1));
        CHECK(r.sample_bilinear(x, y) == Approx(3.0 + 2.0 * x - 0.5 * y).epsilon(1e-12));
    }
    CHECK(std::isnan(r.sample_bilinear(9.0, 21.0)));
    r(3, 3) = std::nan("");
    CHECK(std::isnan(r.sample_bilinear(g.x_of(3.5), g.y_of(2.5))));
    CHECK(r.is_nodata(3, 3));
}

TEST_CASE("Neighbourhoods are clipped at the edges", "[raster]") {
    RasterD r(GridSpec{4, 4, 1.0, 0, 0});
    int corner = 0, interior = 0, vn_corner = 0;
    r.for_moore(0, 0, [&](int, int) { ++corner; });
    r.for_moore(2, 2, [&](int, int) { ++interior; });
    r.for_von_neumann(3, 3, [&](int, int) { ++vn_corner; });
    CHECK(corner == 3);
    CHECK(interior == 8);
    CHECK(vn_corner == 2);
}

TEST_CASE("Crops keep their georeference", "[raster]") {
    const GridSpec g{10, 10, 2.0, 0, 0};
    RasterD r(g);
    for (int j = 0; j < 10; ++j)
        for (int i = 0; i < 10; ++i) r(i, j) = i + 100 * j;
    const RasterD c = r.crop(3, 4, 5, 2);
    CHECK(c.nx() == 5);
    CHECK(c.ny() == 2);
    CHECK(c.grid().origin_x_m == Approx(6.0));
    CHECK(c.grid().origin_y_m == Approx(8.0));
    CHECK(c(0, 0) == 3 + 400);
    CHECK(c.sample_bilinear(c.grid().x_of(1), c.grid().y_of(1)) == Approx(4 + 500));
    CHECK_THROWS_AS(r.crop(8, 0, 5, 2), InputError);
}

TEST_CASE("Statistics ignore NODATA, an all-NODATA raster is refused", "[raster]") {
    RasterD r(GridSpec{2, 2, 1.0, 0, 0}, std::nan(""));
    CHECK_THROWS_WITH(require_valid_cells(r, "x.asc"),
                      Catch::Contains("x.asc") && Catch::Contains("NODATA"));
    r(0, 0) = 1.0;
    r(1, 1) = 3.0;
    const auto s = stats(r);
    CHECK(s.valid == 2);
    CHECK(s.mean == Approx(2.0));
    CHECK(s.stddev == Approx(1.0));
}

TEST_CASE("Grids too large for memory are refused before allocation", "[raster][errors]") {
    CHECK_THROWS_WITH(ensure_fits_in_memory(std::int64_t{1} << 40, 8.0, "grid 1048576x1048576"),
                      Catch::Contains("grid 1048576x1048576") && Catch::Contains("GiB"));
    CHECK_NOTHROW(ensure_fits_in_memory(1000, 8.0, "small"));
}

TEST_CASE("Random streams are reproducible and independent", "[random]") {
    Rng a(42, "x"), b(42, "x"), c(42, "y"), d(42, "x", 1);
    for (int k = 0; k < 100; ++k) {
        const auto va = a();
        CHECK(va == b());
        CHECK(va != c());
        CHECK(va != d());
    }
    Rng u(7);
    double s = 0, s2 = 0, n1 = 0, n2 = 0;
    const int N = 200000;
    for (int k = 0; k < N; ++k) {
        const double x = u.uniform();
        s += x;
        s2 += x * x;
        const double z = u.normal();
        n1 += z;
        n2 += z * z;
    }
    CHECK(s / N == Approx(0.5).margin(0.005));
    CHECK(s2 / N - 0.25 == Approx(1.0 / 12.0).margin(0.002));
    CHECK(n1 / N == Approx(0.0).margin(0.01));
    CHECK(n2 / N == Approx(1.0).margin(0.01));
    std::array<int, 5> counts{};
    for (int k = 0; k < 50000; ++k) ++counts[u.below(5)];
    for (int c5 : counts) CHECK(c5 == Approx(10000).margin(400));
}
