// Run pictures drawn with Cairo (libcairo2-dev).
#include "ecoterra/run/pictures.hpp"
#include "ecoterra/error.hpp"
#include "ecoterra/hydro/pictures.hpp"
#include "ecoterra/io/atomic_file.hpp"
#include "ecoterra/terrain/picture.hpp"
#include "ecoterra/terrain/roughness.hpp"

#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

namespace ecoterra::run {

using namespace ecoterra::eco;

namespace {

namespace fs = std::filesystem;

struct SurfaceOwner {
    cairo_surface_t* s;
    cairo_t* cr;
    SurfaceOwner(int w, int h)
        : s(cairo_image_surface_create(CAIRO_FORMAT_RGB24, w, h)), cr(cairo_create(s)) {}
    ~SurfaceOwner() {
        cairo_destroy(cr);
        cairo_surface_destroy(s);
    }
    void save(const fs::path& path) {
        cairo_surface_flush(s);
        if (cairo_surface_write_to_png(s, path.string().c_str()) != CAIRO_STATUS_SUCCESS)
            throw IoError(path.string() + ": cannot write the PNG picture");
    }
};

// Okabe-Ito palette (colour-blind safe), then greys.
constexpr double kPalette[8][3] = {{0.90, 0.62, 0.00}, {0.34, 0.71, 0.91}, {0.00, 0.62, 0.45},
                                   {0.94, 0.89, 0.26}, {0.00, 0.45, 0.70}, {0.84, 0.37, 0.00},
                                   {0.80, 0.47, 0.65}, {0.40, 0.40, 0.40}};

void text(cairo_t* cr, double x, double y, const std::string& s, double size, double align = 0,
          const char* role = "") {
    terrain::draw_text(cr, x, y, s, size, align, role);
}

std::string fmt(double v, int digits = 1) {
    char b[64];
    std::snprintf(b, sizeof b, "%.*f", digits, v);
    return b;
}

double nice_step(double range) {
    const double raw = range / 5.0;
    const double p = std::pow(10.0, std::floor(std::log10(raw)));
    for (double m : {1.0, 2.0, 5.0, 10.0})
        if (m * p >= raw) return m * p;
    return 10 * p;
}

/// A plot frame with axes and ticks; returns the data->pixel mapping.
struct Frame {
    double x0, y0, w, h, xmin, xmax, ymin, ymax;
    double xunit = 0; ///< > 0: x ticks at whole multiples of it (a histogram's class edges)
    double px(double x) const { return x0 + (x - xmin) / (xmax - xmin) * w; }
    double py(double y) const { return y0 + h - (y - ymin) / (ymax - ymin) * h; }
    void draw(cairo_t* cr, const std::string& xlabel, const std::string& ylabel,
              const std::string& title) const {
        terrain::begin_axes();
        cairo_set_source_rgb(cr, 0, 0, 0);
        cairo_set_line_width(cr, 1);
        cairo_rectangle(cr, x0, y0, w, h);
        cairo_stroke(cr);
        double sx = nice_step(xmax - xmin);
        if (xunit > 0) sx = xunit * std::max(1.0, std::round(sx / xunit));
        const double sy = nice_step(ymax - ymin);
        for (double v = std::ceil(xmin / sx) * sx; v <= xmax + 1e-9; v += sx) {
            cairo_move_to(cr, px(v), y0 + h);
            cairo_line_to(cr, px(v), y0 + h + 5);
            cairo_stroke(cr);
            text(cr, px(v), y0 + h + 18, fmt(v, terrain::tick_digits(sx)), 12, 0.5, "xtick");
        }
        double widest = 0; // the y label goes left of the widest tick label
        for (double v = std::ceil(ymin / sy) * sy; v <= ymax + 1e-9; v += sy) {
            cairo_move_to(cr, x0 - 5, py(v));
            cairo_line_to(cr, x0, py(v));
            cairo_stroke(cr);
            const std::string label = fmt(v, terrain::tick_digits(sy));
            text(cr, x0 - 8, py(v) + 4, label, 12, 1.0, "ytick");
            widest = std::max(widest, terrain::text_width(label, 12));
        }
        text(cr, x0 + w / 2, y0 + h + 38, xlabel, 13, 0.5, "xlabel");
        terrain::draw_text_vertical(cr, x0 - 16 - widest, y0 + h / 2, ylabel, 13);
        text(cr, x0 + w / 2, y0 - 10, title, 14, 0.5, "title");
    }
};

void white(cairo_t* cr) {
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_paint(cr);
}

/// A map of the grid `g` in a square of about kMapPx pixels: metres to pixels, y up.
struct MapFrame {
    GridSpec g;
    double scale = 1, top = 30;
    int w = 0, h = 0;
    explicit MapFrame(const GridSpec& grid, double px = 760.0) : g(grid) {
        scale = px / std::max(g.width_m(), g.height_m());
        w = static_cast<int>(std::ceil(g.width_m() * scale));
        h = static_cast<int>(std::ceil(g.height_m() * scale));
    }
    double x(double xm) const { return (xm - g.origin_x_m) * scale; }
    double y(double ym) const { return top + (g.height_m() - (ym - g.origin_y_m)) * scale; }
};

/// Speed colours: red (0) through yellow to green (the top speed).
terrain::Rgb speed_rgb(double fraction) {
    const double f = std::clamp(fraction, 0.0, 1.0);
    auto byte = [](double v) { return static_cast<std::uint8_t>(std::lround(255 * v)); };
    return {byte(f < 0.5 ? 0.85 : 0.85 * (1 - f) * 2), byte(f < 0.5 ? 1.6 * f : 0.75), byte(0.1)};
}
void speed_colour(cairo_t* cr, double fraction, double alpha = 1.0) {
    const terrain::Rgb c = speed_rgb(fraction);
    cairo_set_source_rgba(cr, c.r / 255.0, c.g / 255.0, c.b / 255.0, alpha);
}

void draw_stems(const Ecosystem& eco, const fs::path& path) {
    const auto& g = eco.plant_grid();
    const auto& dem = eco.scene().hydro.dem;
    constexpr double kMapPx = 760.0, kLegendPx = 220.0;
    const double scale = kMapPx / std::max(g.width_m(), g.height_m());
    const int mw = static_cast<int>(std::ceil(g.width_m() * scale));
    const int mh = static_cast<int>(std::ceil(g.height_m() * scale));
    const auto& species = eco.scene().ecosystem.species;
    const StandMetrics st = eco.stand();
    const std::vector<Plant> plants = eco::rows(eco.plants());
    const std::string title = "Year " + std::to_string(eco.years_done()) + ": " +
                              std::to_string(plants.size()) + " plants, BA " +
                              fmt(st.basal_area_m2_per_ha) + " m2/ha (" +
                              fmt(st.basal_area_m2_per_ha * kFt2PerAcrePerM2PerHa) + " ft2/acre)";
    // The legend's width and height and the title's width decide the picture's size on narrow
    // or flat maps.
    double legend_w = kLegendPx;
    for (const auto& sp : species)
        legend_w = std::max(legend_w, 34 + terrain::text_width(sp.name, 12) + 12);
    const double below = 50 + 24.0 * static_cast<double>(species.size());
    const int width = static_cast<int>(
        std::ceil(std::max(mw + legend_w, 10 + terrain::text_width(title, 14) + 10)));
    SurfaceOwner s(width, static_cast<int>(std::ceil(std::max(mh + 40.0, below + 60))));
    cairo_t* cr = s.cr;
    white(cr);
    terrain::paint_image(cr, terrain::hillshade_image(dem), 0, 30, mw, mh, true);
    // Crowns, largest first so small plants stay visible.
    std::vector<std::size_t> order(eco.plants().size());
    for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        return plants[a].crown_radius_m > plants[b].crown_radius_m;
    });
    cairo_set_line_width(cr, 0.8);
    // Crowns of plants near the edges stay on the map.
    cairo_save(cr);
    cairo_rectangle(cr, 0, 30, mw, mh);
    cairo_clip(cr);
    for (const std::size_t k : order) {
        const Plant& p = plants[k];
        const auto* c = kPalette[std::min<std::size_t>(p.species, 7)];
        const double cx = (p.x_m - g.origin_x_m) * scale;
        const double cy = 30 + (g.height_m() - (p.y_m - g.origin_y_m)) * scale;
        const double r = std::max(1.0, p.crown_radius_m * scale);
        cairo_arc(cr, cx, cy, r, 0, 2 * M_PI);
        cairo_set_source_rgba(cr, c[0], c[1], c[2], 0.55);
        cairo_fill_preserve(cr);
        cairo_set_source_rgba(cr, 0.1, 0.1, 0.1, 0.8);
        cairo_stroke(cr);
    }
    cairo_restore(cr);
    cairo_set_source_rgb(cr, 0, 0, 0);
    text(cr, 10, 20, title, 14, 0, "title");
    for (std::size_t k = 0; k < species.size(); ++k) {
        const auto* c = kPalette[std::min<std::size_t>(k, 7)];
        const double y = 50 + 24.0 * static_cast<double>(k);
        cairo_set_source_rgb(cr, c[0], c[1], c[2]);
        cairo_arc(cr, mw + 20, y - 4, 7, 0, 2 * M_PI);
        cairo_fill(cr);
        cairo_set_source_rgb(cr, 0, 0, 0);
        text(cr, mw + 34, y, species[k].name, 12, 0, "legend");
    }
    text(cr, mw + 12, below + 10, "circle = crown; north up", 11);
    terrain::draw_scale_bar(cr, mw + 14, below + 36, scale, kLegendPx - 80);
    s.save(path);
}

