#include "ecoterra/terrain/picture.hpp"

#include "ecoterra/terrain/roughness.hpp"

#include <cmath>

namespace ecoterra::terrain {

namespace {
/// Viridis (matplotlib, CC0) sampled at 9 points and interpolated linearly.
constexpr double kViridis[9][3] = {{68, 1, 84},    {71, 44, 122},  {59, 81, 139},
                                   {44, 113, 142}, {33, 144, 141}, {39, 173, 129},
                                   {92, 200, 99},  {170, 220, 50}, {253, 231, 37}};
constexpr Rgb kNodata{200, 225, 240};
/// Majhor & Bos Fig. 4 colours: low blue, semi orange, high yellow.
constexpr Rgb kClassColours[3] = {{40, 90, 200}, {240, 140, 30}, {250, 225, 40}};

/// Water: white to deep blue (ColorBrewer Blues, 9 classes).
constexpr double kWater[9][3] = {{247, 251, 255}, {222, 235, 247}, {198, 219, 239},
                                 {158, 202, 225}, {107, 174, 214}, {66, 146, 198},
                                 {33, 113, 181},  {8, 81, 156},    {8, 48, 107}};

Rgb ramp(const double (&table)[9][3], double t) {
    t = std::clamp(std::isnan(t) ? 0.0 : t, 0.0, 1.0) * 8.0;
    const int k = std::min(7, static_cast<int>(t));
    const double f = t - k;
    auto c = [&](int ch) {
        return static_cast<std::uint8_t>(
            std::lround(table[k][ch] * (1 - f) + table[k + 1][ch] * f));
    };
    return {c(0), c(1), c(2)};
}
} // namespace

Rgb palette_colour(Palette p, double t) {
    return ramp(p == Palette::water ? kWater : kViridis, t);
}

Rgb class_colour(int c) {
    return c >= 0 && c < 3 ? kClassColours[c] : kNodata;
}

Image hillshade_image(const RasterD& z) {
    const RasterD h = hillshade(z);
    Image img(z.nx(), z.ny());
    for (int j = 0; j < z.ny(); ++j)
        for (int i = 0; i < z.nx(); ++i) {
            const double v = h(i, j);
            auto g = static_cast<std::uint8_t>(std::lround(255.0 * (std::isnan(v) ? 0 : v)));
            img.at(i, z.ny() - 1 - j) = std::isnan(v) ? kNodata : Rgb{g, g, g};
        }
    return img;
}

Image colormap_image(const RasterD& v, double vmin, double vmax, Palette palette) {
    const auto s = stats(v);
    if (std::isnan(vmin)) vmin = s.min;
    if (std::isnan(vmax)) vmax = s.max;
    const double span = vmax > vmin ? vmax - vmin : 1.0;
    Image img(v.nx(), v.ny());
    for (int j = 0; j < v.ny(); ++j)
        for (int i = 0; i < v.nx(); ++i) {
            const double x = v(i, j);
            img.at(i, v.ny() - 1 - j) =
                std::isnan(x) ? kNodata : palette_colour(palette, (x - vmin) / span);
        }
    return img;
}

Image classes_image(const RasterU8& classes, const RasterD* shade, int border_cells) {
    Image img(classes.nx(), classes.ny());
    for (int j = 0; j < classes.ny(); ++j)
        for (int i = 0; i < classes.nx(); ++i) {
            const std::uint8_t c = classes(i, j);
            Rgb p = c < 3 ? kClassColours[c] : kNodata;
            double f = 1.0;
            if (shade && !std::isnan((*shade)(i, j))) f = 0.55 + 0.45 * (*shade)(i, j);
            const bool border = i < border_cells || j < border_cells ||
                                i >= classes.nx() - border_cells ||
                                j >= classes.ny() - border_cells;
            if (border) f *= 0.45;
            p = {static_cast<std::uint8_t>(p.r * f), static_cast<std::uint8_t>(p.g * f),
                 static_cast<std::uint8_t>(p.b * f)};
            img.at(i, classes.ny() - 1 - j) = p;
        }
    return img;
}

} // namespace ecoterra::terrain
