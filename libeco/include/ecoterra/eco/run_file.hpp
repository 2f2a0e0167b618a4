#pragma once
// Ecosystem runs on disk (layout in docs/formats.md).
//
//   RUN.h5                     main file, replaced atomically after every snapshot: terrain, soil,
//                              species, provenance, yearly and daily series, the checkpoint of
//                              the state at the last snapshot, and /snapshots/NNNN links
//   RUN.snapshots/NNNN.h5      one file per snapshot, written atomically once and never touched
//                              again; /snapshots/NNNN in RUN.h5 is an HDF5 external link to it
// A crash or kill during a write leaves the earlier snapshots and the previous main file intact;
// `ecoterra run --resume RUN.h5` continues from the last checkpoint.
#include "ecoterra/eco/ecosystem.hpp"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <functional>
#include <optional>

namespace ecoterra::eco {

struct RunOptions {
    std::filesystem::path output;
    bool pictures = true;
    std::filesystem::path picture_dir; ///< default: RUN.pictures next to the output
    nlohmann::json provenance;         ///< version, command line (the scene is added)
    std::optional<int> years;          ///< years to run now (default: the scene's, less done)
    bool resume = false;
};

struct RunProgress {
    int year = 0, years = 0;
    std::size_t plants = 0;
    double basal_area_m2_per_ha = 0, seconds = 0, plant_years = 0;
};

struct RunSummary {
    int years_run = 0, years_total = 0, snapshots = 0;
    bool reached_target = false;
    StandMetrics stand;
    double seconds = 0, plant_years = 0;
    double water_residual_relative = 0, carbon_residual_relative = 0;
    std::filesystem::path picture_dir;
};

/// Runs a scene from its start (opt.resume false) or continues the run in opt.output.
RunSummary run_ecosystem(const EcoScene* scene, const RunOptions& opt,
                         const std::function<void(const RunProgress&)>& progress = {});

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

/// Per-run pictures (Cairo): stems over hillshade, moisture, standing water, the DBH histogram
/// with its exponential fit, basal area and stems over time.
void draw_run_pictures(const Ecosystem& eco, const std::filesystem::path& dir);

} // namespace ecoterra::eco
