#pragma once
// Running an ecosystem scene into a run file, and resuming one (file layout in docs/formats.md).
// The run file RUN.h5 is replaced atomically after every snapshot and each snapshot is a file of
// its own in RUN.snapshots/: a crash or kill during a write leaves the earlier snapshots and the
// previous run file intact, and `ecoterra run --resume RUN.h5` continues from the last checkpoint.
#include "ecoterra/eco/ecosystem.hpp"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <functional>
#include <memory>
#include <optional>

namespace ecoterra::run {

struct RunOptions {
    std::filesystem::path output;
    bool pictures = true;
    std::filesystem::path picture_dir; ///< default: RUN.pictures next to the output
    nlohmann::json provenance;         ///< version, command line (the scene is added)
    std::optional<int> years;          ///< years to run now (default: the scene's, less done)
    bool resume = false;
    /// A new run into the path of an earlier run replaces it (atomically) only if true; else
    /// InputError. Checked while holding the output's lock (io::FileLock), which every run holds
    /// for as long as it writes, so that two processes never write one run.
    bool replace = true;
};

struct RunProgress {
    int year = 0, years = 0;
    std::size_t plants = 0;
    double basal_area_m2_per_ha = 0, seconds = 0, plant_years = 0;
};

struct RunSummary {
    int years_run = 0, years_total = 0, snapshots = 0;
    bool reached_target = false;
    eco::StandMetrics stand;             ///< trees
    eco::UndergrowthMetrics undergrowth; ///< shrubs, objects, ground layer
    std::vector<std::string> species;
    double seconds = 0, plant_years = 0;
    double water_residual_relative = 0, carbon_residual_relative = 0;
    /// The water partition over all the run's days, mm per year over the domain.
    struct WaterPartition {
        double rain = 0, evaporation = 0, transpiration = 0, interception = 0, runoff_out = 0,
               drainage_out = 0, groundwater_out = 0, recharge = 0;
    } water_mm_per_yr;
    std::filesystem::path picture_dir;
    Methods methods;          ///< the published methods the run used (also in its provenance)
    eco::Diagnosis diagnosis; ///< why the stand is what it is (also in /diagnosis of the run)
};

/// The engine of the run file `run` at its last checkpoint, built from the scene the run stores,
/// as `ecoterra run --resume` starts it (the same checks: the checksum, the terrain): for a
/// library caller that steps it further itself (the Python module).
std::unique_ptr<eco::Ecosystem> load_run_engine(const std::filesystem::path& run);

/// Writes the engine as it stands into the run file `run`: one snapshot of its present state and
/// the checkpoint, so that `ecoterra stand`, `export`, `mobility` and `run --resume` read it as
/// any run. An existing file is refused unless `replace`; then it is replaced atomically (a
/// failure keeps it). The run's total years become the years done.
void write_run_file(const eco::Ecosystem& eco, const std::filesystem::path& run,
                    const nlohmann::json& provenance, bool replace);

/// Runs a scene from its start (opt.resume false) or continues the run in opt.output.
RunSummary run_ecosystem(const eco::EcoScene* scene, const RunOptions& opt,
                         const std::function<void(const RunProgress&)>& progress = {});

} // namespace ecoterra::run
