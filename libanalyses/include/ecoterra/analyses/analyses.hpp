#pragma once
// The analyses of a run or a terrain, one layer for the program and the ensembles: each analysis
// has catalogued options (defaults, units, ranges, as scene keys have) and catalogued metrics, so
// that a metric has one name and one unit everywhere: the top-level keys of `ecoterra stand
// --json`, `ecoterra mobility --json`, `ecoterra terrain traverse --json` and `ecoterra terrain
// analyze --json`, the ensembles' columns ("stand.basal_area_m2_per_ha"), their units in the
// ensemble's tables, and docs/parameters.md (`ecoterra describe outputs`).
//
//   run        run_metrics()       of run::RunSummary (the run an ensemble member grew)
//   stand      stand_metrics()     of eco::StandMetrics (trees of a snapshot)
//   mobility   mobility_metrics()  of mobility::StandMobility, options mobility_catalog()
//   traverse   traverse_metrics()  of mobility::TraverseReport, options traverse_catalog()
//   terrain    terrain_metrics()   of terrain::TerrainAnalysis, options terrain_catalog()
#include "ecoterra/catalog.hpp"
#include "ecoterra/eco/stand_metrics.hpp"
#include "ecoterra/mobility/map.hpp"
#include "ecoterra/mobility/stand.hpp"
#include "ecoterra/mobility/traverse.hpp"
#include "ecoterra/run/run.hpp"
#include "ecoterra/terrain/analysis.hpp"
#include "ecoterra/terrain/missions.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <utility>
#include <vector>

namespace ecoterra::analyses {

const std::vector<Column<run::RunSummary>>& run_metrics();
const std::vector<Column<eco::StandMetrics>>& stand_metrics();
const std::vector<Column<mobility::StandMobility>>& mobility_metrics();
const std::vector<Column<mobility::TraverseReport>>& traverse_metrics();
const std::vector<Column<mobility::MobilityMap>>& mobility_map_metrics();
const std::vector<Column<terrain::TerrainAnalysis>>& terrain_metrics();

/// Metric values in catalogue order, named "ANALYSIS.METRIC".
using Values = std::vector<std::pair<std::string, double>>;
template <class R>
void add_values(Values& out, const std::string& analysis, const std::vector<Column<R>>& metrics,
                const R& r) {
    for (const auto& m : metrics) out.emplace_back(analysis + "." + m.name, m.get(r));
}
/// Each metric as a top-level key of an analysis's JSON: counts as integers, a NaN (a fit that
/// could not be made) as null.
template <class R>
void put_metrics(nlohmann::json& doc, const std::vector<Column<R>>& metrics, const R& r) {
    for (const auto& m : metrics) {
        const double v = m.get(r);
        if (!(v == v))
            doc[m.name] = nullptr;
        else if (m.type == ColumnType::int64)
            doc[m.name] = static_cast<std::int64_t>(v);
        else
            doc[m.name] = v;
    }
}
/// The JSON documents of the analyses: the metrics as top-level keys and the details of each
/// (the stand's histogram and fit, the mobility lines, the traverse records, the terrain's PSD).
nlohmann::json stand_json(const eco::StandMetrics& m);
nlohmann::json mobility_json(const mobility::StandMobility& m, const mobility::Vehicle& v);
nlohmann::json traverse_json(const mobility::TraverseReport& r, const mobility::Vehicle& v);
nlohmann::json terrain_json(const terrain::TerrainAnalysis& a, const terrain::AnalysisOptions& o);

/// The unit of "ANALYSIS.METRIC" from its catalogue; "" when it is not a metric.
std::string metric_unit(const std::string& qualified);
/// The unit of a column of an ensemble's tables: a metric's (also with an aggregate's ".mean",
/// ".sd", ".p10", ".p50", ".p90"), an axis's scene key's, or one of the tables' own columns
/// (member, seed, seconds, ...); "" when none is known.
std::string column_unit(const std::string& column);
/// Every metric for `ecoterra describe outputs`, named "ANALYSIS.METRIC".
std::vector<ColumnInfo> describe_metrics();

/// Options of the mobility analysis (`ecoterra mobility`, an ensemble's analyses.mobility).
struct MobilityAnalysis {
    std::string vehicle; ///< vehicle file (required)
    int lines = 200;
    double length_m = 50;
    std::uint64_t seed = 1;
    mobility::LineLayout layout = mobility::LineLayout::random;
    bool deadwood = true; ///< drive through the snapshot's snags and over or around its logs
    bool soil = true;     ///< the snapshot's soil strength and standing water (ground.hpp)
    mobility::StemEffects effects = mobility::StemEffects::both; ///< which stems the lines meet
    mobility::StandLinesOptions lines_options() const;
};
const ParamCatalog<MobilityAnalysis>& mobility_catalog();

/// Options of the mobility-map analysis (`ecoterra mobility map`, an ensemble's
/// analyses.mobility_map: each member's map, and per combination the stochastic map of its
/// members).
struct MobilityMapAnalysis {
    std::string vehicle; ///< vehicle file (required)
    double cell_m = 0;   ///< 0: the terrain's cell
    int headings = 8;
    bool deadwood = true;
    bool soil = true;
    mobility::MapOptions map_options() const;
};
const ParamCatalog<MobilityMapAnalysis>& mobility_map_catalog();

/// Options of the traversal analysis (`ecoterra terrain traverse`, analyses.traverse).
struct TraverseAnalysis {
    std::string vehicle; ///< vehicle file (required)
    int missions = terrain::MissionOptions{}.count;
    double length_m = terrain::MissionOptions{}.length_m;
    std::uint64_t seed = 1;
    double speed_m_per_s = 0; ///< 0: the vehicle's top speed
    bool allow_fewer = false; ///< drive the missions found when the terrain has room for fewer
    terrain::MissionOptions mission_options() const;
    mobility::TraverseOptions traverse_options() const;
};
const ParamCatalog<TraverseAnalysis>& traverse_catalog();

/// Options of the terrain analysis (`ecoterra terrain analyze`, analyses.terrain).
struct TerrainAnalysisOptions {
    double border_m = terrain::AnalysisOptions{}.border_m;
    double closing_radius_m = terrain::AnalysisOptions{}.closing_radius_m;
    terrain::AnalysisOptions options() const;
};
const ParamCatalog<TerrainAnalysisOptions>& terrain_catalog();

/// Options of an ensemble's scene exports (analyses.export; `ecoterra export scene` writes one
/// format per call).
struct ExportAnalysis {
    std::vector<std::string> formats; ///< scene formats (export/formats.hpp), each once
    bool layers = false;              ///< the GeoTIFF layers too
};
const ParamCatalog<ExportAnalysis>& export_catalog();

/// The keys each analysis of an ensemble's manifest takes ("stand": none), from the catalogues
/// (the seed aside: each member derives its own).
const std::vector<std::pair<std::string, std::vector<std::string>>>& analysis_keys();

} // namespace ecoterra::analyses
