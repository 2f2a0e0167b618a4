#include "ecoterra/random.hpp"
#include "ecoterra/terrain/analysis.hpp"
#include "ecoterra/terrain/filters.hpp"
#include "ecoterra/terrain/io/raster_io.hpp"
#include "ecoterra/terrain/missions.hpp"
#include "ecoterra/terrain/roughness.hpp"
#include "ecoterra/terrain/spectral.hpp"
#include "support/temp_dir.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>

using namespace ecoterra;
using namespace ecoterra::terrain;

namespace {
RasterD plane(const GridSpec& g, double a, double b) {
    RasterD z(g);
    for (int j = 0; j < g.ny; ++j)
        for (int i = 0; i < g.nx; ++i) z(i, j) = a * g.x_of(i) + b * g.y_of(j);
    return z;
}
RasterD wave(const GridSpec& g, double amp, double wavelength) {
    RasterD z(g);
    for (int j = 0; j < g.ny; ++j)
        for (int i = 0; i < g.nx; ++i)
            z(i, j) = amp * std::sin(2 * std::numbers::pi * g.x_of(i) / wavelength);
    return z;
}
} // namespace

TEST_CASE("Moore gradient map of a plane (eqs 3-4)", "[roughness]") {
    const GridSpec g{20, 20, 0.05, 0, 0};
    const RasterD z = plane(g, 0.3, -0.4);
    const RasterD grad = max_gradient_map(z);
    // Edge neighbours give |0.3| and |0.4|; diagonals |0.3 +- 0.4| / sqrt 2 = 0.495 at most.
    const double expect = std::max({0.3, 0.4, 0.7 / std::sqrt(2.0)});
    CHECK(grad(10, 10) == Approx(expect));
    // At the south-west corner only (1,0), (0,1) and (1,1) exist: max(0.3, 0.4, 0.1 / sqrt 2).
    CHECK(grad(0, 0) == Approx(0.4));
}

TEST_CASE("Gradient classes use the paper's thresholds converted to slopes", "[roughness]") {
    CHECK(kDefaultLowThreshold == Approx(50 * 0.75 / 128));
    CHECK(kDefaultHighThreshold == Approx(140 * 0.75 / 128));
    RasterD grad(GridSpec{4, 1, 1.0, 0, 0});
    grad(0, 0) = 0.29;
    grad(1, 0) = 0.30;
    grad(2, 0) = 0.83;
    grad(3, 0) = std::nan("");
    const RasterU8 c = classify_gradient(grad);
    CHECK(c(0, 0) == 0);
    CHECK(c(1, 0) == 1);
    CHECK(c(2, 0) == 2);
    CHECK(c(3, 0) == 255);
    CHECK_THROWS_WITH(classify_gradient(grad, ClassThresholds{0.5, 0.2}),
                      Catch::Contains("low=0.5"));
}

TEST_CASE("Class areas leave out the border", "[roughness]") {
    RasterU8 c(GridSpec{100, 100, 0.1, 0, 0}, 2); // all high
    for (int j = 10; j < 90; ++j)
        for (int i = 10; i < 90; ++i) c(i, j) = i < 50 ? 0 : 1;
    const ClassAreas a = class_areas(c, 1.0); // 1 m = 10 cells
    CHECK(a.cells == 80 * 80);
    CHECK(a.low_pct == Approx(50.0));
    CHECK(a.semi_pct == Approx(50.0));
    CHECK(a.high_pct == Approx(0.0));
    CHECK_THROWS_WITH(class_areas(c, 6.0), Catch::Contains("border"));
}

TEST_CASE("Closing fills gaps narrower than the disk and keeps wide ones", "[roughness]") {
    RasterU8 c(GridSpec{60, 20, 0.05, 0, 0}, 0);
    for (int j = 0; j < 20; ++j) {
        for (int i = 10; i < 20; ++i) c(i, j) = 2;
        for (int i = 22; i < 32; ++i) c(i, j) = 2; // 2-cell gap at 20, 21
        for (int i = 50; i < 60; ++i) c(i, j) = 2; // 18-cell gap at 32..49
    }
    const RasterU8 closed = close_classes(c, 0.1); // radius 2 cells
    CHECK(closed(20, 10) == 2);
    CHECK(closed(21, 10) == 2);
    CHECK(closed(40, 10) == 0);
    CHECK(closed(5, 10) == 0);
    // Closing never shrinks the rough areas (extensive).
    for (int j = 0; j < 20; ++j)
        for (int i = 0; i < 60; ++i) CHECK(closed(i, j) >= c(i, j));
}