void draw_histogram(const Ecosystem& eco, const fs::path& path) {
    SurfaceOwner s(720, 460);
    cairo_t* cr = s.cr;
    white(cr);
    const StandMetrics st = eco.stand();
    const double w = st.class_width_cm;
    const double nclass = std::max<double>(4, static_cast<double>(st.histogram.size()));
    double ymax = 1;
    for (auto c : st.histogram) ymax = std::max(ymax, static_cast<double>(c) / st.area_ha);
    // The frame holds the fitted curve too, from the first class middle on.
    if (st.fit_valid)
        ymax = std::max(ymax, std::exp(st.intercept - st.rate_per_cm * 0.5 * w) / st.area_ha);
    Frame f{80, 40, 600, 340, 0, nclass * w, 0, ymax * 1.1, w};
    for (std::size_t i = 0; i < st.histogram.size(); ++i) {
        const double v = static_cast<double>(st.histogram[i]) / st.area_ha;
        cairo_rectangle(cr, f.px(static_cast<double>(i) * w) + 1, f.py(v), f.px(w) - f.px(0) - 2,
                        f.py(0) - f.py(v));
        cairo_set_source_rgb(cr, 0.34, 0.71, 0.91);
        cairo_fill(cr);
    }
    if (st.fit_valid) {
        cairo_set_source_rgb(cr, 0.84, 0.37, 0.0);
        cairo_set_line_width(cr, 2);
        for (int k = 0; k <= 200; ++k) {
            const double x = 0.5 * w + (nclass - 1) * w * k / 200.0;
            const double y = std::exp(st.intercept - st.rate_per_cm * x) / st.area_ha;
            (k == 0 ? cairo_move_to : cairo_line_to)(cr, f.px(x), f.py(y));
        }
        cairo_stroke(cr);
        cairo_set_source_rgb(cr, 0, 0, 0);
        text(cr, f.x0 + f.w - 10, f.y0 + 20,
             "N = k exp(-" + fmt(st.rate_per_cm, 3) + " d), q = " + fmt(st.q_per_class, 2) +
                 " per " + fmt(st.class_width_cm, 0) + " cm, R2 = " + fmt(st.r2, 2),
             12, 1.0);
    }
    f.draw(cr, "trunk diameter at breast height (cm), " + fmt(w, 0) + " cm classes", "stems per ha",
           "Year " + std::to_string(eco.years_done()) + ", BA " + fmt(st.basal_area_m2_per_ha) +
               " m2/ha, " + fmt(st.stems_per_ha, 0) + " stems/ha");
    s.save(path);
}

