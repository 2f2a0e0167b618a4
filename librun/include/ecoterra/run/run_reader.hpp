#pragma once
// Reading ecosystem runs: what `stand`, `export` and resume read from RUN.h5 and its snapshots.
#include "ecoterra/eco/species.hpp"
#include "ecoterra/eco/stand_metrics.hpp"
#include "ecoterra/mobility/stand.hpp"
#include "ecoterra/raster.hpp"
#include "ecoterra/run/records.hpp"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace ecoterra::run {

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

/// The snags and logs of a snapshot (runs before dead wood, or with it off: none).
struct SnapshotDeadWood {
    int index = 0, year = 0;
    std::vector<DeadWoodRecord> pieces; ///< columns: deadwood_columns()
};
SnapshotDeadWood read_snapshot_deadwood(const std::filesystem::path& run, int index);

/// Shrubs, objects and the ground layer of snapshot `index` (runs before life forms: none).
eco::UndergrowthMetrics read_snapshot_undergrowth(const std::filesystem::path& run, int index);

/// A snapshot's plants as mobility sees them: trees by their DBH, shrubs by their stem at the
/// ground, objects as rigid obstacles (the ground layer has no stems).
std::vector<mobility::StandStem> stand_stems(const std::vector<PlantRecord>& plants);
/// A snapshot's dead wood as mobility sees it: snags as standing stems, logs as steps on the
/// ground (their tops' heights at both ends).
mobility::StandDeadWood stand_deadwood(const std::vector<DeadWoodRecord>& pieces);

/// The species of a run, as resolved when it started (every parameter).
std::vector<eco::Species> read_run_species(const std::filesystem::path& run);
/// The run's terrain (m), on the grid every other raster of the run shares.
RasterD read_run_terrain(const std::filesystem::path& run);
/// A soil raster of the run (`/soil/NAME`: field_capacity, wilting_point, porosity, ...; m3/m3 or
/// as docs/formats.md lists) on `grid`; InputError naming the run and dataset if it is missing or
/// of another size.
RasterD read_run_soil(const std::filesystem::path& run, const std::string& name,
                      const GridSpec& grid);
/// A raster of snapshot `index` (e.g. soil_moisture, surface_water_depth_m, catchment_id,
/// water_table_depth_m, on the terrain's grid; shade_fraction on the light grid) with the grid
/// given; InputError naming the run, the snapshot and the dataset if it is missing or its size
/// differs from the grid.
RasterD read_snapshot_raster(const std::filesystem::path& run, int index, const std::string& name,
                             const GridSpec& grid);
/// Whether snapshot `index` holds the dataset `name` (e.g. ground_cover, absent in runs made
/// before life forms).
bool snapshot_has_dataset(const std::filesystem::path& run, int index, const std::string& name);
/// The ground a vehicle meets on a snapshot's day (on the terrain's grid): the soil's rating cone
/// index (none in runs made before it), the standing water and the fine-grained soils.
struct SnapshotGround {
    std::optional<RasterD> rci_kpa;
    std::optional<RasterD> water_depth_m;
    std::optional<RasterU8> fine_grained;
    /// Pointers into this object (keep it alive while they are used).
    mobility::GroundMaps maps() const;
};
SnapshotGround read_snapshot_ground(const std::filesystem::path& run, int index,
                                    const GridSpec& grid);

/// What a vehicle meets in snapshot `index` of a run: the run's terrain with the root plates' pits
/// carved, the living stems with the snags, the logs (`deadwood`), and the ground's strength and
/// standing water (`soil`): the world of the mobility analyses of the ensembles and the Python
/// module.
struct DrivingWorld {
    RasterD dem;
    std::vector<mobility::StandStem> stems;
    mobility::StandDeadWood dead;
    std::optional<SnapshotGround> ground;
};
DrivingWorld read_driving_world(const std::filesystem::path& run, int index, bool deadwood,
                                bool soil);
/// The index of the snapshot of year `year`; InputError naming the run and its snapshots' years
/// if none is.
int snapshot_of_year(const std::filesystem::path& run, int year);
/// The snapshot index `index` stands for (negative: from the last), checked against the run.
int resolve_snapshot_index(const std::filesystem::path& run, int index);

} // namespace ecoterra::run