TEST_CASE("RMS roughness: plain, detrended and band-limited", "[roughness][verification]") {
    const GridSpec g{400, 120, 0.1, 0, 0};
    // A sine of amplitude A has RMS A / sqrt 2.
    const RasterD short_wave = wave(g, 0.05, 1.0);
    const RasterD long_wave = wave(g, 0.5, 10.0);
    RmsOptions opt; // 3 m window and 3 m cutoff
    CHECK(rms_roughness(short_wave, opt).rms_m == Approx(0.05 / std::sqrt(2.0)).epsilon(0.01));
    // The band filter passes the 1 m wave and removes the 10 m wave.
    CHECK(rms_roughness(short_wave, opt).rms_band_limited_m ==
          Approx(0.05 / std::sqrt(2.0)).epsilon(0.02));
    // The Gaussian low-pass passes exp(-2 pi^2 sigma^2 / lambda^2) of a wave: 94 % at 10 m, so
    // the high-pass residual is 6 % of the 10 m wave's RMS.
    const double sigma = gaussian_sigma_for_cutoff(3.0);
    const double pass10 = std::exp(-2 * std::pow(std::numbers::pi * sigma / 10.0, 2));
    CHECK(rms_roughness(long_wave, opt).rms_band_limited_m ==
          Approx(0.5 / std::sqrt(2.0) * (1 - pass10)).epsilon(0.03));
    // A tilted plane has no roughness once detrended, whatever its slope.
    const RmsResult p = rms_roughness(plane(g, 0.2, 0.1), opt);
    CHECK(p.rms_m > 1.0);
    CHECK(p.rms_detrended_m == Approx(0.0).margin(1e-9));
    CHECK(p.rms_band_limited_m == Approx(0.0).margin(1e-6));
}

TEST_CASE("Gaussian filter: 50 % transmission at the cutoff wavelength", "[filters]") {
    const GridSpec g{600, 8, 0.05, 0, 0};
    const double cutoff = 3.0;
    const RasterD z = wave(g, 1.0, cutoff);
    const RasterD f = gaussian_filter(z, gaussian_sigma_for_cutoff(cutoff));
    double num = 0, den = 0;
    for (int i = 150; i < 450; ++i) num += f(i, 4) * f(i, 4), den += z(i, 4) * z(i, 4);
    CHECK(std::sqrt(num / den) == Approx(0.5).margin(0.01));
    // NODATA stays NODATA and does not leak into its neighbours.
    RasterD h(GridSpec{9, 9, 1.0, 0, 0}, 2.0);
    h(4, 4) = std::nan("");
    const RasterD fh = gaussian_filter(h, 1.5);
    CHECK(std::isnan(fh(4, 4)));
    CHECK(fh(3, 4) == Approx(2.0));
    CHECK(box_mean(h, 3.0)(0, 0) == Approx(2.0));
}

TEST_CASE("Slope and aspect of planes", "[roughness]") {
    const GridSpec g{10, 10, 2.0, 0, 0};
    // z falls towards the east: downslope direction is east (90 deg).
    const auto east = slope_aspect(plane(g, -0.5, 0.0));
    CHECK(east.slope(5, 5) == Approx(0.5));
    CHECK(east.slope_deg(5, 5) == Approx(std::atan(0.5) * 180 / std::numbers::pi));
    CHECK(east.aspect_deg(5, 5) == Approx(90.0));
    const auto north = slope_aspect(plane(g, 0.0, -1.0));
    CHECK(north.aspect_deg(5, 5) == Approx(0.0).margin(1e-9));
    const auto sw = slope_aspect(plane(g, 1.0, 1.0)); // rises to the north-east
    CHECK(sw.aspect_deg(5, 5) == Approx(225.0));
    CHECK(std::isnan(slope_aspect(plane(g, 0, 0)).aspect_deg(3, 3)));
}

