#include "ecoterra/terrain/analysis.hpp"

#include "ecoterra/io/atomic_file.hpp"

#include "ecoterra/terrain/picture.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace ecoterra::terrain {

void AnalysisOptions::validate() const {
    thresholds.validate();
    psd.validate();
    fd.validate();
    if (!(border_m >= 0)) throw InputError("--border must be >= 0 m");
    if (!(closing_radius_m >= 0)) throw InputError("--closing-radius must be >= 0 m");
}

TerrainAnalysis analyze_terrain(const RasterD& z, const AnalysisOptions& opt) {
    opt.validate();
    require_valid_cells(z, "terrain analysis");
    TerrainAnalysis a;
    a.elevation = stats(z);
    a.rms = rms_roughness(z, opt.rms);
    const RasterD g = max_gradient_map(z);
    a.class_map = classify_gradient(g, opt.thresholds);
    a.classes = class_areas(a.class_map, opt.border_m);
    a.closed_class_map = close_classes(a.class_map, opt.closing_radius_m);
    a.closed_classes = class_areas(a.closed_class_map, opt.border_m);
    a.psd = radial_psd(z, opt.psd);
    a.fd = fractal_dimension(z, opt.fd);
    const auto sa = slope_aspect(z);
    const auto ss = stats(sa.slope);
    a.mean_slope = ss.mean;
    a.max_slope = ss.max;
    a.notes = scale_notes(opt, z.cell_size());
    a.detrended_valid = opt.rms.detrend_window_m >= 2 * z.cell_size();
    a.band_limited_valid = opt.rms.band_long_cutoff_m >= 2 * z.cell_size();
    return a;
}

std::vector<std::string> scale_notes(const AnalysisOptions& opt, double cell_m) {
    std::vector<std::string> parts;
    char b[240];
    auto add = [&](bool when, const char* f, double v) {
        if (!when) return;
        std::snprintf(b, sizeof b, f, v);
        parts.emplace_back(b);
    };
    const double two = 2 * cell_m;
    add(opt.rms.detrend_window_m < two, "the detrended RMS (its %.3g m window is under two cells)",
        opt.rms.detrend_window_m);
    add(opt.rms.band_long_cutoff_m < two,
        "the band-limited RMS (wavelengths under %.3g m are shorter than two cells)",
        opt.rms.band_long_cutoff_m);
    add(opt.closing_radius_m < cell_m, "the class map's closing (its %.3g m disk is under a cell)",
        opt.closing_radius_m);
    add(opt.border_m > 0 && opt.border_m < cell_m, "the border (%.3g m, under a cell)",
        opt.border_m);
    add(cell_m > 5,
        "the slope classes (slopes over %.4g m cells are far gentler than a vehicle "
        "meets; paper 000's classes are for cells of a few metres)",
        cell_m);
    // The closing and the border alone (cells of 0.25-5 m) are not worth a note: the figures that
    // matter are the RMS windows and the classes.
    if (!(opt.rms.detrend_window_m < two || opt.rms.band_long_cutoff_m < two || cell_m > 5))
        return {};
    std::string t;
    for (std::size_t k = 0; k < parts.size(); ++k)
        t += (k == 0 ? "" : k + 1 == parts.size() ? " and " : ", ") + parts[k];
    std::snprintf(b, sizeof b,
                  "cells of %.4g m are too coarse for the vehicle-scale figures: ", cell_m);
    std::string head = b;
    std::snprintf(b, sizeof b,
                  ". Analyse a window of the DEM resampled to about 1 m (a scene's terrain.window "
                  "and terrain.cell_m), or give windows of %.4g m or more",
                  two);
    return {head + t + b};
}

