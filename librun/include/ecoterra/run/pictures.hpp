#pragma once
// Pictures of an ecosystem run, drawn with Cairo.
#include "ecoterra/eco/ecosystem.hpp"
#include "ecoterra/mobility/map.hpp"
#include "ecoterra/mobility/route.hpp"
#include "ecoterra/mobility/stand.hpp"
#include "ecoterra/mobility/traverse.hpp"
#include "ecoterra/terrain/picture.hpp"

#include <array>
#include <string>
#include <vector>

#include <filesystem>

typedef struct _cairo cairo_t; // cairo.h's own declaration

namespace ecoterra::run {

/// The colour of species k in every picture: Okabe-Ito (colour-blind safe), grey from the 8th.
std::array<double, 3> species_colour(std::size_t k);

/// Per-run pictures (Cairo): stems over hillshade, moisture, standing water, the DBH histogram
/// with its exponential fit, basal area and stems over time.
void draw_run_pictures(const eco::Ecosystem& eco, const std::filesystem::path& dir);

/// `ecoterra mobility`: smg_lines.png (the lines over the stem map, stems avoided and pushed over
/// marked, the paths driven coloured by SMG) and smg_histogram.png, into `dir`.
void draw_mobility_pictures(const mobility::StandMobility& m, const mobility::Vehicle& v,
                            const RasterD& dem, const std::filesystem::path& dir);
/// `ecoterra mobility map`: speed.png (the mean speed over the headings over the hillshade, NO-GO
/// cells dark red, with a colour bar) and limiting_factor.png (the factor that limits most
/// headings, with a legend), written to the paths given.
void draw_mobility_map_pictures(const mobility::MobilityMap& m, const RasterD& dem,
                                const std::filesystem::path& speed_png,
                                const std::filesystem::path& limit_png);
/// `ecoterra mobility route`: the route's cells in white over the map's mean speed, with the
/// start and goal, its time and length in the notes.
void draw_route_picture(const RasterD& speed_mean_m_per_s, double top_speed_m_per_s,
                        const mobility::Route& route, const std::filesystem::path& png);
/// `ecoterra terrain traverse`: missions.png in `dir`, the missions over the slope map coloured by
/// outcome.
void draw_traverse_picture(const std::vector<mobility::MissionLine>& missions,
                           const std::vector<mobility::TraverseResult>& results, const RasterD& dem,
                           const std::filesystem::path& dir);

/// One series of a summary plot: y against x with an optional band (lo..hi, e.g. the 10th and
/// 90th percentiles) drawn behind it.
struct PlotSeries {
    std::string label;
    std::vector<double> x, y, lo, hi; ///< lo and hi empty: no band
};
/// A line plot of the series (720 x 500 px) with a legend, axes with units in the labels, and a
/// note at the bottom (what the band shows, how many members).
void draw_line_plot(const std::vector<PlotSeries>& series, const std::string& title,
                    const std::string& xlabel, const std::string& ylabel, const std::string& note,
                    const std::filesystem::path& file);

/// One mean diameter histogram: stems per ha per class, and its negative-exponential fit
/// N = exp(intercept - rate d) (per ha) when fit is true.
struct HistogramSeries {
    std::string label;
    std::vector<double> stems_per_ha;
    bool fit = false;
    double intercept = 0, rate_per_cm = 0, q_per_class = 0, r2 = 0;
};
/// The histograms side by side per class (720 x 500 px) with their fits and a legend.
void draw_histogram_plot(const std::vector<HistogramSeries>& series, double class_width_cm,
                         const std::string& title, const std::string& note,
                         const std::filesystem::path& file);

} // namespace ecoterra::run