void draw_history(const Ecosystem& eco, const fs::path& path) {
    SurfaceOwner s(1320, 760);
    cairo_t* cr = s.cr;
    white(cr);
    const Table& t = eco.yearly();
    const auto col = [&](const char* name) -> const std::vector<double>& {
        for (std::size_t k = 0; k < t.names.size(); ++k)
            if (t.names[k] == name) return t.columns[k];
        throw Error(std::string("no yearly column ") + name);
    };
    const auto& year = col("year");
    // A panel of one or more yearly series (scaled by `factor`), with a legend when several.
    using Series = std::pair<std::string, std::vector<double>>;
    const auto panel = [&](const std::vector<Series>& series, double x0, double y0,
                           const std::string& label, const std::string& title) {
        double ymax = 0;
        for (const auto& [name, y] : series)
            for (double v : y) ymax = std::max(ymax, v);
        if (!(ymax > 0)) ymax = 1; // nothing yet: an axis from 0 to 1, not to 1e-9
        const Frame f{x0, y0,        520, 250, 0, std::max(1.0, year.empty() ? 1.0 : year.back()),
                      0,  ymax * 1.1};
        for (std::size_t k = 0; k < series.size(); ++k) {
            const auto* c = kPalette[(k + 4) % 8];
            cairo_set_source_rgb(cr, c[0], c[1], c[2]);
            cairo_set_line_width(cr, 2);
            const auto& y = series[k].second;
            for (std::size_t i = 0; i < y.size() && i < year.size(); ++i)
                (i == 0 ? cairo_move_to : cairo_line_to)(cr, f.px(year[i]), f.py(y[i]));
            cairo_stroke(cr);
            if (series.size() > 1) {
                const double ly = f.y0 + 16 + 16.0 * static_cast<double>(k);
                cairo_rectangle(cr, f.x0 + 10, ly - 9, 14, 10);
                cairo_fill(cr);
                cairo_set_source_rgb(cr, 0, 0, 0);
                text(cr, f.x0 + 30, ly, series[k].first, 12);
            }
        }
        cairo_set_source_rgb(cr, 0, 0, 0);
        f.draw(cr, "simulation year", label, title);
    };
    const double area_ha = eco.plant_grid().width_m() * eco.plant_grid().height_m() / 1e4;
    auto scaled = [](const std::vector<double>& v, double k) {
        std::vector<double> out(v);
        for (double& x : out) x *= k;
        return out;
    };
    panel({{"basal area", col("basal_area_m2_per_ha")}}, 90, 50, "m2/ha", "Basal area");
    panel({{"stems", col("stems_per_ha")}}, 760, 50, "stems/ha", "Stems at breast height");
    panel({{"quadratic mean", scaled(col("quadratic_mean_dbh_m"), 100)},
           {"arithmetic mean", scaled(col("mean_dbh_m"), 100)}},
          90, 440, "cm", "Mean trunk diameter at breast height");
    panel({{"starvation", scaled(col("deaths_starvation"), 1 / area_ha)},
           {"suppression", scaled(col("deaths_suppression"), 1 / area_ha)},
           {"overlap (light-only)", scaled(col("deaths_overlap"), 1 / area_ha)},
           {"age", scaled(col("deaths_age"), 1 / area_ha)},
           {"background", scaled(col("deaths_background"), 1 / area_ha)}},
          760, 440, "deaths per ha and year", "Deaths by cause (all plants)");
    text(cr, 20, 24,
         "Stand history: " + eco.scene().ecosystem.name + ", " + fmt(area_ha, 2) + " ha, " +
             competition_name(eco.scene().competition) + " competition",
         16);
    s.save(path);
}

} // namespace

