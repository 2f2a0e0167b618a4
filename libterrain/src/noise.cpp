#include "ecoterra/terrain/noise.hpp"

#include "ecoterra/progress.hpp"
#include "ecoterra/random.hpp"
#include "ecoterra/terrain/fft.hpp"

#include <atomic>
#include <cmath>
#include <numbers>
#include <numeric>
#include <sstream>
#include <vector>

namespace ecoterra::terrain {

namespace {

/// MAVS algorithm 1 uses frequency 1 / (1.25 pi lambda) and magnitude 4 a for the high band.
constexpr double kMavsHiWavelengthFactor = 1.25 * std::numbers::pi;
constexpr double kMavsHiMagnitudeFactor = 4.0;
/// sqrt(2) brings 2D gradient noise with unit gradients from about +-0.71 to about +-1.
constexpr double kPerlinScale = std::numbers::sqrt2;
/// Padding of the gaussian surface's FFT grid, in correlation lengths (correlation e^-8 there).
constexpr double kGaussianPadLengths = 8.0;

void require_positive(double v, const char* name) {
    if (!(v > 0.0) || !std::isfinite(v))
        throw InputError(std::string(name) + " must be > 0, got " + format_number(v));
}
void require_nonnegative(double v, const char* name) {
    if (!(v >= 0.0) || !std::isfinite(v))
        throw InputError(std::string(name) + " must be >= 0, got " + format_number(v));
}

double fade(double t) {
    return t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
}

/// Fills a raster by evaluating f(x, y) at every cell centre, rows in parallel.
template <class F>
RasterD evaluate(const GridSpec& grid, F&& f) {
    grid.validate("surface grid");
    ensure_fits_in_memory(grid.size(), 8.0, "surface grid");
    RasterD z(grid, 0.0);
    std::atomic<int> done{0};
#pragma omp parallel for schedule(static)
    for (int j = 0; j < grid.ny; ++j) {
        const double y = grid.y_of(j);
        double* row = z.row(j);
        for (int i = 0; i < grid.nx; ++i) row[i] = f(grid.x_of(i), y);
        report_progress(static_cast<double>(++done) / grid.ny);
    }
    return z;
}

} // namespace

Perlin2D::Perlin2D(std::uint64_t seed, std::uint64_t stream) {
    Rng rng(seed, "terrain.perlin", stream);
    std::array<std::uint8_t, 256> p{};
    std::iota(p.begin(), p.end(), 0);
    for (int i = 255; i > 0; --i) std::swap(p[i], p[rng.below(static_cast<std::uint64_t>(i) + 1)]);
    for (int i = 0; i < 512; ++i) m_perm[i] = p[i & 255];
}

double Perlin2D::operator()(double x, double y) const {
    static constexpr double s = std::numbers::sqrt2 / 2.0;
    static constexpr double gx[8] = {1, -1, 0, 0, s, -s, s, -s};
    static constexpr double gy[8] = {0, 0, 1, -1, s, s, -s, -s};
    const double fx = std::floor(x), fy = std::floor(y);
    const int X = static_cast<int>(static_cast<std::int64_t>(fx) & 255);
    const int Y = static_cast<int>(static_cast<std::int64_t>(fy) & 255);
    const double dx = x - fx, dy = y - fy;
    auto grad = [&](int hx, int hy, double px, double py) {
        const int h = m_perm[m_perm[hx] + hy] & 7;
        return gx[h] * px + gy[h] * py;
    };
    const double n00 = grad(X, Y, dx, dy);
    const double n10 = grad(X + 1, Y, dx - 1, dy);
    const double n01 = grad(X, Y + 1, dx, dy - 1);
    const double n11 = grad(X + 1, Y + 1, dx - 1, dy - 1);
    const double u = fade(dx), v = fade(dy);
    const double a = n00 + u * (n10 - n00);
    const double b = n01 + u * (n11 - n01);
    return kPerlinScale * (a + v * (b - a));
}

void validate(const PerlinSurfaceParams& p) {
    require_positive(p.hi_wavelength_m, "perlin: high-frequency wavelength (m)");
    require_positive(p.lo_wavelength_m, "perlin: low-frequency wavelength (m)");
    require_nonnegative(p.hi_magnitude_m, "perlin: high-frequency magnitude (m)");
    require_nonnegative(p.lo_magnitude_m, "perlin: low-frequency magnitude (m)");
}

void validate(const GaussianSurfaceParams& p) {
    require_nonnegative(p.rms_m, "gaussian: RMS height (m)");
    require_positive(p.correlation_length_m, "gaussian: correlation length (m)");
    require_positive(p.lo_wavelength_m, "gaussian: low-frequency wavelength (m)");
    require_nonnegative(p.lo_magnitude_m, "gaussian: low-frequency magnitude (m)");
}

void validate(const VariableSurfaceParams& p) {
    require_nonnegative(p.hi_magnitude_m, "variable: high-frequency magnitude (m)");
    require_positive(p.max_wavelength_m, "variable: maximum wavelength (m)");
    require_nonnegative(p.envelope_wavelength_m, "variable: envelope wavelength (m)");
    if (!std::isfinite(p.spectral_exponent) || p.spectral_exponent < 0.0 ||
        p.spectral_exponent > 6.0)
        throw InputError("variable: spectral exponent must be in [0, 6], got " +
                         format_number(p.spectral_exponent));
}

RasterD perlin_surface(const GridSpec& grid, const PerlinSurfaceParams& p, std::uint64_t seed) {
    validate(p);
    const Perlin2D hi(seed, 0), lo(seed, 1);
    const double hi_wl =
        p.mavs_compat ? kMavsHiWavelengthFactor * p.hi_wavelength_m : p.hi_wavelength_m;
    const double hi_mag =
        p.mavs_compat ? kMavsHiMagnitudeFactor * p.hi_magnitude_m : p.hi_magnitude_m;
    return evaluate(grid, [&](double x, double y) {
        return hi_mag * hi(x / hi_wl, y / hi_wl) +
               p.lo_magnitude_m * lo(x / p.lo_wavelength_m, y / p.lo_wavelength_m);
    });
}

RasterD gaussian_surface(const GridSpec& grid, const GaussianSurfaceParams& p, std::uint64_t seed) {
    validate(p);
    grid.validate("surface grid");
    // Spectral synthesis on a grid padded by a few correlation lengths (the FFT field is periodic;
    // the padding keeps the wrap-around out of the part that is kept).
    const double beta = p.correlation_length_m;
    const int pad =
        static_cast<int>(std::min(std::ceil(kGaussianPadLengths * beta / grid.cell_size_m),
                                  4.0 * std::max(grid.nx, grid.ny)));
    const GridSpec big{grid.nx + pad, grid.ny + pad, grid.cell_size_m, 0.0, 0.0};
    ensure_fits_in_memory(big.size(), 8.0 * 4, "surface grid");
    const double wx = big.width_m(), wy = big.height_m();
    HalfSpectrum spec(big.nx, big.ny);
    Rng rng(seed, "terrain.gaussian");
    for (int b = 0; b < big.ny; ++b) {
        const double ky = (b <= big.ny / 2 ? b : b - big.ny) / wy;
        for (int a = 0; a < spec.nxh(); ++a) {
            const double k = std::hypot(a / wx, ky);
            // 2D spectral density of the covariance exp(-r / beta), cycles per metre.
            const double tb = 2.0 * std::numbers::pi * beta * k;
            const double amp = (a == 0 && b == 0) ? 0.0 : std::pow(1.0 + tb * tb, -0.75);
            const double re = rng.normal(), im = rng.normal();
            spec.at(a, b) = {amp * re, amp * im};
        }
    }
    RasterD field(big, 0.0);
    inverse_real_fft(spec, field);
    const auto st = stats(field);
    const double scale = st.stddev > 0 ? p.rms_m / st.stddev : 0.0;
    const Perlin2D lo(seed, 2);
    RasterD z(grid, 0.0);
#pragma omp parallel for schedule(static)
    for (int j = 0; j < grid.ny; ++j) {
        double* row = z.row(j);
        const double y = grid.y_of(j) / p.lo_wavelength_m;
        for (int i = 0; i < grid.nx; ++i)
            row[i] = scale * (field(i, j) - st.mean) +
                     p.lo_magnitude_m * lo(grid.x_of(i) / p.lo_wavelength_m, y);
    }
    return z;
}

std::vector<double> variable_octave_wavelengths(const GridSpec& grid,
                                                const VariableSurfaceParams& p) {
    const double min_wl = 2.0 * grid.cell_size_m;
    const double max_wl =
        std::min(p.max_wavelength_m, 0.25 * std::min(grid.width_m(), grid.height_m()));
    std::vector<double> wl;
    for (double w = min_wl; w <= max_wl * (1 + 1e-12); w *= 2.0) wl.push_back(w);
    if (wl.empty()) wl.push_back(min_wl);
    return wl;
}

RasterD variable_surface(const GridSpec& grid, const VariableSurfaceParams& p, std::uint64_t seed) {
    validate(p);
    const auto wl = variable_octave_wavelengths(grid, p);
    const double alpha = p.mavs_compat ? 3.0 : p.spectral_exponent;
    std::vector<Perlin2D> octaves;
    std::vector<double> mag;
    for (std::size_t n = 0; n < wl.size(); ++n) {
        octaves.emplace_back(seed, 16 + n);
        mag.push_back(p.hi_magnitude_m * std::pow(wl[n] / wl[0], 0.5 * (alpha - 1.0)));
    }
    const Perlin2D envelope(seed, 15);
    const double ewl = p.envelope_wavelength_m;
    return evaluate(grid, [&](double x, double y) {
        double z = 0.0;
        for (std::size_t n = 0; n < wl.size(); ++n) z += mag[n] * octaves[n](x / wl[n], y / wl[n]);
        const double scale = ewl > 0.0 ? 0.5 * (1.0 + envelope(x / ewl, y / ewl)) : 1.0;
        return scale * z;
    });
}

} // namespace ecoterra::terrain
