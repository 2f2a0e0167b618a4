#pragma once
// Spectral and variogram measures of a surface's scaling.
//
// Radial power spectral density (reference terrain.md s3): the plane-detrended surface is
// Hann-windowed and Fourier-transformed; P(k) = |F(k)|^2 h^2 / (nx ny U), U = mean(w^2), in m^4
// (m^2 per (cycle/m)^2), so that sum P dk^2 is the height variance. Annuli are log-spaced with a
// width ratio of at least gamma (1.5 by default): the W-M surface has a line spectrum at gamma^n /
// L, and narrower bins hold mostly leakage. For a self-affine surface P ~ k^{-(8 - 2D)}, so D_psd =
// (8 + slope) / 2.
//
// Fractal dimension from elevation differences against distance (Wang, Guo & Chen 2006, J. Zhejiang
// Univ. Sci. A 7(suppl. I) 287, who plot either the mean E or the standard deviation S of the
// differences). Over pairs h apart along rows and columns:
//   madogram:  E(h) = mean |z(p + h) - z(p)|         (power index 1)
//   variogram: S(h) = sqrt(mean (z(p + h) - z(p))^2) (power index 2)
// both go as h^H for a self-affine surface, and D = 3 - H (Gneiting, Sevcikova & Percival 2012,
// Stat. Sci. 27(2) 247, compare the two). The linear part of the log-log curve is found by
// iterative least squares: the longest run of consecutive lags whose points all lie within a
// tolerance of their own fitted line.
#include "ecoterra/raster.hpp"

#include <vector>

namespace ecoterra::terrain {

struct PsdOptions {
    double bin_ratio = 1.5;   ///< ratio of an annulus's outer to inner frequency, >= 1.1
    double anchor_cpm = 0.0;  ///< a bin is centred on this frequency, cycles/m (0 = 1/extent)
    double fit_min_cpm = 0.0; ///< lowest bin centre fitted, cycles/m (0 = 10 / extent)
    double fit_max_cpm = 0.0; ///< highest bin centre fitted, cycles/m (0 = Nyquist)
    void validate() const;
};

struct PsdBin {
    double k_cpm = 0; ///< bin centre, cycles/m
    double power = 0; ///< mean PSD in the annulus, m^4
    int count = 0;    ///< Fourier coefficients averaged
    bool fitted = false;
};

struct PsdResult {
    std::vector<PsdBin> bins;
    double slope = 0; ///< d log P / d log k over the fitted bins
    double r2 = 0;
    double fit_min_cpm = 0, fit_max_cpm = 0;
    double dimension = 0; ///< (8 + slope) / 2 for a self-affine surface
};

PsdResult radial_psd(const RasterD& z, const PsdOptions& opt = {});

enum class DimensionEstimator { variogram, madogram };

struct FractalDimensionOptions {
    DimensionEstimator estimator = DimensionEstimator::variogram;
    double max_lag_fraction = 0.25; ///< longest lag as a fraction of the shorter side
    double lag_ratio = 1.25;        ///< ratio between successive lags (distinct integers)
    double tolerance = 0.015;       ///< largest |residual| in log10 E for the linear range
    int min_points = 5;             ///< fewest lags in the linear range
    void validate() const;
};

struct FractalDimensionResult {
    std::vector<double> lag_m;       ///< lag distances, m
    std::vector<double> structure_m; ///< S(h) or E(h), m
    int first = 0, last = 0;         ///< indices of the linear range (inclusive)
    double range_min_m = 0, range_max_m = 0;
    double hurst = 0;     ///< slope of log E against log h in the range
    double dimension = 0; ///< 3 - hurst
    double r2 = 0;
};

FractalDimensionResult fractal_dimension(const RasterD& z, const FractalDimensionOptions& opt = {});

/// Least-squares line y = a + b x; returns {a, b, r2}.
std::array<double, 3> fit_line(const std::vector<double>& x, const std::vector<double>& y);

} // namespace ecoterra::terrain