nlohmann::json TerrainAnalysis::to_json(const AnalysisOptions& opt) const {
    using nlohmann::json;
    json bins = json::array();
    for (const auto& b : psd.bins)
        bins.push_back({{"k_cycles_per_m", b.k_cpm},
                        {"psd_m4", b.power},
                        {"count", b.count},
                        {"fitted", b.fitted}});
    json curve = json::array();
    for (std::size_t k = 0; k < fd.lag_m.size(); ++k)
        curve.push_back({{"lag_m", fd.lag_m[k]}, {"value_m", fd.structure_m[k]}});
    auto areas = [](const ClassAreas& c) {
        return json{{"low", c.low_pct},
                    {"semi", c.semi_pct},
                    {"high", c.high_pct},
                    {"cells_counted", c.cells}};
    };
    return {{"elevation_m",
             {{"min", elevation.min},
              {"max", elevation.max},
              {"mean", elevation.mean},
              {"std", elevation.stddev},
              {"valid_cells", elevation.valid}}},
            {"rms_m", rms.rms_m},
            {"rms_detrended_m", detrended_valid ? json(rms.rms_detrended_m) : json()},
            {"rms_band_limited_m", band_limited_valid ? json(rms.rms_band_limited_m) : json()},
            {"notes", notes},
            {"rms_options",
             {{"detrend_window_m", opt.rms.detrend_window_m},
              {"band_long_cutoff_m", opt.rms.band_long_cutoff_m},
              {"band_short_cutoff_m", opt.rms.band_short_cutoff_m}}},
            {"classes_pct", areas(classes)},
            {"closed_classes_pct", areas(closed_classes)},
            {"class_options",
             {{"low_max_slope", opt.thresholds.low},
              {"semi_max_slope", opt.thresholds.high},
              {"border_m", opt.border_m},
              {"closing_radius_m", opt.closing_radius_m}}},
            {"slope", {{"mean", mean_slope}, {"max", max_slope}}},
            {"psd_slope", psd.slope},
            {"psd",
             {{"slope", psd.slope},
              {"r2", psd.r2},
              {"fit_min_cycles_per_m", psd.fit_min_cpm},
              {"fit_max_cycles_per_m", psd.fit_max_cpm},
              {"implied_dimension", psd.dimension},
              {"bin_ratio", opt.psd.bin_ratio},
              {"bins", bins}}},
            {"fractal_dimension_fit",
             {{"value", fd.dimension},
              {"hurst", fd.hurst},
              {"range_m", {fd.range_min_m, fd.range_max_m}},
              {"r2", fd.r2},
              {"estimator",
               opt.fd.estimator == DimensionEstimator::variogram ? "variogram" : "madogram"},
              {"curve", curve}}}};
}

namespace {
std::string metres(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%.4g m", v);
    return b;
}
} // namespace

std::string TerrainAnalysis::summary(const AnalysisOptions& opt) const {
    char buf[2048];
    std::snprintf(
        buf, sizeof buf,
        "elevation        %.4g .. %.4g m (mean %.4g, std %.4g), %lld valid cells\n"
        "RMS roughness    %.4g m plain, %s detrended (%.3g m window), %s band-limited "
        "(< %.3g m)\n"
        "slope            mean %.3f, max %.3f (rise over run)\n"
        "classes          low %.2f %%, semi %.2f %%, high %.2f %% (slope <= %.3f / <= %.3f, "
        "%.3g m border)\n"
        "closed classes   low %.2f %%, semi %.2f %%, high %.2f %% (disk radius %.3g m)\n"
        "PSD slope        %.3f over %.3g..%.3g cycles/m (r2 %.4f, implies D = %.3f)\n"
        "fractal dim.     D = %.3f (H = %.3f) over %.3g..%.3g m, r2 %.4f\n",
        elevation.min, elevation.max, elevation.mean, elevation.stddev,
        static_cast<long long>(elevation.valid), rms.rms_m,
        detrended_valid ? metres(rms.rms_detrended_m).c_str() : "n/a", opt.rms.detrend_window_m,
        band_limited_valid ? metres(rms.rms_band_limited_m).c_str() : "n/a",
        opt.rms.band_long_cutoff_m, mean_slope, max_slope, classes.low_pct, classes.semi_pct,
        classes.high_pct, opt.thresholds.low, opt.thresholds.high, opt.border_m,
        closed_classes.low_pct, closed_classes.semi_pct, closed_classes.high_pct,
        opt.closing_radius_m, psd.slope, psd.fit_min_cpm, psd.fit_max_cpm, psd.r2, psd.dimension,
        fd.dimension, fd.hurst, fd.range_min_m, fd.range_max_m, fd.r2);
    return buf;
}

namespace {

/// The q-quantile of the finite values (nearest rank).
double quantile_of(const RasterD& z, double q) {
    std::vector<double> v;
    v.reserve(static_cast<std::size_t>(z.size()));
    for (Eigen::Index k = 0; k < z.size(); ++k)
        if (std::isfinite(z.data()[k])) v.push_back(z.data()[k]);
    if (v.empty()) return 0;
    const auto n = static_cast<std::size_t>(q * static_cast<double>(v.size() - 1) + 0.5);
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(n), v.end());
    return v[n];
}

std::string fixed(double v, int digits) {
    char b[48];
    std::snprintf(b, sizeof b, "%.*f", digits, v);
    return b;
}

} // namespace

