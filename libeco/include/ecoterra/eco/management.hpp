#pragma once
// Forest management (docs/ecosystem.md s12): operations in the scene at given years or when the
// stand's basal area exceeds a threshold; each cuts trees, which leave stumps and slash as dead
// wood (deadwood.hpp) while their merchantable stems leave the stand.
//
//   "vegetation": {"management": {"stump_height_m": 0.2, "operations": [
//       {"year": 40, "type": "thin_from_below", "target_basal_area_m2_per_ha": 18},
//       {"when_basal_area_above_m2_per_ha": 32, "type": "thin_from_above",
//        "target_basal_area_m2_per_ha": 24},
//       {"year": 60, "type": "selection", "min_dbh_m": 0.45},
//       {"year": 90, "type": "clear_cut"}]}}
#include "ecoterra/eco/population.hpp"
#include "ecoterra/eco/species.hpp"

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

namespace ecoterra::eco {

enum class CutKind { thin_from_below, thin_from_above, selection, clear_cut };
const char* cut_kind_name(CutKind k);

struct ManagementOp {
    CutKind kind = CutKind::thin_from_below;
    int year = 0; ///< the year-end it acts at (1-based); 0: whenever the condition holds
    std::optional<double> when_basal_area_above_m2_per_ha; ///< the condition (with year 0)
    double target_basal_area_m2_per_ha = 0;                ///< thinnings: the basal area left
    double min_dbh_m = 0;                                  ///< selection: cut at and above it
};

struct ManagementOptions {
    /// Stump height after a cut, m: 0.1-0.3 m is typical of machine harvest (reference
    /// deadwood.md s5, not verified).
    double stump_height_m = 0.2;
    std::vector<ManagementOp> operations;
};

/// Reads vegetation.management; `years` is the run's length (operations past it are refused).
/// Unknown keys, a missing or impossible year, basal area or diameter, or an unknown type are
/// InputErrors naming the key (vegetation.management.operations[K].KEY) and the value.
ManagementOptions read_management(const nlohmann::json& j, int years);
nlohmann::json to_json(const ManagementOptions& m);

/// The year's harvest: marks with `mark` in `dead` the live trees (life form tree, reaching breast
/// height, not yet dead)
/// that the operations acting at the end of `year` cut. Basal area is over `area_m2` of the trees
/// that reach breast height. Thinnings remove the smallest (from below) or the largest (from
/// above) stems first, ties by plant id, until the basal area is at or below the target.
/// Returns the number of plants cut.
std::int64_t mark_harvest(const ManagementOptions& m, const Population& pop,
                          const std::vector<Species>& species, double area_m2, int year,
                          std::vector<char>& dead, char mark);

} // namespace ecoterra::eco
