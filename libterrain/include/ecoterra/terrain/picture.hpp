#pragma once
// Pictures of rasters as 8-bit RGB PNG files (libpng). Image row 0 is the top (north) edge.
#include "ecoterra/raster.hpp"

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

typedef struct _cairo cairo_t; // cairo.h's own declaration

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

/// A text a figure drew: its box in the picture's pixels, its role (title, xtick, ytick, xlabel,
/// ylabel, bar_label, bar_tick, legend, scale_bar, note or "") and the picture it is on.
struct DrawnText {
    std::string text, role;
    double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    const void* surface = nullptr; ///< one id per picture
    int surface_width = 0, surface_height = 0;
    int axes = 0; ///< which axes (panel) of the picture, counted by begin_axes(); 0 outside any
};
/// While a FigureLog lives, the texts drawn on its thread (draw_text, draw_text_vertical) are
/// kept in it: tests check that figures keep their labels inside the picture, their ticks
/// distinct and their axes labelled. Nesting is not supported.
struct FigureLog {
    FigureLog();
    ~FigureLog();
    FigureLog(const FigureLog&) = delete;
    FigureLog& operator=(const FigureLog&) = delete;
    std::vector<DrawnText> texts;
};

/// Text at (x, y) (the baseline) in a Cairo drawing; `align` 0 left, 0.5 centred, 1 right.
void draw_text(cairo_t* cr, double x, double y, const std::string& s, double size, double align = 0,
               const char* role = "");
/// Text read bottom to top, centred on (x, y) (an axis label left of a plot).
void draw_text_vertical(cairo_t* cr, double x, double y, const std::string& s, double size,
                        const char* role = "ylabel");
/// Marks the start of a new set of axes (a panel): the texts drawn until the next call belong
/// to it in the FigureLog.
void begin_axes();
/// The width in pixels of `s` at `size` (Cairo's toy font, as draw_text uses).
double text_width(const std::string& s, double size);
/// The decimals a tick label needs at this step (0 for steps of 1 and more; 2 for 0.02).
int tick_digits(double step);
/// A scale bar at (x, y) (its left end): a round length (1, 2 or 5 x 10^k m) of at most
/// `max_px` pixels at `px_per_m`, with its length written after it. Returns the bar's length, m.
double draw_scale_bar(cairo_t* cr, double x, double y, double px_per_m, double max_px);
/// A vertical colour bar at (x, y), w x h pixels, from vmin (bottom) to vmax (top), coloured by
/// `colour(t)` for t in [0, 1], its label above and round ticks to the right.
void draw_colour_bar(cairo_t* cr, double x, double y, double w, double h, double vmin, double vmax,
                     const std::string& label, const std::function<Rgb(double)>& colour);
/// Paints `img` scaled to w x h pixels at (x, y) of a Cairo drawing; `smooth` interpolates
/// (continuous fields), otherwise each cell stays a sharp block (classes).
void paint_image(cairo_t* cr, const Image& img, double x, double y, double w, double h,
                 bool smooth = false);

/// Grey hillshade; NODATA cells are drawn in light blue.
Image hillshade_image(const RasterD& z);
/// Colour maps of continuous fields: viridis (matplotlib, perceptually uniform) and water (white
/// to deep blue, for depths).
enum class Palette { viridis, water };
/// The colour at t in [0, 1] (clamped).
Rgb palette_colour(Palette p, double t);
/// A continuous field through a colour map between vmin and vmax (NaN: auto range); values
/// outside are drawn at the ends.
Image colormap_image(const RasterD& v, double vmin = std::nan(""), double vmax = std::nan(""),
                     Palette palette = Palette::viridis);

/// A labelled colour of a categorical map's legend.
struct LegendEntry {
    std::string label;
    Rgb colour;
};

/// How a map is presented: title, colour bar (units and range) or legend, and notes.
struct MapFigure {
    std::string title;
    std::string bar_label;     ///< the colour bar's quantity and unit, e.g. "elevation (m)"
    double vmin = 0, vmax = 1; ///< the colour bar's range (the image's colours span it)
    Palette palette = Palette::viridis;
    bool colour_bar = true;          ///< false: no bar (hillshade) or the legend below
    std::vector<LegendEntry> legend; ///< categorical maps: shown instead of a colour bar
    std::vector<std::string> notes; ///< lines under the map (ranges, clipping, "no standing water")
    bool smooth = true; ///< scale continuous fields smoothly; categorical ones cell by cell
};

/// Writes `img` (one pixel per cell of the grid `g`, row 0 north) as a figure 800 px wide (wider
/// when the legend, the colour bar label or a note needs it): the
/// title, the map scaled to fill 600 px, its colour bar with ticks (or legend), a scale bar in
/// metres and the notes. Atomic; IoError naming the file.
void write_map_figure(const Image& img, const GridSpec& g, const MapFigure& f,
                      const std::filesystem::path& path);
/// The colour of roughness class c (0 low, 1 semi, 2 high; others NODATA), unshaded.
Rgb class_colour(int c);
/// Roughness classes (low blue, semi orange, high yellow as in Majhor & Bos Fig. 4) over
/// hillshade; `border_cells` > 0 draws the excluded border darker.
Image classes_image(const RasterU8& classes, const RasterD* shade = nullptr, int border_cells = 0);

} // namespace ecoterra::terrain
