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
#include <vector>

namespace ecoterra::mobility {

/// One plant of a stand as mobility sees it.
enum class StemKind { tree, shrub, object };

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

enum class LineLayout { random, transects };

struct StandLinesOptions {
    int lines = 200;
    std::uint64_t seed = 1;
    double length_m = 50;
    LineLayout layout = LineLayout::random;
    SmgOptions smg;
};

struct LineRecord {
    Point a, b;
    LineResult result;
};

struct StandMobility {
    std::vector<LineRecord> lines;
    std::vector<Stem> stems; ///< the stems with a diameter at the push height (LineResult indices)
    double smg_mean_m_per_s = 0, smg_median_m_per_s = 0, smg_p10_m_per_s = 0, smg_p90_m_per_s = 0;
    double smg_mean_go_m_per_s = 0; ///< over the lines that are not NOGO
    double nogo_fraction = 0;
    double override_fraction = 0; ///< of the distance driven, spent pushing stems
    double detour_fraction = 0;   ///< of the distance driven, beyond the straight lines
    double basal_area_m2_per_ha = 0;
    std::int64_t trees = 0;   ///< stems that reach breast height
    std::int64_t shrubs = 0;  ///< shrubs (overridden or avoided by their stem at the push height)
    std::int64_t objects = 0; ///< rigid obstacles (always avoided)
    double area_ha = 0;
    double critical_diameter_m = 0;
};

/// Drives `opt.lines` lines over the terrain `dem` (which also sets the stand's area) through
/// `stems`. Lines are drawn from the seed; a random line is drawn again while one of its ends is
/// not clear of the stems the vehicle cannot override (a vehicle has to stand there).
StandMobility analyse_stand(const Vehicle& v, const std::vector<StandStem>& stems,
                            const RasterD& dem, const StandLinesOptions& opt);

/// The report's details: the vehicle and one record per line. The figures above are the mobility
/// analysis's metrics (analyses.hpp: analyses::mobility_json writes both).
nlohmann::json to_json(const StandMobility& m, const Vehicle& v);

} // namespace ecoterra::mobility
