// Map figures drawn with Cairo: a raster picture scaled to a readable size with its title, colour
// bar or legend, scale bar and notes.
#include "ecoterra/error.hpp"
#include "ecoterra/io/atomic_file.hpp"
#include "ecoterra/terrain/picture.hpp"

#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>

namespace ecoterra::terrain {

namespace {

constexpr double kMapPx = 600, kLeft = 30, kTop = 56, kWidth = 800;

void text(cairo_t* cr, double x, double y, const std::string& s, double size, double align = 0) {
    draw_text(cr, x, y, s, size, align);
}

/// 1, 2 or 5 times a power of ten, at most `limit`.
double nice_below(double limit) {
    const double p = std::pow(10.0, std::floor(std::log10(limit)));
    for (double m : {5.0, 2.0, 1.0})
        if (m * p <= limit) return m * p;
    return p;
}

std::string number(double v, double step) {
    char b[32];
    std::snprintf(b, sizeof b, "%.*f", tick_digits(step), v);
    return b;
}

void set(cairo_t* cr, const Rgb& c) {
    cairo_set_source_rgb(cr, c.r / 255.0, c.g / 255.0, c.b / 255.0);
}

} // namespace

namespace {
thread_local FigureLog* t_log = nullptr;
thread_local int t_axes = 0;

/// Logs the text whose box in user space is (x, y, w, h), in device pixels.
void log_text(cairo_t* cr, const std::string& s, const char* role, double x, double y, double w,
              double h) {
    if (!t_log) return;
    double xs[4] = {x, x + w, x, x + w}, ys[4] = {y, y, y + h, y + h};
    DrawnText d{s, role, 1e300, 1e300, -1e300, -1e300, nullptr, 0, 0, t_axes};
    for (int k = 0; k < 4; ++k) {
        cairo_user_to_device(cr, &xs[k], &ys[k]);
        d.x0 = std::min(d.x0, xs[k]);
        d.y0 = std::min(d.y0, ys[k]);
        d.x1 = std::max(d.x1, xs[k]);
        d.y1 = std::max(d.y1, ys[k]);
    }
    // One id per picture: surfaces are tagged as they are first met (a freed surface's address
    // is often the next one's).
    static const cairo_user_data_key_t key{};
    static std::uintptr_t next_id = 1;
    cairo_surface_t* target = cairo_get_target(cr);
    void* id = cairo_surface_get_user_data(target, &key);
    if (!id) {
        id = reinterpret_cast<void*>(next_id++);
        cairo_surface_set_user_data(target, &key, id, nullptr);
    }
    d.surface = id;
    if (cairo_surface_get_type(target) == CAIRO_SURFACE_TYPE_IMAGE) {
        d.surface_width = cairo_image_surface_get_width(target);
        d.surface_height = cairo_image_surface_get_height(target);
    }
    t_log->texts.push_back(std::move(d));
}
} // namespace

FigureLog::FigureLog() {
    t_log = this;
    t_axes = 0;
}

void begin_axes() {
    ++t_axes;
}
FigureLog::~FigureLog() {
    t_log = nullptr;
}

void draw_text(cairo_t* cr, double x, double y, const std::string& s, double size, double align,
               const char* role) {
    cairo_set_font_size(cr, size);
    cairo_text_extents_t e;
    cairo_text_extents(cr, s.c_str(), &e);
    cairo_move_to(cr, x - align * e.width, y);
    cairo_show_text(cr, s.c_str());
    if (!s.empty())
        log_text(cr, s, role, x - align * e.width + e.x_bearing, y + e.y_bearing, e.width,
                 e.height);
}

void draw_text_vertical(cairo_t* cr, double x, double y, const std::string& s, double size,
                        const char* role) {
    cairo_save(cr);
    cairo_translate(cr, x, y);
    cairo_rotate(cr, -M_PI / 2);
    draw_text(cr, 0, 0, s, size, 0.5, role);
    cairo_restore(cr);
}

double text_width(const std::string& s, double size) {
    cairo_surface_t* surface = cairo_image_surface_create(CAIRO_FORMAT_RGB24, 1, 1);
    cairo_t* cr = cairo_create(surface);
    cairo_set_font_size(cr, size);
    cairo_text_extents_t e;
    cairo_text_extents(cr, s.c_str(), &e);
    cairo_destroy(cr);
    cairo_surface_destroy(surface);
    return e.x_advance;
}

int tick_digits(double step) {
    if (!(step > 0) || step >= 1) return 0;
    return std::min(6, static_cast<int>(std::ceil(-std::log10(step) - 1e-9)));
}

double draw_scale_bar(cairo_t* cr, double x, double y, double px_per_m, double max_px) {
    if (!(px_per_m > 0) || !(max_px > 0)) return 0;
    const double len_m = nice_below(max_px / px_per_m);
    const double px = len_m * px_per_m;
    cairo_save(cr);
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_set_line_width(cr, 3);
    cairo_move_to(cr, x, y);
    cairo_line_to(cr, x + px, y);
    cairo_stroke(cr);
    cairo_set_line_width(cr, 1);
    for (const double e : {x, x + px}) {
        cairo_move_to(cr, e, y - 6);
        cairo_line_to(cr, e, y + 6);
        cairo_stroke(cr);
    }
    draw_text(cr, x + px + 8, y + 5, number(len_m, len_m) + " m", 12, 0, "scale_bar");
    cairo_restore(cr);
    return len_m;
}

void draw_colour_bar(cairo_t* cr, double x, double y, double w, double h, double vmin, double vmax,
                     const std::string& label, const std::function<Rgb(double)>& colour) {
    cairo_save(cr);
    cairo_set_source_rgb(cr, 0, 0, 0);
    draw_text(cr, x, y - 8, label, 12, 0, "bar_label");
    const int steps = 200;
    for (int k = 0; k < steps; ++k) {
        set(cr, colour((k + 0.5) / steps));
        const double y0 = y + h * (1 - static_cast<double>(k + 1) / steps);
        cairo_rectangle(cr, x, y0, w, h / steps + 0.6);
        cairo_fill(cr);
    }
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_set_line_width(cr, 1);
    cairo_rectangle(cr, x - 0.5, y - 0.5, w + 1, h + 1);
    cairo_stroke(cr);
    const double span = vmax - vmin;
    if (span > 0 && std::isfinite(span)) {
        const double raw = span / 5;
        const double p = std::pow(10.0, std::floor(std::log10(raw)));
        double step = p;
        for (double m : {1.0, 2.0, 5.0, 10.0})
            if (m * p >= raw) {
                step = m * p;
                break;
            }
        for (double v = std::ceil(vmin / step - 1e-9) * step; v <= vmax + 1e-9 * span; v += step) {
            const double ty = y + h * (1 - (v - vmin) / span);
            cairo_move_to(cr, x + w, ty);
            cairo_line_to(cr, x + w + 5, ty);
            cairo_stroke(cr);
            draw_text(cr, x + w + 8, ty + 4, number(std::abs(v) < 1e-9 * span ? 0.0 : v, step), 12,
                      0, "bar_tick");
        }
    }
    cairo_restore(cr);
}

void paint_image(cairo_t* cr, const Image& img, double x, double y, double w, double h,
                 bool smooth) {
    cairo_surface_t* raster = cairo_image_surface_create(CAIRO_FORMAT_RGB24, img.width, img.height);
    cairo_surface_flush(raster);
    unsigned char* data = cairo_image_surface_get_data(raster);
    const int stride = cairo_image_surface_get_stride(raster);
    for (int r = 0; r < img.height; ++r) {
        auto* row =
            reinterpret_cast<std::uint32_t*>(data + static_cast<std::ptrdiff_t>(r) * stride);
        for (int c = 0; c < img.width; ++c) {
            const Rgb& p = img.pixels[static_cast<std::size_t>(r) * img.width + c];
            row[c] = (std::uint32_t{p.r} << 16) | (std::uint32_t{p.g} << 8) | p.b;
        }
    }
    cairo_surface_mark_dirty(raster);
    const double sx = w / img.width, sy = h / img.height;
    cairo_save(cr);
    cairo_translate(cr, x, y);
    cairo_scale(cr, sx, sy);
    cairo_set_source_surface(cr, raster, 0, 0);
    cairo_pattern_set_filter(
        cairo_get_source(cr),
        !smooth ? CAIRO_FILTER_NEAREST
                : (std::min(sx, sy) < 1 ? CAIRO_FILTER_GOOD : CAIRO_FILTER_BILINEAR));
    cairo_pattern_set_extend(cairo_get_source(cr), CAIRO_EXTEND_PAD);
    cairo_rectangle(cr, 0, 0, img.width, img.height);
    cairo_fill(cr);
    cairo_restore(cr);
    cairo_surface_destroy(raster);
}

namespace {

/// Each legend entry: a swatch, and its label's lines ('\n') beside and under it.
/// The lines of a legend label ('\n' between them).
std::vector<std::string> lines_of(const std::string& label) {
    std::vector<std::string> out;
    std::size_t start = 0;
    for (;;) {
        const auto nl = label.find('\n', start);
        out.push_back(label.substr(start, nl - start));
        if (nl == std::string::npos) return out;
        start = nl + 1;
    }
}

void draw_legend(cairo_t* cr, const MapFigure& f, double bx) {
    double y = kTop + 4;
    for (const auto& e : f.legend) {
        set(cr, e.colour);
        cairo_rectangle(cr, bx, y, 18, 14);
        cairo_fill(cr);
        cairo_set_source_rgb(cr, 0, 0, 0);
        cairo_rectangle(cr, bx - 0.5, y - 0.5, 19, 15);
        cairo_stroke(cr);
        double ly = y + 12 - 16;
        for (const auto& line : lines_of(e.label))
            draw_text(cr, bx + 26, ly += 16, line, 12, 0, "legend");
        y = ly + 16;
    }
}

/// The scale bar under the map (a round length up to a quarter of its width) and the notes.
void draw_map_footer(cairo_t* cr, const GridSpec& g, const MapFigure& f, double mw, double mh) {
    if (g.width_m() > 0) {
        const double y = kTop + mh + 24;
        const double len_m = draw_scale_bar(cr, kLeft, y, mw / g.width_m(), mw / 4);
        const double px = len_m * mw / g.width_m();
        text(cr, kLeft + px + 60, y + 5,
             "(map " + number(g.width_m(), 0.01) + " x " + number(g.height_m(), 0.01) + " m, " +
                 std::to_string(g.nx) + " x " + std::to_string(g.ny) + " cells of " +
                 number(g.cell_size_m, 0.001) + " m)",
             12);
    }
    for (std::size_t k = 0; k < f.notes.size(); ++k)
        draw_text(cr, kLeft, kTop + mh + 56 + 20.0 * static_cast<double>(k), f.notes[k], 12, 0,
                  "note");
}

} // namespace

void write_map_figure(const Image& img, const GridSpec& g, const MapFigure& f,
                      const std::filesystem::path& path) {
    if (img.width < 1 || img.height < 1) throw Error("map figure: empty image");
    const double scale = kMapPx / std::max(img.width, img.height);
    const double mw = img.width * scale, mh = img.height * scale;
    const double notes_h = 20.0 * static_cast<double>(f.notes.size());
    const int height = static_cast<int>(std::ceil(kTop + mh + 60 + notes_h + 10));
    // Wide enough for the legend's and the notes' longest lines (a legend of long class names
    // was cut at the right edge).
    const double bx = kLeft + mw + 40;
    double width = std::max(kWidth, kLeft + text_width(f.title, 17) + 10);
    for (const auto& e : f.legend)
        for (const auto& line : lines_of(e.label))
            width = std::max(width, bx + 26 + text_width(line, 12) + 12);
    if (f.legend.empty() && f.colour_bar)
        width = std::max(width, bx + text_width(f.bar_label, 12) + 12);
    for (const auto& n : f.notes) width = std::max(width, kLeft + text_width(n, 12) + 12);
    cairo_surface_t* surface =
        cairo_image_surface_create(CAIRO_FORMAT_RGB24, static_cast<int>(std::ceil(width)), height);
    cairo_t* cr = cairo_create(surface);
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_paint(cr);

    paint_image(cr, img, kLeft, kTop, mw, mh, f.smooth);
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_set_line_width(cr, 1);
    cairo_rectangle(cr, kLeft - 0.5, kTop - 0.5, mw + 1, mh + 1);
    cairo_stroke(cr);
    // Title and north; the colour bar or legend right of the map; the footer under it.
    draw_text(cr, kLeft, 30, f.title, 17, 0, "title");
    text(cr, kLeft + mw, 30, "north up", 12, 1.0);
    if (!f.legend.empty())
        draw_legend(cr, f, bx);
    else if (f.colour_bar)
        draw_colour_bar(cr, bx, kTop, 20, std::min(mh, 360.0), f.vmin, f.vmax, f.bar_label,
                        [&f](double t) { return palette_colour(f.palette, t); });
    draw_map_footer(cr, g, f, mw, mh);

    cairo_destroy(cr);
    cairo_surface_flush(surface);
    io::AtomicOutput out(path);
    const auto status = cairo_surface_write_to_png(surface, out.temp_path().c_str());
    cairo_surface_destroy(surface);
    if (status != CAIRO_STATUS_SUCCESS)
        throw IoError(path.string() + ": cannot write the PNG picture");
    out.commit();
}

} // namespace ecoterra::terrain