std::array<double, 3> species_colour(std::size_t k) {
    const auto* c = kPalette[std::min<std::size_t>(k, 7)];
    return {c[0], c[1], c[2]};
}

void draw_run_pictures(const Ecosystem& eco, const fs::path& dir) {
    io::create_folder(dir, "the picture folder");
    draw_stems(eco, dir / "stems.png");
    draw_histogram(eco, dir / "dbh_histogram.png");
    draw_history(eco, dir / "stand_history.png");
    const auto& hy = eco.hydrology();
    hydro::write_water_pictures(eco.scene().hydro.dem, eco.scene().hydro.soil, hy.soil_moisture(),
                                hy.surface_water_depth(),
                                "end of simulation day " + std::to_string(eco.days_done()) +
                                    " (year " + std::to_string(eco.years_done()) +
                                    ", day of year " + std::to_string(eco.last_weather().doy) + ")",
                                dir);
}

namespace {

/// Stems: obstacles dark red, stems pushed over orange, the rest grey; true size, at least a
/// pixel.
void draw_smg_stems(cairo_t* cr, const MapFrame& f, const mobility::StandMobility& m) {
    std::vector<char> pushed(m.stems.size(), 0);
    for (const auto& l : m.lines)
        for (const auto k : l.result.pushed_stems) pushed[static_cast<std::size_t>(k)] = 1;
    for (std::size_t k = 0; k < m.stems.size(); ++k) {
        const auto& st = m.stems[k];
        const bool obstacle = st.diameter_m >= m.critical_diameter_m;
        cairo_arc(cr, f.x(st.x_m), f.y(st.y_m), std::max(1.0, 0.5 * st.diameter_m * f.scale), 0,
                  2 * M_PI);
        // Colours apart from the paths' red-yellow-green: avoided black, pushed over blue.
        if (obstacle)
            cairo_set_source_rgb(cr, 0.0, 0.0, 0.0);
        else if (pushed[k])
            cairo_set_source_rgb(cr, 0.0, 0.45, 0.70);
        else
            cairo_set_source_rgba(cr, 0.45, 0.45, 0.45, 0.6);
        cairo_fill(cr);
    }
}

/// Up to this many lines every straight line is drawn dashed and the paths 2 px wide.
constexpr std::size_t kFewLines = 40;

/// Lines: the straight line thin and dashed, the path driven coloured by its SMG; NOGO lines
/// black.
void draw_smg_lines(cairo_t* cr, const MapFrame& f, const mobility::StandMobility& m,
                    const mobility::Vehicle& v) {
    // Many lines (200 is common) would bury the map: thinner, translucent paths, and the straight
    // lines only where NOGO.
    const bool many = m.lines.size() > kFewLines;
    for (const auto& l : m.lines) {
        const auto& r = l.result;
        if (!many || r.nogo) {
            cairo_set_line_width(cr, 0.8);
            const double dash[] = {3.0, 3.0};
            cairo_set_dash(cr, dash, 2, 0);
            cairo_set_source_rgba(cr, 0, 0, 0, r.nogo ? 0.9 : 0.35);
            cairo_move_to(cr, f.x(l.a.x_m), f.y(l.a.y_m));
            cairo_line_to(cr, f.x(l.b.x_m), f.y(l.b.y_m));
            cairo_stroke(cr);
            cairo_set_dash(cr, nullptr, 0, 0);
        }
        if (r.nogo || r.path.empty()) continue;
        cairo_set_line_width(cr, many ? 1.0 : 2.0);
        speed_colour(cr, r.smg_m_per_s / v.top_speed_m_per_s, many ? 0.6 : 1.0);
        cairo_move_to(cr, f.x(r.path.front().x_m), f.y(r.path.front().y_m));
        for (const auto& p : r.path) cairo_line_to(cr, f.x(p.x_m), f.y(p.y_m));
        cairo_stroke(cr);
    }
}

void draw_smg_legend(cairo_t* cr, const MapFrame& f, const mobility::StandMobility& m,
                     const mobility::Vehicle& v) {
    const double lx = f.w + 14;
    double ly = 56;
    auto legend = [&](double r, double g, double b, const std::string& label) {
        cairo_set_source_rgb(cr, r, g, b);
        cairo_arc(cr, lx + 6, ly - 4, 6, 0, 2 * M_PI);
        cairo_fill(cr);
        cairo_set_source_rgb(cr, 0, 0, 0);
        text(cr, lx + 18, ly, label, 12, 0, "legend");
        ly += 22;
    };
    legend(0, 0, 0, "stem avoided (d >= " + fmt(kCmPerM * m.critical_diameter_m) + " cm)");
    legend(0.0, 0.45, 0.70, "stem pushed over");
    legend(0.45, 0.45, 0.45, "other stem");
    if (!m.log_list.empty()) {
        for (const bool high : {false, true}) {
            cairo_set_line_width(cr, 3);
            high ? cairo_set_source_rgb(cr, 0.45, 0.0, 0.35)
                 : cairo_set_source_rgb(cr, 0.6, 0.4, 0.2);
            cairo_move_to(cr, lx, ly - 4);
            cairo_line_to(cr, lx + 14, ly - 4);
            cairo_stroke(cr);
            cairo_set_source_rgb(cr, 0, 0, 0);
            text(cr, lx + 18, ly,
                 high ? "log above " + fmt(m.step_limit_m, 2) + " m (avoided)" : "log climbed", 12);
            ly += 22;
        }
    }
    text(cr, lx, ly, m.lines.size() > kFewLines ? "dashed: a NOGO line" : "dashed: the line", 12, 0,
         "legend");
    ly += 40;
    terrain::draw_colour_bar(cr, lx, ly, 16, 150, 0, v.top_speed_m_per_s, "path's SMG (m/s)",
                             speed_rgb);
    terrain::draw_scale_bar(cr, lx, ly + 180, f.scale, 150);
}

void draw_smg_map(const mobility::StandMobility& m, const mobility::Vehicle& v, const RasterD& dem,
                  const fs::path& file) {
    const MapFrame f(dem.grid());
    // The legend (stems, logs, the colour bar and the scale bar) sets the height of flat maps.
    const double legend_h = 56 + 22.0 * (3 + (m.log_list.empty() ? 0 : 2)) + 40 + 200 + 20;
    SurfaceOwner s(f.w + 250, static_cast<int>(std::ceil(std::max(f.h + 40.0, legend_h))));
    cairo_t* cr = s.cr;
    white(cr);
    terrain::paint_image(cr, terrain::hillshade_image(dem), 0, f.top, f.w, f.h, true);
    // Logs under the lines, then stems and lines, all clipped to the map: the parts of logs low
    // enough to climb in brown, the rest in purple.
    cairo_save(cr);
    cairo_rectangle(cr, 0, f.top, f.w, f.h);
    cairo_clip(cr);
    for (const auto& l : m.log_list) {
        cairo_set_line_width(cr, std::max(1.0, l.diameter_m * f.scale));
        // Split where the top's height (linear along the log) crosses the step limit.
        const double dh = l.height_b_m - l.height_a_m;
        const double u = dh != 0 ? std::clamp((m.step_limit_m - l.height_a_m) / dh, 0.0, 1.0)
                                 : (l.height_a_m > m.step_limit_m ? 1.0 : 0.0);
        const double ux = l.a.x_m + u * (l.b.x_m - l.a.x_m), uy = l.a.y_m + u * (l.b.y_m - l.a.y_m);
        for (const bool first : {true, false}) {
            const double h = first ? l.height_a_m : l.height_b_m;
            h > m.step_limit_m ? cairo_set_source_rgb(cr, 0.45, 0.0, 0.35)
                               : cairo_set_source_rgb(cr, 0.6, 0.4, 0.2);
            const auto& end = first ? l.a : l.b;
            cairo_move_to(cr, f.x(end.x_m), f.y(end.y_m));
            cairo_line_to(cr, f.x(ux), f.y(uy));
            cairo_stroke(cr);
        }
    }
    draw_smg_stems(cr, f, m);
    draw_smg_lines(cr, f, m, v);
    cairo_restore(cr);
    cairo_set_source_rgb(cr, 0, 0, 0);
    text(cr, 10, 20,
         v.name + ": " + std::to_string(m.lines.size()) + " lines, SMG mean " +
             fmt(m.smg_mean_m_per_s, 2) + " m/s, NOGO " + fmt(100 * m.nogo_fraction) + " %, BA " +
             fmt(m.basal_area_m2_per_ha) + " m2/ha",
         14, 0, "title");
    draw_smg_legend(cr, f, m, v);
    s.save(file);
}

void draw_smg_histogram(const mobility::StandMobility& m, const mobility::Vehicle& v,
                        const fs::path& file) {
    SurfaceOwner s(720, 460);
    cairo_t* cr = s.cr;
    white(cr);
    constexpr int kBins = 20;
    const double top = v.top_speed_m_per_s;
    std::vector<double> count(kBins, 0);
    for (const auto& l : m.lines) {
        const int b = std::min(kBins - 1, static_cast<int>(l.result.smg_m_per_s / top * kBins));
        count[static_cast<std::size_t>(std::max(b, 0))] += 1;
    }
    double ymax = 1;
    for (const double c : count) ymax = std::max(ymax, c);
    Frame f{80, 40, 600, 340, 0, top, 0, ymax * 1.1};
    for (int b = 0; b < kBins; ++b) {
        const double c = count[static_cast<std::size_t>(b)];
        cairo_rectangle(cr, f.px(b * top / kBins) + 1, f.py(c), f.px(top / kBins) - f.px(0) - 2,
                        f.py(0) - f.py(c));
        speed_colour(cr, (b + 0.5) / kBins);
        cairo_fill(cr);
    }
    f.draw(cr, "speed made good (m/s); NOGO lines at 0", "lines",
           "SMG of " + std::to_string(m.lines.size()) + " lines: mean " +
               fmt(m.smg_mean_m_per_s, 2) + ", median " + fmt(m.smg_median_m_per_s, 2) + " m/s");
    s.save(file);
}

} // namespace