TEST_CASE("Missions start low, end low or semi, and keep their length and border", "[missions]") {
    const GridSpec g{400, 400, 0.125, 0, 0}; // 50 m square
    RasterU8 raw(g, 0);
    for (int j = 0; j < g.ny; ++j)
        for (int i = 0; i < g.nx; ++i)
            raw(i, j) = ((i / 40 + j / 40) % 3 == 0) ? 2 : ((i / 40 + j / 40) % 3 == 1 ? 1 : 0);
    MissionOptions opt;
    opt.count = 30;
    opt.seed = 4;
    const auto ms = plan_missions(raw, raw, opt);
    REQUIRE(ms.size() == 30);
    for (const auto& m : ms) {
        CHECK(raw(raw.cell_at(m.start_x_m, m.start_y_m)[0],
                  raw.cell_at(m.start_x_m, m.start_y_m)[1]) == 0);
        const auto gc = raw.cell_at(m.goal_x_m, m.goal_y_m);
        CHECK(raw(gc[0], gc[1]) <= 1);
        CHECK(std::hypot(m.goal_x_m - m.start_x_m, m.goal_y_m - m.start_y_m) == Approx(35.0));
        for (double v : {m.start_x_m, m.start_y_m, m.goal_x_m, m.goal_y_m}) {
            CHECK(v >= 5.0);
            CHECK(v <= 45.0);
        }
        CHECK(m.class_fraction[0] + m.class_fraction[1] + m.class_fraction[2] == Approx(1.0));
        CHECK(m.heading_deg >= 0.0);
        CHECK(m.heading_deg < 360.0);
    }
    const auto again = plan_missions(raw, raw, opt);
    CHECK(again[7].goal_x_m == ms[7].goal_x_m);
    RasterU8 rough(g, 2);
    CHECK_THROWS_WITH(plan_missions(rough, rough, opt), Catch::Contains("no low-roughness"));
    opt.length_m = 80;
    CHECK_THROWS_WITH(plan_missions(raw, raw, opt),
                      Catch::Contains("a 80 m mission does not fit in this 50 x 50 m terrain less "
                                      "its 5 m border"));
}

TEST_CASE("With allow_fewer, a terrain short of room gets the missions found, the same draws",
          "[missions]") {
    const GridSpec g{400, 400, 0.125, 0, 0}; // 50 m square
    RasterU8 raw(g, 0);
    for (int j = 0; j < g.ny; ++j)
        for (int i = 0; i < g.nx; ++i) raw(i, j) = ((i / 40 + j / 40) % 3 == 0) ? 2 : 0;
    for (std::uint64_t seed : {1u, 2u, 3u}) {
        MissionOptions opt;
        opt.count = 30;
        opt.seed = seed;
        const auto all = plan_missions(raw, raw, opt);
        opt.max_attempts_per_mission = 1; // 30 draws: some miss the border or a high goal
        CHECK_THROWS_WITH(plan_missions(raw, raw, opt), Catch::Contains("found only"));
        opt.allow_fewer = true;
        const auto few = plan_missions(raw, raw, opt);
        CHECK(few.size() > 0);
        CHECK(few.size() < all.size());
        for (std::size_t k = 0; k < few.size(); ++k) { // the first draws of the full plan
            CHECK(few[k].id == all[k].id);
            CHECK(few[k].start_x_m == all[k].start_x_m);
            CHECK(few[k].goal_y_m == all[k].goal_y_m);
        }
    }
    // Only a low patch in the middle: every 35 m line from it leaves the 5 m border.
    RasterU8 centre(g, 2);
    for (int j = 190; j < 210; ++j)
        for (int i = 190; i < 210; ++i) centre(i, j) = 0;
    MissionOptions opt;
    CHECK_THROWS_WITH(plan_missions(centre, centre, opt), Catch::Contains("found only 0 of 20"));
    opt.allow_fewer = true;
    CHECK(plan_missions(centre, centre, opt).empty());
    RasterU8 rough(g, 2);
    CHECK(plan_missions(rough, rough, opt).empty());
    opt.length_m = 80; // a mission that cannot fit is still an error
    CHECK_THROWS_WITH(plan_missions(centre, centre, opt), Catch::Contains("does not fit"));
}

namespace {
/// Valid cells of a class map inside a border of b cells.
std::int64_t valid_inside(const RasterU8& c, int b) {
    std::int64_t n = 0;
    for (int j = b; j < c.ny() - b; ++j)
        for (int i = b; i < c.nx() - b; ++i) n += c(i, j) < 3;
    return n;
}
/// Checks the no-data invariants of the classes and their closing.
void check_nodata_stays_out(const RasterD& z, const AnalysisOptions& opt) {
    const TerrainAnalysis a = analyze_terrain(z, opt);
    const int b = static_cast<int>(std::ceil(opt.border_m / z.cell_size() - 1e-9));
    std::int64_t nan_cells = 0;
    for (int j = 0; j < z.ny(); ++j)
        for (int i = 0; i < z.nx(); ++i) {
            const bool hole = std::isnan(z(i, j));
            nan_cells += hole;
            // No-data is no class before the closing and after it.
            CHECK((a.class_map(i, j) == 255) == hole);
            CHECK((a.closed_class_map(i, j) == 255) == hole);
            // The closing is extensive on the valid cells.
            if (!hole) CHECK(a.closed_class_map(i, j) >= a.class_map(i, j));
        }
    CHECK(a.classes.cells == valid_inside(a.class_map, b));
    CHECK(a.closed_classes.cells == a.classes.cells);
    CHECK(a.elevation.valid == z.size() - nan_cells);
    CHECK(a.classes.low_pct + a.classes.semi_pct + a.classes.high_pct == Approx(100));
    CHECK(a.closed_classes.low_pct + a.closed_classes.semi_pct + a.closed_classes.high_pct ==
          Approx(100));
    CHECK(std::isfinite(a.psd.slope));
    CHECK(std::isfinite(a.fd.dimension));
}
} // namespace

