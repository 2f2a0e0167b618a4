#pragma once
// MAVS-style rough surfaces (Goodin et al., MAVS "Terrain Roughness" documentation; reference
// terrain.md s2 and mavs.md s3.2), with the corrections the documentation's own theory asks for.
//
// - perlin: z = a_hi P(x / lambda_hi, y / lambda_hi) + a_lo P(x / lambda_lo, y / lambda_lo) with
//   2D gradient noise P (Perlin 2002, quintic fade) in about [-1, 1]. Defaults lambda_hi = 2 m,
//   lambda_lo = 50 m. With mavs_compat the high band uses MAVS's frequency 1 / (1.25 pi lambda_hi)
//   and magnitude 4 a_hi.
// - gaussian: a Gaussian field with the isotropic exponential covariance s^2 exp(-r / beta), the 2D
//   form of the Ornstein-Uhlenbeck process (Matern nu = 1/2), plus the low-frequency Perlin. It is
//   synthesised spectrally: 2D spectral density proportional to (1 + (2 pi beta k)^2)^{-3/2}, on a
//   grid padded by 8 beta so the periodic wrap does not show, then scaled to RMS s. The correlation
//   length beta is in metres, so rho(r) = exp(-r / beta) whatever the cell size (MAVS's AR(1)
//   chain uses rho = exp(-2 beta^2), which is not dimensionally consistent, and is anisotropic).
// - variable: octaves of Perlin noise with wavelengths lambda_n = 2^n * 2h from 2h up to
//   min(100 m, extent / 4), amplitudes a_n = a_0 (lambda_n / lambda_0)^{(alpha - 1) / 2},
//   multiplied by the envelope 0.5 (1 + P(x / 100 m, y / 100 m)). An octave carries variance a_n^2
//   over a band of width proportional to its frequency Omega, so the profile PSD goes as
//   Omega^{-alpha}: alpha = 2 is Van Deussen's natural-terrain law P(Omega) = C Omega^-2 (the
//   default); MAVS's own code doubles the magnitude per octave (a_n proportional to lambda_n), i.e.
//   alpha = 3, which mavs_compat reproduces.
#include "ecoterra/raster.hpp"

#include <array>
#include <cstdint>

namespace ecoterra::terrain {

/// Seeded 2D gradient noise (Perlin 2002 "Improving noise": quintic fade, 256-entry permutation,
/// 8 unit gradients), values in about [-1, 1], zero at lattice points.
class Perlin2D {
public:
    explicit Perlin2D(std::uint64_t seed, std::uint64_t stream = 0);
    double operator()(double x, double y) const;

private:
    std::array<std::uint8_t, 512> m_perm{};
};

struct PerlinSurfaceParams {
    double hi_wavelength_m = 2.0;  ///< short feature wavelength, m
    double hi_magnitude_m = 0.1;   ///< amplitude of the short features, m
    double lo_wavelength_m = 50.0; ///< rolling-hill wavelength, m
    double lo_magnitude_m = 1.0;   ///< amplitude of the rolling hills, m
    bool mavs_compat = false;      ///< MAVS's 1/(1.25 pi lambda) frequency and 4x magnitude
};

struct GaussianSurfaceParams {
    double rms_m = 0.05;               ///< standard deviation of the correlated field, m
    double correlation_length_m = 2.0; ///< e-folding length beta of the correlation, m
    double lo_wavelength_m = 50.0;     ///< low-frequency Perlin wavelength, m
    double lo_magnitude_m = 1.0;       ///< low-frequency Perlin amplitude, m
};

struct VariableSurfaceParams {
    double hi_magnitude_m = 0.1;          ///< amplitude of the shortest octave (2 cells), m
    double spectral_exponent = 2.0;       ///< alpha in PSD ~ Omega^-alpha (2 = Van Deussen)
    double max_wavelength_m = 100.0;      ///< longest octave is min(this, extent / 4), m
    double envelope_wavelength_m = 100.0; ///< wavelength of the roughness envelope, m (0 = none)
    bool mavs_compat = false;             ///< MAVS's amplitude law (alpha = 3)
};

void validate(const PerlinSurfaceParams& p);
void validate(const GaussianSurfaceParams& p);
void validate(const VariableSurfaceParams& p);

RasterD perlin_surface(const GridSpec& grid, const PerlinSurfaceParams& p, std::uint64_t seed);
RasterD gaussian_surface(const GridSpec& grid, const GaussianSurfaceParams& p, std::uint64_t seed);
RasterD variable_surface(const GridSpec& grid, const VariableSurfaceParams& p, std::uint64_t seed);

/// The octave wavelengths (m) the variable surface uses on this grid.
std::vector<double> variable_octave_wavelengths(const GridSpec& grid,
                                                const VariableSurfaceParams& p);

} // namespace ecoterra::terrain