void draw_mobility_pictures(const mobility::StandMobility& m, const mobility::Vehicle& v,
                            const RasterD& dem, const fs::path& dir) {
    io::create_folder(dir, "the picture folder");
    draw_smg_map(m, v, dem, dir / "smg_lines.png");
    draw_smg_histogram(m, v, dir / "smg_histogram.png");
}

namespace {

/// The hillshade's grey level (0-1) under each cell of the map grid `g` (nearest terrain cell).
std::vector<double> shade_under(const RasterD& dem, const GridSpec& g) {
    const RasterD h = terrain::hillshade(dem);
    std::vector<double> out(static_cast<std::size_t>(g.size()), 1.0);
    for (int j = 0; j < g.ny; ++j)
        for (int i = 0; i < g.nx; ++i) {
            const auto [ii, jj] = dem.grid().clamped_cell(g.x_of(i), g.y_of(j));
            const double v = h(ii, jj);
            out[static_cast<std::size_t>(j) * g.nx + i] = std::isnan(v) ? 1.0 : v;
        }
    return out;
}

/// `c` darkened by the hillshade (0.45 in full shade to 1 in full light).
terrain::Rgb shaded(terrain::Rgb c, double shade) {
    const double f = 0.45 + 0.55 * std::clamp(shade, 0.0, 1.0);
    auto ch = [&](std::uint8_t x) { return static_cast<std::uint8_t>(std::lround(x * f)); };
    return {ch(c.r), ch(c.g), ch(c.b)};
}

} // namespace

