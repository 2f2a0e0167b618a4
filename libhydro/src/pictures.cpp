#include "ecoterra/hydro/pictures.hpp"

#include "ecoterra/terrain/picture.hpp"
#include "ecoterra/terrain/roughness.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace ecoterra::hydro {

namespace {
std::string fixed(double v, int digits) {
    char b[48];
    std::snprintf(b, sizeof b, "%.*f", digits, v);
    return b;
}
} // namespace

void write_water_pictures(const RasterD& dem, const SoilMap& soil, const RasterD& moisture,
                          const RasterD& water_depth_m, const std::string& when,
                          const std::filesystem::path& dir) {
    const GridSpec& g = dem.grid();
    {
        RasterD rel(g, std::nan(""));
        double sum = 0, lo = 1e300, hi = -1e300, wp = 0;
        std::int64_t n = 0, above = 0;
        for (int j = 0; j < g.ny; ++j)
            for (int i = 0; i < g.nx; ++i) {
                const double fc = soil.field_capacity(i, j), th = moisture(i, j);
                if (!(fc > 0) || !std::isfinite(th)) continue;
                const double r = th / fc;
                rel(i, j) = r;
                sum += th, wp += soil.wilting_point(i, j) / fc, ++n;
                lo = std::min(lo, r), hi = std::max(hi, r);
                above += r > kMoisturePictureMax;
            }
        terrain::MapFigure f;
        f.title = "Soil moisture, " + when;
        f.bar_label = "theta / field capacity";
        f.vmin = 0;
        f.vmax = kMoisturePictureMax;
        f.notes = {"fixed range 0 to " + fixed(kMoisturePictureMax, 1) +
                       " (1 = field capacity; the wilting point is at " +
                       fixed(n ? wp / static_cast<double>(n) : 0.0, 2) + " on average)",
                   n ? "root-zone water: mean " + fixed(sum / static_cast<double>(n), 3) +
                           " m3/m3; theta/FC " + fixed(lo, 2) + " to " + fixed(hi, 2) +
                           (above ? " (" + std::to_string(above) + " cells above the range)" : "")
                     : "no cell with soil"};
        terrain::write_map_figure(terrain::colormap_image(rel, f.vmin, f.vmax), g, f,
                                  dir / "soil_moisture.png");
    }
    {
        // Standing water in blues over a grey hillshade of the dry land.
        const RasterD shade = terrain::hillshade(dem);
        terrain::Image img(g.nx, g.ny);
        double deepest = 0;
        std::int64_t wet = 0;
        for (int j = 0; j < g.ny; ++j)
            for (int i = 0; i < g.nx; ++i) {
                const double d = water_depth_m(i, j);
                terrain::Rgb c;
                if (d > 0) {
                    c = terrain::palette_colour(terrain::Palette::water,
                                                0.15 + 0.85 * d / kWaterPictureMaxM);
                    deepest = std::max(deepest, d);
                    ++wet;
                } else {
                    const double s = std::isnan(shade(i, j)) ? 0.5 : shade(i, j);
                    const auto v = static_cast<std::uint8_t>(std::lround(150 + 90 * s));
                    c = {v, v, v};
                }
                img.at(i, g.ny - 1 - j) = c;
            }
        terrain::MapFigure f;
        f.title = "Standing water, " + when;
        f.bar_label = "depth (m)";
        f.palette = terrain::Palette::water;
        f.vmin = 0;
        f.vmax = kWaterPictureMaxM;
        f.notes = {
            wet == 0
                ? std::string("no standing water: every cell is dry (grey: hillshade)")
                : std::to_string(wet) + " wet cells (" +
                      fixed(100.0 * static_cast<double>(wet) / static_cast<double>(g.size()), 1) +
                      " % of the area), deepest " + fixed(deepest, 3) +
                      " m; dry cells in grey (hillshade)",
            "fixed range 0 to " + fixed(kWaterPictureMaxM, 2) +
                " m; deeper water takes the darkest blue"};
        terrain::write_map_figure(img, g, f, dir / "surface_water_depth.png");
    }
}

} // namespace ecoterra::hydro
