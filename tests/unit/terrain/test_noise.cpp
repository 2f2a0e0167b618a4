#include "ecoterra/terrain/fractal_dimension.hpp"
#include "ecoterra/terrain/noise.hpp"
#include "ecoterra/terrain/spectral.hpp"

#include <catch2/catch.hpp>
#include <omp.h>

#include <cmath>

using namespace ecoterra;
using namespace ecoterra::terrain;

namespace {
/// Mean 1D PSD slope of the rows of z (profile PSD, periodogram averaged over rows, fitted over
/// [kmin, kmax] cycles/m in log-spaced bins).
double profile_psd_slope(const RasterD& z, double kmin, double kmax) {
    const int n = z.nx();
    const double h = z.cell_size();
    std::vector<double> p(n / 2 + 1, 0.0);
    for (int j = 0; j < z.ny(); ++j) {
        std::vector<double> row(z.row(j), z.row(j) + n);
        double mean = 0;
        for (double v : row) mean += v;
        mean /= n;
        for (int k = 1; k <= n / 2; ++k) {
            double re = 0, im = 0;
            for (int i = 0; i < n; ++i) {
                const double w = 0.5 - 0.5 * std::cos(2 * M_PI * i / (n - 1));
                re += w * (row[i] - mean) * std::cos(2 * M_PI * k * i / n);
                im -= w * (row[i] - mean) * std::sin(2 * M_PI * k * i / n);
            }
            p[k] += re * re + im * im;
        }
    }
    std::vector<double> lx, ly;
    const double width = n * h;
    for (double k0 = kmin; k0 < kmax; k0 *= 1.5) {
        double s = 0;
        int c = 0;
        for (int k = 1; k <= n / 2; ++k) {
            const double f = k / width;
            if (f >= k0 && f < 1.5 * k0) s += p[k], ++c;
        }
        if (c) lx.push_back(std::log10(k0 * std::sqrt(1.5))), ly.push_back(std::log10(s / c));
    }
    return fit_line(lx, ly)[1];
}
} // namespace

TEST_CASE("Perlin noise vanishes on the lattice and stays within about [-1, 1]", "[noise]") {
    const Perlin2D p(5);
    double mx = 0;
    for (int i = -20; i < 20; ++i)
        for (int j = -20; j < 20; ++j) {
            CHECK(p(i, j) == Approx(0.0).margin(1e-12));
            for (double f : {0.25, 0.5, 0.75}) mx = std::max(mx, std::abs(p(i + f, j + 0.5)));
        }
    CHECK(mx <= 1.05);
    CHECK(mx > 0.3);
    const Perlin2D q(6);
    CHECK(p(3.3, 4.7) != q(3.3, 4.7));
}

TEST_CASE("The gaussian surface has the requested RMS and isotropic exponential correlation",
          "[noise]") {
    const GridSpec g{600, 600, 0.25, 0, 0};
    GaussianSurfaceParams p;
    p.rms_m = 0.2;
    p.correlation_length_m = 2.0;
    p.lo_magnitude_m = 0.0;
    const RasterD z = gaussian_surface(g, p, 4);
    const auto s = stats(z);
    CHECK(s.stddev == Approx(0.2).epsilon(0.1));
    auto corr = [&](int di, int dj) {
        double c = 0, v = 0;
        for (int j = 0; j + dj < g.ny; ++j)
            for (int i = 0; i + di < g.nx; ++i) {
                c += (z(i, j) - s.mean) * (z(i + di, j + dj) - s.mean);
                v += (z(i, j) - s.mean) * (z(i, j) - s.mean);
            }
        return c / v;
    };
    // rho(r) = exp(-r / beta) along x, along y and along a diagonal (isotropy).
    CHECK(corr(4, 0) == Approx(std::exp(-1.0 / 2.0)).margin(0.05));
    CHECK(corr(0, 4) == Approx(std::exp(-1.0 / 2.0)).margin(0.05));
    CHECK(corr(6, 8) == Approx(std::exp(-2.5 / 2.0)).margin(0.05));
    CHECK(corr(16, 0) == Approx(std::exp(-4.0 / 2.0)).margin(0.05));
}