void draw_mobility_map_pictures(const mobility::MobilityMap& m, const RasterD& dem,
                                const fs::path& speed_png, const fs::path& limit_png) {
    using mobility::Limit;
    const GridSpec& g = m.grid;
    const std::vector<double> shade = shade_under(dem, g);
    const double top = std::max(m.top_speed_m_per_s, 1e-9);
    const terrain::Rgb nogo{150, 20, 20};
    terrain::Image speed(g.nx, g.ny), limit(g.nx, g.ny);
    const std::array<terrain::Rgb, mobility::kLimitKinds> colours{{{225, 225, 225},
                                                                   {150, 100, 50},
                                                                   {240, 150, 30},
                                                                   {40, 150, 50},
                                                                   {40, 90, 220},
                                                                   {120, 40, 140}}};
    for (int j = 0; j < g.ny; ++j)
        for (int i = 0; i < g.nx; ++i) {
            const double sh = shade[static_cast<std::size_t>(j) * g.nx + i];
            const terrain::Rgb c = m.go_fraction(i, j) > 0
                                       ? terrain::palette_colour(terrain::Palette::viridis,
                                                                 m.speed_mean_m_per_s(i, j) / top)
                                       : nogo;
            speed.at(i, g.ny - 1 - j) = shaded(c, sh);
            const std::uint8_t l = m.limiting(i, j);
            limit.at(i, g.ny - 1 - j) =
                l < colours.size() ? shaded(colours[l], sh) : terrain::Rgb{255, 255, 255};
        }
    terrain::MapFigure f;
    f.title = "Mean speed over " + std::to_string(m.headings_deg.size()) + " headings";
    f.bar_label = "speed (m/s)";
    f.vmin = 0;
    f.vmax = top;
    f.smooth = false;
    f.notes = {"dark red: NO-GO in every heading; shaded by the terrain",
               "mean " + format_number(std::round(m.mean_speed_m_per_s * 100) / 100) +
                   " m/s; GO in " + format_number(std::round(m.go_share * 1000) / 10) +
                   " % of cell-headings"};
    terrain::write_map_figure(speed, g, f, speed_png);
    terrain::MapFigure fl;
    fl.title = "What limits the vehicle (most headings)";
    fl.colour_bar = false;
    fl.smooth = false;
    for (int k = 0; k < mobility::kLimitKinds; ++k)
        fl.legend.push_back({std::string(mobility::limit_name(static_cast<Limit>(k))) + " " +
                                 format_number(std::round(m.limit_share[k] * 1000) / 10) + " %",
                             colours[static_cast<std::size_t>(k)]});
    fl.notes = {"shares of cell-headings; 'none': the vehicle's own power and top speed"};
    terrain::write_map_figure(limit, g, fl, limit_png);
}

