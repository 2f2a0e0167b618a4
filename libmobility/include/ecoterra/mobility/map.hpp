#pragma once
// Mobility maps (docs/mobility.md s10): per map cell and heading, the steady speed a vehicle can
// hold across the cell, from the slope and side slope, the ground (soil strength and standing
// water, ground.hpp), the vegetation (the override and avoidance model of drive_line, over the
// cell's neighbourhood) and dead wood; NO-GO where it cannot cross; and the factor that limits it.
//
// A cell of side c is crossed along heading u by a vehicle of width w whose centre line may run
// anywhere within the cell (lateral offsets -c/2..c/2, in steps of at most w/8, as the planning
// grid of drive_line). A lane is closed by a stem to avoid (at or above the critical diameter, or
// rigid) within (d + w)/2 of its centre line, by a log's part above the step limit within w/2 of
// it, or by a cluster of stems too heavy to push. On an open lane the vehicle pushes over the
// stems within w/2 of its centre line in segments of one vehicle width (a cell shorter than that
// takes the width-long segment centred on it), climbs the logs across it at most at sqrt(g (r -
// h)), and holds the steady speed against rolling, grade and soil resistance plus the segment's
// override force; the cell's speed is the fastest lane's. The grade is the terrain's rise over
// max(c, w) along u through the cell's centre, the side slope its rise across the track. The
// limiting factor of a GO crossing is the one that costs the most speed (slope against flat
// ground, soil against firm, vegetation against open, dead wood against none), if it costs more
// than 10 % of the top speed; otherwise none.
#include "ecoterra/mobility/ground.hpp"
#include "ecoterra/mobility/smg.hpp"
#include "ecoterra/mobility/stand.hpp"
#include "ecoterra/mobility/vehicle.hpp"
#include "ecoterra/raster.hpp"

#include <nlohmann/json.hpp>

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace ecoterra::mobility {

struct MapOptions {
    /// The map's cell, m: 0 takes the terrain's; otherwise a whole multiple of it (the ground of
    /// a coarse cell is the median of the terrain cells it covers).
    double cell_m = 0;
    /// Headings, evenly spaced from north (0 deg) clockwise.
    int headings = 8;
};

inline constexpr int kLimitKinds = 6; ///< Limit::none ... Limit::obstacle

struct MobilityMap {
    GridSpec grid;                      ///< the map's cells
    std::string crs_wkt;                ///< the terrain's CRS (every raster carries it too)
    std::vector<double> headings_deg;   ///< compass headings, clockwise from north
    std::vector<RasterD> speed_m_per_s; ///< per heading: the steady speed across, 0 NO-GO
    std::vector<RasterU8> limit;        ///< per heading: the limiting factor (Limit)
    RasterD speed_mean_m_per_s;         ///< mean over the headings (NO-GO as 0)
    RasterD go_fraction;                ///< share of the headings that are GO
    RasterU8 limiting;                  ///< the factor that limits most headings
    RasterD rci_kpa;                    ///< the ground the map used (NaN: firm)
    RasterD water_depth_m;              ///< standing water the map used
    // Summary over the cells.
    double mean_speed_m_per_s = 0;                 ///< mean of speed_mean over the cells
    double go_share = 0;                           ///< share of cell-headings that are GO
    double any_go_share = 0;                       ///< share of cells GO in at least one heading
    std::array<double, kLimitKinds> limit_share{}; ///< share of cell-headings by factor
    double top_speed_m_per_s = 0; ///< the vehicle's steady speed on flat, firm, open ground
};

/// A map's part that does not depend on the ground: per cell and heading the grade, the speed on
/// it, and the lanes (closed, free, or what they push and climb), computed once from the stems
/// and logs (which it does not keep). map() then maps a day's ground over it: a season maps every
/// day over one plan.
class MapPlan {
public:
    MapPlan(const Vehicle& v, const RasterD& dem, const StemIndex& stems, const LogIndex& logs,
            const MapOptions& opt);
    /// From a stand's stems (snags included) and logs, as analyse_stand takes them.
    MapPlan(const Vehicle& v, const RasterD& dem, const std::vector<StandStem>& stems,
            const std::vector<Log>& logs, const MapOptions& opt);
    ~MapPlan();
    MapPlan(MapPlan&&) noexcept;
    MapPlan& operator=(MapPlan&&) = delete;
    const GridSpec& grid() const;
    /// The map on this ground (on the terrain's grid; empty: firm, dry ground). Without
    /// `per_heading` the per-heading rasters are left empty (a season needs only the means).
    MobilityMap map(const GroundMaps& ground, bool per_heading = true) const;

private:
    struct Impl;
    std::unique_ptr<Impl> m;
};

/// The mobility map of `v` over `dem` with its stems (snags included), logs (and root plates) and
/// ground (on the terrain's grid). InputError for a map cell finer than the terrain's or not a
/// whole multiple of it, or a heading count outside 1..360.
MobilityMap mobility_map(const Vehicle& v, const RasterD& dem, const StemIndex& stems,
                         const LogIndex& logs, const GroundMaps& ground, const MapOptions& opt);

/// The same from a stand's stems (StandStem: trees, shrubs, objects and snags, as
/// analyse_stand takes them) and logs.
MobilityMap mobility_map(const Vehicle& v, const RasterD& dem, const std::vector<StandStem>& stems,
                         const std::vector<Log>& logs, const GroundMaps& ground,
                         const MapOptions& opt);

/// A season of daily maps of one place (the same grid every day) and what they add up to per
/// cell: the share of days GO (in at least one heading) and the median and 10th percentile of the
/// day's mean speed over the headings (NO-GO days as 0). Keeps one float per cell and day.
class MapSeason {
public:
    void add(const MobilityMap& day);
    int days() const { return m_days; }
    RasterD go_share_of_days() const;
    RasterD speed_quantile_m_per_s(double q) const;

private:
    GridSpec m_grid;
    std::string m_crs;
    int m_days = 0;
    std::vector<float> m_speed; ///< [cell][day]: appended day by day, cell-major on output
    std::vector<std::uint16_t> m_go;
};

/// The summary as JSON (units in the keys).
nlohmann::json to_json(const MobilityMap& m);

} // namespace ecoterra::mobility
