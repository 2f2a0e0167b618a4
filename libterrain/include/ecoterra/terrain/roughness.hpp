#pragma once
// Roughness measures for ground vehicles.
//
// - RMS roughness (US Army definition, Durst et al. 2011 J. Terramech. 48(2) 105): the RMS
//   deviation of elevation from a mean, sigma = sqrt(sum (z_i - zbar)^2 / N). Three variants:
//   plain (zbar = the global mean), detrended (zbar = the local mean over a square window) and
//   band-limited (wavelengths longer than a cutoff, 3.0 m = 10 ft by default, removed with the
//   ISO 16610-21 Gaussian filter; optionally wavelengths shorter than a second cutoff removed too).
//   The filtered variants leave out the edge cells where the window is truncated (half a window
//   for the local mean, the 4-sigma kernel radius for the Gaussian).
// - Gradient map (Majhor & Bos eqs 3-4): P_grad = max_i |z_P - z_Qi| / dist(P, Qi) over the Moore
//   neighbourhood, a dimensionless rise-over-run slope. Classes: low <= t_low < semi <= t_high <
//   high. The paper's thresholds 50 and 140 were in 16-bit units per cm with one unit = 0.75/128
//   cm, i.e. slopes 50 * 0.75 / 128 = 0.29297 and 140 * 0.75 / 128 = 0.82031.
// - Slope (rise over run, and degrees) and aspect (degrees clockwise from north, downslope
//   direction) by Horn's (1981) 3x3 finite differences.
#include "ecoterra/raster.hpp"

namespace ecoterra::terrain {

/// The paper's class thresholds converted to rise-over-run slopes (see header).
inline constexpr double kPaperUnitsPerCmToSlope = 0.75 / 128.0;
inline constexpr double kDefaultLowThreshold = 50.0 * kPaperUnitsPerCmToSlope;
inline constexpr double kDefaultHighThreshold = 140.0 * kPaperUnitsPerCmToSlope;

enum class RoughnessClass : std::uint8_t { low = 0, semi = 1, high = 2, nodata = 255 };

struct RmsOptions {
    double detrend_window_m = 3.0;    ///< side of the local-mean window, m
    double band_long_cutoff_m = 3.0;  ///< wavelengths longer than this are removed, m
    double band_short_cutoff_m = 0.0; ///< wavelengths shorter than this are removed, m (0 = none)
};

struct RmsResult {
    double rms_m = 0.0;              ///< about the global mean, m
    double rms_detrended_m = 0.0;    ///< about the local mean, m
    double rms_band_limited_m = 0.0; ///< after the Gaussian band filter, m
};

RmsResult rms_roughness(const RasterD& z, const RmsOptions& opt = {});

/// RMS of the valid cells of r about zero (r is a residual field), m, leaving out `margin` cells
/// at each edge (unless that leaves nothing).
double rms_about_zero(const RasterD& r, int margin = 0);

/// Moore-neighbourhood maximum absolute gradient (eqs 3-4), dimensionless. NaN where the cell is
/// NODATA; NODATA neighbours are left out.
RasterD max_gradient_map(const RasterD& z);

struct ClassThresholds {
    double low = kDefaultLowThreshold;   ///< slope at or below which a cell is low roughness
    double high = kDefaultHighThreshold; ///< slope above which a cell is high roughness
    void validate() const;
};

/// Class of each cell from a gradient map (255 = NODATA).
RasterU8 classify_gradient(const RasterD& gradient, const ClassThresholds& t = {});

struct ClassAreas {
    double low_pct = 0, semi_pct = 0, high_pct = 0; ///< percent of counted cells
    std::int64_t cells = 0;                         ///< cells counted
};

/// Area percentages of each class, leaving out a border of border_m metres and NODATA.
ClassAreas class_areas(const RasterU8& classes, double border_m);

/// Morphological closing of the class map with a disk of radius radius_m (m): rough areas grow
/// over narrow smooth gaps (Majhor & Bos Fig. 4b). NODATA cells take no part and stay NODATA.
RasterU8 close_classes(const RasterU8& classes, double radius_m);

struct SlopeAspect {
    RasterD slope;      ///< rise over run, dimensionless
    RasterD slope_deg;  ///< degrees from horizontal
    RasterD aspect_deg; ///< downslope direction, degrees clockwise from north; NaN on flats
};
SlopeAspect slope_aspect(const RasterD& z);

/// Hillshade in [0, 1] (Horn gradients; sun azimuth clockwise from north and altitude in degrees).
RasterD hillshade(const RasterD& z, double azimuth_deg = 315.0, double altitude_deg = 45.0,
                  double z_factor = 1.0);

} // namespace ecoterra::terrain
