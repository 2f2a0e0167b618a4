#pragma once
// Speed made good over a whole stand (docs/mobility.md s5): many straight lines (random headings
// and positions as Majhor & Bos (paper 000)'s missions, or parallel transects) driven by
// drive_line(), and their distribution, beside the stand's basal area.
#include "ecoterra/mobility/smg.hpp"
#include "ecoterra/mobility/vehicle.hpp"
#include "ecoterra/raster.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace ecoterra::mobility {

/// One plant of a stand as mobility sees it; a snag is a standing dead tree (overridden or avoided
/// as a tree of its DBH, not in the basal area).
enum class StemKind { tree, shrub, object, snag };

struct StandStem {
    double x_m = 0, y_m = 0;
    double dbh_m = 0;    ///< a tree's at breast height (1.3 m); 0 below it
    double height_m = 0; ///< NaN when unknown: the DBH is then taken at the push height
    StemKind kind = StemKind::tree;
    /// A shrub's stem diameter at the ground (tapering to 0 at its height), or an object's
    /// diameter (rigid, avoided), m.
    double base_diameter_m = 0;
};

/// Reads a stem list: CSV with a header naming at least x_m, y_m and dbh_cm (or dbh_m), and
/// optionally height_m, life_form (tree, shrub or object; trees without it) and stem_diameter_cm
/// (a shrub's or object's diameter at the ground; needed with life_form) (the CSV of `ecoterra
/// export vegetation` is one); other columns are ignored. Non-numeric, non-finite or negative
/// values are InputErrors naming the file, the line, the column and the value.
std::vector<StandStem> read_stem_csv(const std::filesystem::path& path);

/// The pit an uprooted tree left (docs/ecosystem.md s13): a disc of the root plate's diameter
/// just windward of the plate standing on edge, half the plate's thickness deep.
struct Pit {
    double x_m = 0, y_m = 0, radius_m = 0, depth_m = 0;
};

/// A stand's dead wood as mobility sees it: snags (StemKind::snag, height_m the tree's height at
/// death for the taper), logs, and the pits of the root plates (cut into the terrain by
/// carve_pits).
struct StandDeadWood {
    std::vector<StandStem> snags;
    std::vector<Log> logs;
    std::vector<Pit> pits;
    /// One piece of the dead-wood table (its `piece` kind, whether it stands, base and far end,
    /// DBH and heights above the ground at both ends) as the vehicle meets it: a stump is a step
    /// as high as it is at a point, a standing piece a snag as tall as it stands, a root plate a
    /// wall as wide as it is high, anything else a log.
    void add(int piece, bool standing, Point base, Point end, double dbh_m, double height_m,
             double end_height_m);
};

/// The depth of the deepest pit over each cell centre of `g`, m (0: none); the pits' coordinates
/// are shifted by -origin first (a scene moved to a local frame).
RasterD pit_depths(const GridSpec& g, const std::vector<Pit>& pits, double origin_x_m = 0,
                   double origin_y_m = 0);
/// Lowers `dem` by the pits' depths (pit_depths on its grid): the ground lines, maps and seasons
/// drive over.
void carve_pits(RasterD& dem, const std::vector<Pit>& pits);

/// Reads a dead-wood list: the CSV of `ecoterra export deadwood` (docs/formats.md), by its header:
/// standing, x_m, y_m, end_x_m, end_y_m, dbh_m, tree_height_m, length_m, height_m and
/// end_height_m; other columns are ignored. Non-numeric, non-finite or negative values (a negative
/// length, height or diameter) are InputErrors naming the file, the line, the column and the value.
StandDeadWood read_deadwood_csv(const std::filesystem::path& path);

enum class LineLayout { random, transects };

/// Which stems the lines meet, to take the slowing apart (paper 002 Fig 9): all of them; only
/// those the vehicle overrides (below its critical diameter; the ones it would avoid are left
/// out); or only those it avoids (at or above the critical diameter, and objects).
enum class StemEffects { both, override_only, avoidance_only };
/// The names of StemEffects, as scene keys and the command line take them.
const std::vector<std::pair<std::string, StemEffects>>& stem_effects_names();

struct StandLinesOptions {
    int lines = 200;
    std::uint64_t seed = 1;
    double length_m = 50;
    LineLayout layout = LineLayout::random;
    StemEffects effects = StemEffects::both;
    SmgOptions smg;
};

struct LineRecord {
    Point a, b;
    LineResult result;
};

struct StandMobility {
    std::vector<LineRecord> lines;
    std::vector<Stem> stems; ///< the stems with a diameter at the push height (LineResult indices)
    std::vector<Log> log_list; ///< the logs
    double smg_mean_m_per_s = 0, smg_median_m_per_s = 0, smg_p10_m_per_s = 0, smg_p90_m_per_s = 0;
    double smg_mean_go_m_per_s = 0; ///< over the lines that are not NOGO
    double nogo_fraction = 0;
    double override_fraction = 0; ///< of the distance driven, spent pushing stems
    double detour_fraction = 0;   ///< of the distance driven, beyond the straight lines
    double basal_area_m2_per_ha = 0;
    std::int64_t trees = 0;   ///< stems that reach breast height
    std::int64_t shrubs = 0;  ///< shrubs (overridden or avoided by their stem at the push height)
    std::int64_t objects = 0; ///< rigid obstacles (always avoided)
    std::int64_t snags = 0;   ///< standing dead trees (overridden or avoided as trees)
    std::int64_t logs = 0;    ///< logs on the ground
    double step_limit_m = 0;  ///< the highest log the vehicle climbs
    double log_crossings_per_100m = 0; ///< logs climbed per 100 m of the lines that go
    double logs_avoided_per_line = 0;  ///< logs too high to climb across a line, mean
    double area_ha = 0;
    double critical_diameter_m = 0;
};

/// Drives `opt.lines` lines over the terrain `dem` (which also sets the stand's area) through
/// `stems` (snags among them) and over or around `logs`. Lines are drawn from the seed; a random
/// line is drawn again while one of its ends is not clear of the stems the vehicle cannot
/// override and the logs it cannot climb (a vehicle has to stand there).
StandMobility analyse_stand(const Vehicle& v, const std::vector<StandStem>& stems,
                            const RasterD& dem, const StandLinesOptions& opt,
                            const std::vector<Log>& logs = {});

/// The report's details: the vehicle and one record per line. The figures above are the mobility
/// analysis's metrics (analyses.hpp: analyses::mobility_json writes both).
nlohmann::json to_json(const StandMobility& m, const Vehicle& v);

} // namespace ecoterra::mobility