std::vector<std::filesystem::path> write_analysis_pictures(const RasterD& z,
                                                           const TerrainAnalysis& a,
                                                           const AnalysisOptions& opt,
                                                           const std::filesystem::path& dir) {
    io::create_folder(dir, "the picture folder");
    std::vector<std::filesystem::path> out;
    const GridSpec& g = z.grid();
    auto put = [&](const Image& img, const MapFigure& f, const char* name) {
        out.push_back(dir / name);
        write_map_figure(img, g, f, out.back());
    };
    const RasterD shade = hillshade(z);
    const int border = static_cast<int>(std::ceil(opt.border_m / z.cell_size() - 1e-9));
    const auto s = stats(z);
    const std::string full = "elevation " + fixed(s.min, 3) + " to " + fixed(s.max, 3) +
                             " m, standard deviation " + fixed(s.stddev, 3) + " m";
    {
        MapFigure f;
        f.title = "Hillshade";
        f.colour_bar = false;
        f.notes = {"light from the north-west (azimuth 315 deg, altitude 45 deg)", full};
        put(hillshade_image(z), f, "hillshade.png");
    }
    {
        // The colours span the 2nd to 98th percentile, so that one high corner does not wash
        // out the rest.
        MapFigure f;
        f.title = "Elevation";
        f.bar_label = "elevation (m)";
        f.vmin = quantile_of(z, 0.02);
        f.vmax = quantile_of(z, 0.98);
        if (!(f.vmax > f.vmin)) f.vmin = s.min, f.vmax = s.max > s.min ? s.max : s.min + 1;
        f.notes = {"colours span the 2nd to 98th percentile (" + fixed(f.vmin, 3) + " to " +
                       fixed(f.vmax, 3) + " m); lower and higher cells take the end colours",
                   full};
        put(colormap_image(z, f.vmin, f.vmax), f, "elevation.png");
    }
    {
        const RasterD slope = slope_aspect(z).slope;
        MapFigure f;
        f.title = "Slope (steepest descent, Horn)";
        f.bar_label = "slope (rise/run)";
        f.vmin = 0;
        f.vmax = 2.0 * opt.thresholds.high;
        std::int64_t above = 0, valid = 0;
        for (Eigen::Index k = 0; k < slope.size(); ++k)
            if (std::isfinite(slope.data()[k])) ++valid, above += slope.data()[k] > f.vmax;
        f.notes = {"fixed range 0 to " + fixed(f.vmax, 3) + " (twice the semi/high class limit); " +
                       fixed(valid ? 100.0 * static_cast<double>(above) / valid : 0.0, 1) +
                       " % of cells are steeper and take the top colour",
                   "mean slope " + fixed(a.mean_slope, 3) + ", steepest " + fixed(a.max_slope, 3)};
        put(colormap_image(slope, f.vmin, f.vmax), f, "slope.png");
    }
    auto classes = [&](const RasterU8& map, const ClassAreas& c, const char* title,
                       const char* name, const std::string& how) {
        MapFigure f;
        f.title = title;
        f.smooth = false;
        const std::string lo = fixed(opt.thresholds.low, 3), hi = fixed(opt.thresholds.high, 3);
        const Image img = classes_image(map, &shade, border);
        f.legend = {
            {"low\ngradient <= " + lo + "\n" + fixed(c.low_pct, 1) + " % of area", class_colour(0)},
            {"semi\n<= " + hi + "\n" + fixed(c.semi_pct, 1) + " % of area", class_colour(1)},
            {"high\n> " + hi + "\n" + fixed(c.high_pct, 1) + " % of area", class_colour(2)}};
        f.notes = {"colours of Majhor & Bos Fig. 4, shaded by the hillshade; " + how,
                   "the darker " + fixed(opt.border_m, 2) +
                       " m border is left out of the percentages and the missions"};
        put(img, f, name);
    };
    classes(a.class_map, a.classes, "Roughness classes (Moore-neighbourhood maximum gradient)",
            "gradient_classes.png", "before closing (as the paper reports the areas)");
    classes(a.closed_class_map, a.closed_classes, "Roughness classes after closing",
            "closed_classes.png",
            "after a morphological closing with a disk of radius " +
                fixed(opt.closing_radius_m, 2) + " m");
    return out;
}

std::vector<Mission> plan_missions(const RasterD& z, const AnalysisOptions& opt, MissionOptions m) {
    opt.validate();
    m.border_m = opt.border_m;
    m.validate();
    const RasterU8 classes = classify_gradient(max_gradient_map(z), opt.thresholds);
    const RasterU8 closed = close_classes(classes, opt.closing_radius_m);
    return plan_missions(closed, classes, m);
}

} // namespace ecoterra::terrain
