#pragma once
// Pictures of the water state, shared by `ecoterra hydro run --png` and the pictures of an
// ecosystem run: readable sizes, colour bars with units, scale bars and fixed colour ranges, so
// that runs can be compared picture to picture (docs/formats.md, "Pictures").
#include "ecoterra/hydro/soil.hpp"
#include "ecoterra/raster.hpp"

#include <filesystem>
#include <string>

namespace ecoterra::hydro {

/// Fixed colour ranges: soil moisture as a fraction of field capacity from 0 to this, and
/// standing water from 0 to this depth (m).
inline constexpr double kMoisturePictureMax = 1.2;
inline constexpr double kWaterPictureMaxM = 0.5;

/// soil_moisture.png (theta / field capacity) and surface_water_depth.png (standing water over
/// the hillshade) into `dir`; `when` names the moment ("year 40, day 365").
void write_water_pictures(const RasterD& dem, const SoilMap& soil, const RasterD& moisture,
                          const RasterD& water_depth_m, const std::string& when,
                          const std::filesystem::path& dir);

} // namespace ecoterra::hydro
