#pragma once
// Neighbourhood filters on rasters. NODATA (NaN) cells are left out of every average by normalised
// convolution (Knutsson & Westin 1993): the filter is applied to the data and to the valid-cell
// mask and the two are divided, which also renormalises the kernel at the grid edges.
#include "ecoterra/raster.hpp"

#include <cstdint>

namespace ecoterra::terrain {

/// Gaussian low-pass with standard deviation sigma_m (m), kernel truncated at 4 sigma. NaN cells
/// stay NaN. sigma_m <= 0 returns a copy.
RasterD gaussian_filter(const RasterD& r, double sigma_m);

/// Radius (m) of the truncated Gaussian kernel used by gaussian_filter: 4 sigma.
double gaussian_kernel_radius_m(double sigma_m);

/// Mean over a square window of side window_m (m, rounded to an odd number of cells >= 1), using
/// only valid cells; edges use the part of the window inside the grid.
RasterD box_mean(const RasterD& r, double window_m);

/// Gaussian standard deviation (m) whose low-pass transmission is 50 % at wavelength cutoff_m, as
/// in the ISO 16610-21 Gaussian profile filter: sigma = cutoff * sqrt(ln 2 / 2) / pi.
double gaussian_sigma_for_cutoff(double cutoff_m);

/// Offsets (di, dj) of a disk of radius radius_px cells (di^2 + dj^2 <= r^2).
std::vector<std::array<int, 2>> disk_offsets(double radius_px);

/// Grey-scale dilation (max) and erosion (min) with a disk, ignoring cells outside the grid and
/// cells holding `nodata` (0..255; -1: none), which keep their value.
RasterU8 dilate_disk(const RasterU8& r, double radius_px, int nodata = -1);
RasterU8 erode_disk(const RasterU8& r, double radius_px, int nodata = -1);
/// Morphological closing (dilation then erosion) with a disk of radius radius_px cells.
RasterU8 close_disk(const RasterU8& r, double radius_px, int nodata = -1);

} // namespace ecoterra::terrain