void draw_route_picture(const RasterD& speed, double top, const mobility::Route& route,
                        const fs::path& png) {
    const GridSpec& g = speed.grid();
    terrain::Image img = terrain::colormap_image(speed, 0.0, std::max(top, 1e-9));
    auto mark = [&](mobility::Point p, terrain::Rgb c) {
        const auto [i, j] = g.clamped_cell(p.x_m, p.y_m);
        img.at(i, g.ny - 1 - j) = c;
    };
    for (const auto& p : route.path) mark(p, {255, 255, 255});
    if (!route.path.empty()) {
        mark(route.path.front(), {230, 30, 30});
        mark(route.path.back(), {30, 30, 230});
    }
    terrain::MapFigure f;
    f.title = "Fastest route over the mean speed";
    f.bar_label = "mean speed over the headings (m/s)";
    f.vmin = 0;
    f.vmax = std::max(top, 1e-9);
    f.smooth = false;
    f.notes = {"white: the route's cells; red: start; blue: goal",
               route.found
                   ? "time " + format_number(std::round(route.time_s * 10) / 10) + " s over " +
                         format_number(std::round(route.length_m)) + " m (straight " +
                         format_number(std::round(route.straight_m)) + " m)"
                   : "no route: the goal cannot be reached"};
    terrain::write_map_figure(img, g, f, png);
}

void draw_traverse_picture(const std::vector<mobility::MissionLine>& missions,
                           const std::vector<mobility::TraverseResult>& results, const RasterD& dem,
                           const fs::path& dir) {
    io::create_folder(dir, "the picture folder");
    const MapFrame f(dem.grid());
    SurfaceOwner s(f.w + 200, static_cast<int>(std::max(f.h + 40.0, 340.0)));
    cairo_t* cr = s.cr;
    white(cr);
    // The slope map (maximum gradient to a neighbour, as the roughness classes use), 0 to 1.
    terrain::paint_image(cr, terrain::colormap_image(terrain::max_gradient_map(dem), 0.0, 1.0), 0,
                         f.top, f.w, f.h, true);
    int ok = 0;
    for (std::size_t k = 0; k < missions.size() && k < results.size(); ++k) {
        const auto& m = missions[k];
        const auto& r = results[k];
        ok += r.success;
        cairo_set_line_width(cr, 2);
        if (r.success)
            cairo_set_source_rgb(cr, 0.1, 0.85, 0.2);
        else
            cairo_set_source_rgb(cr, 0.95, 0.1, 0.1);
        cairo_move_to(cr, f.x(m.start_x_m), f.y(m.start_y_m));
        cairo_line_to(cr, f.x(m.goal_x_m), f.y(m.goal_y_m));
        cairo_stroke(cr);
        if (!r.success) {
            const double len = std::hypot(m.goal_x_m - m.start_x_m, m.goal_y_m - m.start_y_m);
            const double t = len > 0 ? r.failed_at_m / len : 0;
            const double x = f.x(m.start_x_m + t * (m.goal_x_m - m.start_x_m));
            const double y = f.y(m.start_y_m + t * (m.goal_y_m - m.start_y_m));
            cairo_set_source_rgb(cr, 1, 1, 1);
            cairo_move_to(cr, x - 5, y - 5);
            cairo_line_to(cr, x + 5, y + 5);
            cairo_move_to(cr, x + 5, y - 5);
            cairo_line_to(cr, x - 5, y + 5);
            cairo_stroke(cr);
        }
    }
    cairo_set_source_rgb(cr, 0, 0, 0);
    text(cr, 10, 20,
         std::to_string(ok) + " of " + std::to_string(results.size()) +
             " missions succeed (green); failed (red, x where)",
         14, 0, "title");
    terrain::draw_colour_bar(cr, f.w + 14, 70, 16, 200, 0, 1, "slope (max gradient)", [](double t) {
        return terrain::palette_colour(terrain::Palette::viridis, t);
    });
    terrain::draw_scale_bar(cr, f.w + 14, 300, f.scale, 150);
    s.save(dir / "missions.png");
}

namespace {

/// The legend: a colour swatch and label per entry, top right inside the frame.
void legend(cairo_t* cr, const Frame& f, const std::vector<std::string>& labels) {
    for (std::size_t k = 0; k < labels.size(); ++k) {
        const auto c = kPalette[k % 8];
        const double y = f.y0 + 14 + 18.0 * static_cast<double>(k);
        cairo_set_source_rgb(cr, c[0], c[1], c[2]);
        cairo_rectangle(cr, f.x0 + f.w - 190, y - 9, 14, 10);
        cairo_fill(cr);
        cairo_set_source_rgb(cr, 0, 0, 0);
        text(cr, f.x0 + f.w - 170, y, labels[k], 12);
    }
}

/// Data range of the values, widened by 5 % (and to a unit range when all are equal).
std::pair<double, double> padded_range(const std::vector<double>& v, bool from_zero) {
    double lo = from_zero ? 0.0 : 1e300, hi = from_zero ? 0.0 : -1e300;
    for (double x : v)
        if (std::isfinite(x)) lo = std::min(lo, x), hi = std::max(hi, x);
    if (lo > hi) return {0.0, 1.0};
    if (hi - lo < 1e-12) return {lo - 0.5, hi + 0.5};
    const double pad = 0.05 * (hi - lo);
    return {from_zero && lo >= 0 ? lo : lo - pad, hi + pad};
}

} // namespace

