#pragma once
// Pictures of an ecosystem run, drawn with Cairo.
#include "ecoterra/eco/ecosystem.hpp"
#include "ecoterra/mobility/stand.hpp"
#include "ecoterra/mobility/traverse.hpp"
#include "ecoterra/terrain/picture.hpp"

#include <array>

#include <filesystem>

typedef struct _cairo cairo_t; // cairo.h's own declaration

namespace ecoterra::eco {

/// Paints an image scaled to w x h pixels at (x, y) (shared with the export picture).
void paint_image(cairo_t* cr, const terrain::Image& im, double x, double y, double w, double h);
/// The colour of species k in every picture: Okabe-Ito (colour-blind safe), grey from the 8th.
std::array<double, 3> species_colour(std::size_t k);

/// Per-run pictures (Cairo): stems over hillshade, moisture, standing water, the DBH histogram
/// with its exponential fit, basal area and stems over time.
void draw_run_pictures(const Ecosystem& eco, const std::filesystem::path& dir);

/// `ecoterra mobility`: smg_lines.png (the lines over the stem map, stems avoided and pushed over
/// marked, the paths driven coloured by SMG) and smg_histogram.png, into `dir`.
void draw_mobility_pictures(const mobility::StandMobility& m, const mobility::Vehicle& v,
                            const RasterD& dem, const std::filesystem::path& dir);
/// `ecoterra terrain traverse`: missions.png in `dir`, the missions over the slope map coloured by
/// outcome.
void draw_traverse_picture(const std::vector<mobility::MissionLine>& missions,
                           const std::vector<mobility::TraverseResult>& results, const RasterD& dem,
                           const std::filesystem::path& dir);

} // namespace ecoterra::eco