TEST_CASE("Variable roughness follows Van Deussen's Omega^-2, mavs_compat gives Omega^-3",
          "[noise][verification]") {
    const GridSpec g{512, 512, 0.25, 0, 0};
    VariableSurfaceParams p;
    p.envelope_wavelength_m = 0; // the envelope modulates amplitude; leave it out of the slope
    const auto wl = variable_octave_wavelengths(g, p);
    CHECK(wl.front() == Approx(0.5));
    CHECK(wl.back() == Approx(32.0)); // min(100 m, 128 m / 4)
    const double kmin = 1.0 / wl.back(), kmax = 0.5 / wl.front();
    const double s2 = profile_psd_slope(variable_surface(g, p, 3), 2 * kmin, kmax / 2);
    p.mavs_compat = true;
    const double s3 = profile_psd_slope(variable_surface(g, p, 3), 2 * kmin, kmax / 2);
    CHECK(s2 == Approx(-2.0).margin(0.25));
    CHECK(s3 == Approx(-3.0).margin(0.25));
}

TEST_CASE("Noise surfaces do not depend on the thread count", "[noise][determinism]") {
    const GridSpec g{257, 129, 0.25, 0, 0};
    const int saved = omp_get_max_threads();
    omp_set_num_threads(1);
    const RasterD a1 = variable_surface(g, VariableSurfaceParams{}, 9);
    const RasterD b1 = gaussian_surface(g, GaussianSurfaceParams{}, 9);
    const RasterD c1 = perlin_surface(g, PerlinSurfaceParams{}, 9);
    omp_set_num_threads(2);
    const RasterD a2 = variable_surface(g, VariableSurfaceParams{}, 9);
    const RasterD b2 = gaussian_surface(g, GaussianSurfaceParams{}, 9);
    const RasterD c2 = perlin_surface(g, PerlinSurfaceParams{}, 9);
    omp_set_num_threads(saved);
    CHECK((a1.array() == a2.array()).all());
    CHECK((b1.array() == b2.array()).all());
    CHECK((c1.array() == c2.array()).all());
}

TEST_CASE("Noise parameters are checked", "[noise][errors]") {
    PerlinSurfaceParams p;
    p.hi_wavelength_m = 0;
    CHECK_THROWS_WITH(validate(p), Catch::Contains("wavelength"));
    GaussianSurfaceParams q;
    q.correlation_length_m = -2;
    CHECK_THROWS_WITH(validate(q), Catch::Contains("correlation length") && Catch::Contains("-2"));
    VariableSurfaceParams v;
    v.spectral_exponent = 9;
    CHECK_THROWS_WITH(validate(v), Catch::Contains("spectral exponent"));
}

TEST_CASE("Spectral fBm has the PSD slope and dimension of its Hurst exponent",
          "[spectral][verification]") {
    const GridSpec g{512, 512, 0.5, 0, 0};
    // The variogram estimate is pulled towards 2.5 (about +0.05 at D = 2.2, -0.04 at 2.8),
    // so it is averaged over seeds as the issue asks.
    for (double D : {2.2, 2.5, 2.8}) {
        double fd = 0;
        const int seeds = 4;
        for (int s = 1; s <= seeds; ++s) {
            const RasterD z = fbm_surface(g, FbmParams::from_dimension(D, 0.7), s);
            CHECK(stats(z).stddev == Approx(0.7));
            CAPTURE(D, s);
            CHECK(radial_psd(z).slope == Approx(-(8 - 2 * D)).margin(0.08));
            fd += fractal_dimension(z).dimension;
        }
        CHECK(fd / seeds == Approx(D).margin(0.07));
    }
}

TEST_CASE("Spectral fBm tiles: the seam is no rougher than the interior", "[spectral]") {
    const GridSpec g{256, 256, 1.0, 0, 0};
    const RasterD z = fbm_surface(g, FbmParams{0.8, 1.0}, 2);
    double seam = 0, inner = 0;
    for (int j = 0; j < g.ny; ++j) {
        seam += std::abs(z(0, j) - z(g.nx - 1, j));
        inner += std::abs(z(100, j) - z(99, j));
    }
    CHECK(seam / inner == Approx(1.0).margin(0.3));
    CHECK_THROWS_WITH(FbmParams::from_dimension(3.0), Catch::Contains("(2, 3)"));
    CHECK_THROWS_AS(fbm_surface(g, FbmParams{0.5, -1.0}, 1), InputError);
}
