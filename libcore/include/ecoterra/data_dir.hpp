#pragma once
// Where ecoterra finds its data files (climates, runoff tables, ecosystems, scenes).
#include <filesystem>

namespace ecoterra {

/// The data folder: $ECOTERRA_DATA if set, else the nearest `share/ecoterra/data` in the running
/// program's folder or one of its three parents. `cmake --install` puts the data at
/// PREFIX/share/ecoterra/data beside PREFIX/bin/ecoterra; the build tree links BUILD/share/
/// ecoterra/data to the source tree's data/. Throws IoError naming the places searched.
std::filesystem::path data_dir();

} // namespace ecoterra
