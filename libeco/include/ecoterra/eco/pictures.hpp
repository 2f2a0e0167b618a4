#pragma once
// Pictures of an ecosystem run, drawn with Cairo.
#include "ecoterra/eco/ecosystem.hpp"
#include "ecoterra/mobility/stand.hpp"
#include "ecoterra/mobility/traverse.hpp"

#include <filesystem>

namespace ecoterra::eco {

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