TEST_CASE("No-data stays out of every class and of the closing: shipped DEMs",
          "[roughness][nodata][data]") {
    for (const char* f : {"dem/luxembourg_elev.tif", "dem/olinda_dem_utm25s.tif"}) {
        INFO(f);
        std::vector<std::string> warnings;
        const RasterD z = io::read_raster(test::data_dir() / f, &warnings);
        AnalysisOptions opt;
        opt.border_m = 0;
        // Thresholds and a disk that give every class and a closing that changes the map at
        // these ~90-800 m cells.
        opt.thresholds.low = 0.01;
        opt.thresholds.high = 0.05;
        opt.closing_radius_m = 2.5 * z.cell_size();
        check_nodata_stays_out(z, opt);
        opt.closing_radius_m = 0;
        const TerrainAnalysis a = analyze_terrain(z, opt);
        CHECK(a.closed_classes.low_pct == Approx(a.classes.low_pct)); // radius 0: no change
    }
}

TEST_CASE("No-data stays out of every class and of the closing: fractal and white-noise DEMs "
          "with holes",
          "[roughness][nodata]") {
    const GridSpec g{96, 80, 0.05, 0, 0};
    for (std::uint64_t seed = 1; seed <= 6; ++seed) {
        INFO("seed " << seed);
        RasterD z = fbm_surface(g, FbmParams{0.2 + 0.1 * static_cast<double>(seed), 0.05}, seed);
        Rng rng(seed, "test.holes");
        if (seed % 2 == 0) // white noise instead of a fractal
            for (Eigen::Index k = 0; k < z.size(); ++k) z.data()[k] = rng.uniform(0, 0.05);
        // Holes: random disks, and on odd seeds an outer band of no-data (a DEM's footprint).
        for (int h = 0; h < 5; ++h) {
            const double cx = rng.uniform(0, g.width_m()), cy = rng.uniform(0, g.height_m());
            const double r = rng.uniform(0.05, 0.5);
            for (int j = 0; j < g.ny; ++j)
                for (int i = 0; i < g.nx; ++i)
                    if (std::hypot(g.x_of(i) - cx, g.y_of(j) - cy) < r) z(i, j) = std::nan("");
        }
        if (seed % 2 == 1)
            for (int j = 0; j < g.ny; ++j)
                for (int i = 0; i < g.nx; ++i)
                    if (i < 6 || j > g.ny - 8) z(i, j) = std::nan("");
        AnalysisOptions opt;
        opt.border_m = seed % 3 == 0 ? 0.0 : 0.25;
        opt.closing_radius_m = 0.1 * static_cast<double>(seed % 4);
        check_nodata_stays_out(z, opt);
    }
}

TEST_CASE("A smooth DEM with a hole stays smooth after the closing", "[roughness][nodata]") {
    // Before the fix the hole counted as high roughness and the closing spread it.
    RasterD z = plane(GridSpec{60, 60, 0.1, 0, 0}, 0.01, 0.0);
    for (int j = 20; j < 40; ++j)
        for (int i = 20; i < 40; ++i) z(i, j) = std::nan("");
    AnalysisOptions opt;
    opt.border_m = 0;
    opt.closing_radius_m = 0.5;
    const TerrainAnalysis a = analyze_terrain(z, opt);
    CHECK(a.classes.low_pct == Approx(100));
    CHECK(a.closed_classes.low_pct == Approx(100));
    CHECK(a.closed_classes.cells == 60 * 60 - 400);
    // Missions never cross the hole.
    MissionOptions m;
    m.count = 40;
    m.length_m = 3;
    m.border_m = 0.5;
    for (const auto& ms : plan_missions(z, opt, m))
        for (int k = 0; k <= 100; ++k) {
            const double t = k / 100.0;
            const auto c = z.cell_at(ms.start_x_m + t * (ms.goal_x_m - ms.start_x_m),
                                     ms.start_y_m + t * (ms.goal_y_m - ms.start_y_m));
            REQUIRE(c[0] >= 0);
            CHECK(!std::isnan(z(c[0], c[1])));
        }
}
