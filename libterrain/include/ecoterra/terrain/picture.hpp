#pragma once
// Pictures of rasters as 8-bit RGB PNG files (libpng). Image row 0 is the top (north) edge.
#include "ecoterra/raster.hpp"

#include <cstdint>
#include <filesystem>
#include <vector>

namespace ecoterra::terrain {

struct Rgb {
    std::uint8_t r = 0, g = 0, b = 0;
};

struct Image {
    int width = 0, height = 0;
    std::vector<Rgb> pixels; ///< row-major, row 0 = top
    Image(int w, int h) : width(w), height(h), pixels(static_cast<std::size_t>(w) * h) {}
    Rgb& at(int x, int y) { return pixels[static_cast<std::size_t>(y) * width + x]; }
};

/// Writes an RGB PNG atomically; throws IoError naming the file.
void write_png_rgb(const Image& img, const std::filesystem::path& path);

/// Grey hillshade; NODATA cells are drawn in light blue.
Image hillshade_image(const RasterD& z);
/// A continuous field through the viridis colour map between vmin and vmax (NaN: auto range).
Image colormap_image(const RasterD& v, double vmin = std::nan(""), double vmax = std::nan(""));
/// Roughness classes (low blue, semi orange, high yellow as in Majhor & Bos Fig. 4) over
/// hillshade; `border_cells` > 0 draws the excluded border darker.
Image classes_image(const RasterU8& classes, const RasterD* shade = nullptr, int border_cells = 0);

} // namespace ecoterra::terrain
