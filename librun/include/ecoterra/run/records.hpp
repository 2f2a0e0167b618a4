#pragma once
// The plant records of a run as catalogues: each column's name, unit, type and description written
// once, and the snapshot writer, the readers and the stem CSV follow from them (docs/parameters.md
// lists them, `ecoterra describe outputs` prints them).
//
//   /snapshots/NNNN/plants/*   plant_columns(), one row per live plant (PlantRecord)
//   stem CSV                   stem_csv_columns() (`ecoterra export vegetation`)
//   /snapshots/NNNN/deadwood/* deadwood_columns(), one row per snag or log (DeadWoodRecord)
//   dead-wood CSV              the same columns, species by name (`ecoterra export deadwood`)
#include "ecoterra/catalog.hpp"
#include "ecoterra/eco/deadwood.hpp"
#include "ecoterra/eco/plant.hpp"
#include "ecoterra/eco/species.hpp"

#include <cstdint>
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace ecoterra::run {

using eco::Plant;
using eco::Species;

/// What a snapshot stores of one plant.
struct PlantRecord {
    std::int64_t id = 0;
    std::int32_t species = 0;
    std::int32_t life_form = 0; ///< LifeForm's value: 0 tree, 1 shrub, 3 object
    double x_m = 0, y_m = 0, z_m = 0, height_m = 0;
    double dbh_m = 0;           ///< trees only (0 below breast height and for other life forms)
    double stem_diameter_m = 0; ///< a tree's at breast height, a shrub's or object's at the ground
    double crown_radius_m = 0, age_yr = 0, carbohydrate_kg = 0;
};
PlantRecord plant_record(const Plant& p, const Species& s);
const std::vector<Column<PlantRecord>>& plant_columns();

/// A column of the stem CSV: its text for one plant, given the run's species names.
struct StemCsvColumn {
    std::string name, unit, description;
    ColumnType type;
    std::string (*text)(const PlantRecord&, const std::vector<std::string>& species);
};
const std::vector<StemCsvColumn>& stem_csv_columns();
/// The stem CSV of a snapshot's plants (header line, then one row per plant).
std::string stem_csv(const std::vector<PlantRecord>& plants,
                     const std::vector<std::string>& species);

/// What a snapshot stores of one snag or log (eco::DeadStem with its derived geometry).
struct DeadWoodRecord {
    std::int64_t id = 0; ///< the tree's plant id
    std::int32_t species = 0, standing = 0, piece = 0, cause = 0, decay_class = 0, year_died = 0,
                 year_down = -1;
    double x_m = 0, y_m = 0, z_m = 0, end_x_m = 0, end_y_m = 0, dbh_m = 0, tree_height_m = 0,
           length_m = 0, azimuth_rad = 0, height_m = 0, end_height_m = 0, mass_kg = 0,
           volume_m3 = 0;
};
DeadWoodRecord deadwood_record(const eco::DeadStem& d, const Species& s);
const std::vector<Column<DeadWoodRecord>>& deadwood_columns();
/// The dead-wood CSV: deadwood_columns() with the species by name (header line, then a row each).
std::string deadwood_csv(const std::vector<DeadWoodRecord>& pieces,
                         const std::vector<std::string>& species);

/// The same tables as JSON: an array of records, one object per row keyed by the CSV's column
/// names, numbers as numbers (pandas: `pd.read_json(path)`).
nlohmann::ordered_json stem_records_json(const std::vector<PlantRecord>& plants,
                                         const std::vector<std::string>& species);
nlohmann::ordered_json deadwood_records_json(const std::vector<DeadWoodRecord>& pieces,
                                             const std::vector<std::string>& species);

} // namespace ecoterra::run