void draw_line_plot(const std::vector<PlotSeries>& series, const std::string& title,
                    const std::string& xlabel, const std::string& ylabel, const std::string& note,
                    const std::filesystem::path& file) {
    SurfaceOwner s(760, 520);
    cairo_t* cr = s.cr;
    white(cr);
    std::vector<double> xs, ys;
    for (const auto& p : series) {
        xs.insert(xs.end(), p.x.begin(), p.x.end());
        ys.insert(ys.end(), p.y.begin(), p.y.end());
        ys.insert(ys.end(), p.lo.begin(), p.lo.end());
        ys.insert(ys.end(), p.hi.begin(), p.hi.end());
    }
    const auto [x0, x1] = padded_range(xs, false);
    const auto [y0, y1] = padded_range(ys, true);
    const Frame f{90, 40, 630, 380, x0, x1, y0, y1};
    std::vector<std::string> labels;
    for (std::size_t k = 0; k < series.size(); ++k) {
        const auto& p = series[k];
        const auto c = kPalette[k % 8];
        labels.push_back(p.label);
        if (p.lo.size() == p.x.size() && p.hi.size() == p.x.size() && !p.x.empty()) {
            cairo_set_source_rgba(cr, c[0], c[1], c[2], 0.22);
            for (std::size_t i = 0; i < p.x.size(); ++i)
                (i == 0 ? cairo_move_to : cairo_line_to)(cr, f.px(p.x[i]), f.py(p.hi[i]));
            for (std::size_t i = p.x.size(); i-- > 0;)
                cairo_line_to(cr, f.px(p.x[i]), f.py(p.lo[i]));
            cairo_close_path(cr);
            cairo_fill(cr);
        }
        cairo_set_source_rgb(cr, c[0], c[1], c[2]);
        cairo_set_line_width(cr, 2.5);
        for (std::size_t i = 0; i < p.x.size(); ++i)
            (i == 0 ? cairo_move_to : cairo_line_to)(cr, f.px(p.x[i]), f.py(p.y[i]));
        cairo_stroke(cr);
        for (std::size_t i = 0; i < p.x.size(); ++i) {
            cairo_arc(cr, f.px(p.x[i]), f.py(p.y[i]), 4, 0, 2 * M_PI);
            cairo_fill(cr);
        }
    }
    legend(cr, f, labels);
    cairo_set_source_rgb(cr, 0, 0, 0);
    f.draw(cr, xlabel, ylabel, title);
    text(cr, f.x0, f.y0 + f.h + 62, note, 12);
    s.save(file);
}

void draw_histogram_plot(const std::vector<HistogramSeries>& series, double class_width_cm,
                         const std::string& title, const std::string& note,
                         const std::filesystem::path& file) {
    SurfaceOwner s(760, 520);
    cairo_t* cr = s.cr;
    white(cr);
    std::size_t classes = 4;
    double ymax = 1;
    for (const auto& h : series) {
        classes = std::max(classes, h.stems_per_ha.size());
        for (double v : h.stems_per_ha) ymax = std::max(ymax, v);
    }
    const double w = class_width_cm;
    const Frame f{90, 40, 630, 380, 0, static_cast<double>(classes) * w, 0, ymax * 1.1, w};
    const double n = std::max<double>(1, static_cast<double>(series.size()));
    std::vector<std::string> labels;
    for (std::size_t k = 0; k < series.size(); ++k) {
        const auto& h = series[k];
        const auto c = kPalette[k % 8];
        cairo_set_source_rgba(cr, c[0], c[1], c[2], 0.85);
        for (std::size_t i = 0; i < h.stems_per_ha.size(); ++i) {
            const double left = f.px(static_cast<double>(i) * w) + 1;
            const double bw = (f.px(w) - f.px(0) - 2) / n;
            const double v = h.stems_per_ha[i];
            cairo_rectangle(cr, left + bw * static_cast<double>(k), f.py(v), bw, f.py(0) - f.py(v));
        }
        cairo_fill(cr);
        std::string label = h.label;
        if (h.fit) {
            // The fit is drawn over every class; above the frame it is cut at the frame's edge.
            cairo_set_source_rgb(cr, c[0] * 0.7, c[1] * 0.7, c[2] * 0.7);
            cairo_set_line_width(cr, 2);
            cairo_save(cr);
            cairo_rectangle(cr, f.x0, f.y0, f.w, f.h);
            cairo_clip(cr);
            for (int j = 0; j <= 200; ++j) {
                const double x = 0.5 * w + (static_cast<double>(classes) - 1) * w * j / 200.0;
                const double y = std::exp(h.intercept - h.rate_per_cm * x);
                (j == 0 ? cairo_move_to : cairo_line_to)(cr, f.px(x), f.py(y));
            }
            cairo_stroke(cr);
            cairo_restore(cr);
            label += ": q " + fmt(h.q_per_class, 2) + ", R2 " + fmt(h.r2, 2);
        }
        labels.push_back(label);
    }
    legend(cr, f, labels);
    cairo_set_source_rgb(cr, 0, 0, 0);
    f.draw(cr, "trunk diameter at breast height (cm), " + fmt(w, 0) + " cm classes",
           "stems per ha (mean of the members)", title);
    text(cr, f.x0, f.y0 + f.h + 62, note, 12);
    s.save(file);
}

} // namespace ecoterra::run
