#pragma once
// Pictures of an ecosystem run, drawn with Cairo.
#include "ecoterra/eco/ecosystem.hpp"

#include <filesystem>

namespace ecoterra::eco {

/// Per-run pictures (Cairo): stems over hillshade, moisture, standing water, the DBH histogram
/// with its exponential fit, basal area and stems over time.
void draw_run_pictures(const Ecosystem& eco, const std::filesystem::path& dir);

} // namespace ecoterra::eco
