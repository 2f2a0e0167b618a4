#pragma once
// Speed made good along a straight A-to-B line through a stand (docs/mobility.md s4), NRMM-style:
// stems thinner than the critical diameter are overridden, the forces of those in each
// vehicle-width cell ahead adding up; thicker stems, and the stems of a cell whose cluster force
// the thrust cannot overcome, are avoided on the shortest collision-free path (stems inflated by
// half the vehicle width); the vehicle drives that path at the steady-state speed of each cell.
// SMG = straight-line length / time; a line with no path, or with a cell the vehicle cannot
// climb, is NOGO (SMG 0).
//
// Logs lie across the path as steps (docs/mobility.md s4.3): where a log's top is no higher than
// the vehicle's step limit, min(ground clearance, wheel radius), the vehicle climbs it at most at
// sqrt(g (r - h)) (the wheel stays on the log's edge); the part of a log above the limit is an
// obstacle to drive around.
#include "ecoterra/mobility/ground.hpp"
#include "ecoterra/mobility/vehicle.hpp"
#include "ecoterra/raster.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace ecoterra::mobility {

struct Stem {
    double x_m = 0, y_m = 0;
    double diameter_m = 0; ///< at the vehicle's push height
    bool rigid = false;    ///< an object (a roadblock): never pushed over, always avoided
};

struct Point {
    double x_m = 0, y_m = 0;
};

/// A log lying on the ground: a straight segment from end 0 to end 1, with the height of its top
/// above the ground at each end (linear between them).
struct Log {
    Point a, b;
    double height_a_m = 0, height_b_m = 0;
    double diameter_m = 0; ///< the largest, for its footprint
};

/// Distance from p to the segment a-b, m.
double point_segment_distance(Point p, Point a, Point b);
/// The part [u0, u1] of a log (0 at end a, 1 at end b) whose top is above `limit`; u0 > u1 when
/// none is.
std::pair<double, double> log_high_part(const Log& l, double limit);
/// Whether the log's axis meets the footprint from c0 along (ux, uy), 0 <= t <= len, |s| <=
/// half across; [lo, hi] is then the part of the log (0 end a, 1 end b) inside it.
bool log_in_footprint(const Log& l, Point c0, double len, double ux, double uy, double half,
                      double& lo, double& hi);

/// The highest log a vehicle drives over: min(ground clearance, wheel radius) (a log thicker than
/// the clearance hangs the vehicle up; a wheel climbs a step below its radius), m.
double step_limit_m(const Vehicle& v);
/// The fastest a vehicle crosses a step of height h <= its limit: the speed at which its wheel,
/// pivoting on the step's edge, still presses on it, v = sqrt(g (r - h)), m/s.
double step_crossing_speed_m_per_s(const Vehicle& v, double h_m);

struct LineResult {
    double straight_m = 0; ///< |B - A|
    double path_m = 0;     ///< length of the path driven
    double time_s = 0;
    double smg_m_per_s = 0;
    bool nogo = false;
    std::string nogo_reason;
    double override_m = 0;                    ///< path length with a stem force to push
    std::int64_t overridden = 0, avoided = 0; ///< stems pushed over, stems avoided
    std::vector<Point> path;                  ///< the path driven, A to B (empty when NOGO)
    std::vector<std::int64_t> pushed_stems;   ///< indices (in the StemIndex) of stems pushed over
    std::int64_t logs_crossed = 0;            ///< logs driven over (once each)
    std::int64_t logs_avoided = 0; ///< logs too high to drive over that lie across the line
};

struct SmgOptions {
    /// Resolution of the planning grid, as a fraction of the vehicle width.
    double grid_fraction_of_width = 0.125;
    /// The planning area reaches this far beyond the line's bounding box, m (a detour wider than
    /// it counts as no path).
    double margin_m = 25;
    /// When set, the planning area is also kept inside [x0, x1] x [y0, y1] (the terrain), m.
    std::optional<std::array<double, 4>> bounds_m;
    /// The ground (ground.hpp): soil strength, standing water and fine-grained soils on the
    /// terrain's grid. A cell softer than the vehicle's VCI1, without net traction (Brixius) or
    /// under water deeper than the fording depth is NO-GO; soft soil adds its motion resistance
    /// and caps the traction. Empty: firm, dry ground everywhere.
    GroundMaps ground;
};

/// Sets `opt`'s soil strength to `rci_kpa` (a snapshot's rating_cone_index_kpa).
void use_soil(SmgOptions& opt, const RasterD& rci_kpa);

