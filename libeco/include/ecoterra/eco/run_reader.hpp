#pragma once
// Reading ecosystem runs: what `stand`, `export` and resume read from RUN.h5 and its snapshots.
#include "ecoterra/eco/outputs.hpp"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace ecoterra::eco {

/// What stand and export read from a run.
struct RunInfo {
    nlohmann::json provenance;
    std::vector<std::string> species;
    int snapshots = 0;
    double area_m2 = 0;
};
RunInfo read_run_info(const std::filesystem::path& run);

struct SnapshotPlants {
    int index = 0, year = 0;
    std::vector<PlantRecord> plants; ///< columns: plant_columns()
    /// One column of every plant, by its name in plant_columns().
    std::vector<double> values(const std::string& column) const;
};
/// Reads the plants of snapshot `index` (negative: counted from the last, -1 = last).
SnapshotPlants read_snapshot_plants(const std::filesystem::path& run, int index);

} // namespace ecoterra::eco