/// Stems in buckets of a fixed size, for queries by rectangle and disk.
class StemIndex {
public:
    StemIndex(std::vector<Stem> stems, double bucket_m);
    const std::vector<Stem>& stems() const { return m_stems; }
    /// The largest diameter of the stems, m (0 without stems).
    double max_diameter_m() const { return m_max_d; }
    /// Calls f(k) for every stem k within the axis-aligned box [x0, x1] x [y0, y1].
    template <class F>
    void for_each_in_box(double x0, double y0, double x1, double y1, F&& f) const {
        const int i0 = bucket(x0, m_x0), i1 = bucket(x1, m_x0);
        const int j0 = bucket(y0, m_y0), j1 = bucket(y1, m_y0);
        for (int j = std::max(j0, 0); j <= std::min(j1, m_ny - 1); ++j)
            for (int i = std::max(i0, 0); i <= std::min(i1, m_nx - 1); ++i)
                for (const std::int64_t k : m_buckets[static_cast<std::size_t>(j) * m_nx + i]) {
                    const Stem& s = m_stems[static_cast<std::size_t>(k)];
                    if (s.x_m >= x0 && s.x_m <= x1 && s.y_m >= y0 && s.y_m <= y1) f(k);
                }
    }

private:
    int bucket(double v, double origin) const {
        return static_cast<int>(std::floor((v - origin) / m_size));
    }
    std::vector<Stem> m_stems;
    double m_size = 1, m_x0 = 0, m_y0 = 0, m_max_d = 0;
    int m_nx = 0, m_ny = 0;
    std::vector<std::vector<std::int64_t>> m_buckets;
};

/// Logs in buckets of a fixed size (a log is in every bucket its bounding box meets).
class LogIndex {
public:
    LogIndex() = default;
    LogIndex(std::vector<Log> logs, double bucket_m);
    const std::vector<Log>& logs() const { return m_logs; }
    /// The largest diameter of the logs, m.
    double max_diameter_m() const { return m_max_d; }
    /// Calls f(k) once for every log k whose bounding box meets [x0, x1] x [y0, y1].
    template <class F>
    void for_each_in_box(double x0, double y0, double x1, double y1, F&& f) const {
        if (m_logs.empty()) return;
        const int i0 = std::max(bucket(x0, m_x0), 0), i1 = std::min(bucket(x1, m_x0), m_nx - 1);
        const int j0 = std::max(bucket(y0, m_y0), 0), j1 = std::min(bucket(y1, m_y0), m_ny - 1);
        for (int j = j0; j <= j1; ++j)
            for (int i = i0; i <= i1; ++i)
                for (const std::int64_t k : m_buckets[static_cast<std::size_t>(j) * m_nx + i]) {
                    const auto& bb = m_box[static_cast<std::size_t>(k)];
                    if (bb[2] < x0 || bb[0] > x1 || bb[3] < y0 || bb[1] > y1) continue;
                    // Report a log from the first bucket it shares with the box only.
                    if (i != std::max(i0, bucket(bb[0], m_x0)) ||
                        j != std::max(j0, bucket(bb[1], m_y0)))
                        continue;
                    f(k);
                }
    }

private:
    int bucket(double v, double origin) const {
        return static_cast<int>(std::floor((v - origin) / m_size));
    }
    std::vector<Log> m_logs;
    std::vector<std::array<double, 4>> m_box; ///< x0, y0, x1, y1 of each log
    double m_size = 1, m_x0 = 0, m_y0 = 0, m_max_d = 0;
    int m_nx = 0, m_ny = 0;
    std::vector<std::vector<std::int64_t>> m_buckets;
};

/// Time to drive cells of lengths `len_m` (m) whose boundaries (one more than cells) may be
/// passed at most at `node_cap_m_per_s`, speeding up at `acc` and braking at `dec` (m/s2) between
/// them: the speed profile of the forward and backward passes, with v^2 linear in distance in
/// each cell, t = 2 len / (u_in + u_out).
double profile_time_s(const std::vector<double>& len_m, std::vector<double> node_cap_m_per_s,
                      double acc, double dec);

/// Drives from `a` to `b` through the stems of `index` and over or around the logs of `logs`, over
/// `dem` (nullptr: flat ground).
LineResult drive_line(const Vehicle& v, const StemIndex& index, const LogIndex& logs,
                      const RasterD* dem, Point a, Point b, const SmgOptions& opt = {});
/// The same without logs.
LineResult drive_line(const Vehicle& v, const StemIndex& index, const RasterD* dem, Point a,
                      Point b, const SmgOptions& opt = {});

} // namespace ecoterra::mobility
