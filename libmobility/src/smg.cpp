#include "ecoterra/mobility/smg.hpp"

#include "ecoterra/error.hpp"
#include "ecoterra/mobility/override.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <queue>

namespace ecoterra::mobility {

double point_segment_distance(Point p, Point a, Point b) {
    const double dx = b.x_m - a.x_m, dy = b.y_m - a.y_m, l2 = dx * dx + dy * dy;
    const double t =
        l2 > 0 ? std::clamp(((p.x_m - a.x_m) * dx + (p.y_m - a.y_m) * dy) / l2, 0.0, 1.0) : 0.0;
    return std::hypot(a.x_m + t * dx - p.x_m, a.y_m + t * dy - p.y_m);
}

std::pair<double, double> log_high_part(const Log& l, double limit) {
    const bool ha = l.height_a_m > limit, hb = l.height_b_m > limit;
    if (ha && hb) return {0.0, 1.0};
    if (!ha && !hb) return {1.0, 0.0};
    const double u = (limit - l.height_a_m) / (l.height_b_m - l.height_a_m);
    return ha ? std::pair{0.0, u} : std::pair{u, 1.0};
}

bool log_in_footprint(const Log& l, Point c0, double len, double ux, double uy, double half,
                      double& lo, double& hi) {
    // The log's axis in the footprint's frame (t along, s across), clipped to 0 <= t <= len,
    // |s| <= half (Liang-Barsky).
    auto t_of = [&](Point p) { return (p.x_m - c0.x_m) * ux + (p.y_m - c0.y_m) * uy; };
    auto s_of = [&](Point p) { return -(p.x_m - c0.x_m) * uy + (p.y_m - c0.y_m) * ux; };
    const double t0 = t_of(l.a), dt = t_of(l.b) - t0;
    const double s0 = s_of(l.a), ds = s_of(l.b) - s0;
    lo = 0;
    hi = 1;
    auto clip = [&](double p, double q) { // keeps p u <= q
        if (p == 0) return q >= 0;
        const double r = q / p;
        if (p < 0)
            lo = std::max(lo, r);
        else
            hi = std::min(hi, r);
        return lo <= hi;
    };
    return clip(-dt, t0) && clip(dt, len - t0) && clip(-ds, s0 + half) && clip(ds, half - s0);
}

namespace {

/// Distance between the segments p0-p1 and q0-q1 (0 when they cross), m.
double segment_distance(Point p0, Point p1, Point q0, Point q1) {
    auto cross = [](Point o, Point a, Point b) {
        return (a.x_m - o.x_m) * (b.y_m - o.y_m) - (a.y_m - o.y_m) * (b.x_m - o.x_m);
    };
    const double d1 = cross(q0, q1, p0), d2 = cross(q0, q1, p1);
    const double d3 = cross(p0, p1, q0), d4 = cross(p0, p1, q1);
    if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0)))
        return 0.0;
    return std::min({point_segment_distance(p0, q0, q1), point_segment_distance(p1, q0, q1),
                     point_segment_distance(q0, p0, p1), point_segment_distance(q1, p0, p1)});
}

/// The point at u (0 end a, 1 end b) along a log.
Point point_along(const Log& l, double u) {
    return {l.a.x_m + u * (l.b.x_m - l.a.x_m), l.a.y_m + u * (l.b.y_m - l.a.y_m)};
}

/// The planning grid refuses areas larger than this many cells.
constexpr double kMaxPlanningCells = 4e7;
/// Replanning rounds (a heavy cluster found on the path becomes obstacles each round).
constexpr int kMaxReplans = 16;
/// The smallest planning cell, m.
constexpr double kMinPlanningCell_m = 0.02;
/// Heading changes below this are straight on, rad.
constexpr double kMinTurn_rad = 1e-6;

struct Grid {
    double x0 = 0, y0 = 0, r = 1;
    int nx = 0, ny = 0;
    std::vector<char> blocked;
    int col(double x) const { return static_cast<int>(std::floor((x - x0) / r)); }
    int row(double y) const { return static_cast<int>(std::floor((y - y0) / r)); }
    bool inside(int i, int j) const { return i >= 0 && j >= 0 && i < nx && j < ny; }
    bool blocked_at(double x, double y) const {
        const int i = col(x), j = row(y);
        return !inside(i, j) || blocked[static_cast<std::size_t>(j) * nx + i] != 0;
    }
    Point centre(std::int64_t c) const {
        return {x0 + (static_cast<double>(c % nx) + 0.5) * r,
                y0 + (static_cast<double>(c / nx) + 0.5) * r};
    }
};

double distance(Point p, Point q) {
    return std::hypot(q.x_m - p.x_m, q.y_m - p.y_m);
}

/// True when the segment p-q crosses no blocked cell (sampled at a quarter cell).
bool line_of_sight(const Grid& g, Point p, Point q) {
    const double len = distance(p, q);
    const int n = std::max(1, static_cast<int>(std::ceil(len / (0.25 * g.r))));
    for (int k = 0; k <= n; ++k) {
        const double t = static_cast<double>(k) / n;
        if (g.blocked_at(p.x_m + t * (q.x_m - p.x_m), p.y_m + t * (q.y_m - p.y_m))) return false;
    }
    return true;
}

/// Shortest 8-connected path of cells from a to b (A*, octile heuristic), pulled taut by line of
/// sight; empty when there is none.
std::vector<Point> plan(const Grid& g, Point a, Point b) {
    if (g.blocked_at(a.x_m, a.y_m) || g.blocked_at(b.x_m, b.y_m)) return {};
    const std::int64_t n = static_cast<std::int64_t>(g.nx) * g.ny;
    const std::int64_t start = static_cast<std::int64_t>(g.row(a.y_m)) * g.nx + g.col(a.x_m);
    const std::int64_t goal = static_cast<std::int64_t>(g.row(b.y_m)) * g.nx + g.col(b.x_m);
    std::vector<float> cost(static_cast<std::size_t>(n), std::numeric_limits<float>::infinity());
    std::vector<std::int64_t> parent(static_cast<std::size_t>(n), -1);
    std::vector<char> done(static_cast<std::size_t>(n), 0);
    const int gi = static_cast<int>(goal % g.nx), gj = static_cast<int>(goal / g.nx);
    auto h = [&](std::int64_t c) {
        const double dx = std::abs(static_cast<double>(c % g.nx - gi));
        const double dy = std::abs(static_cast<double>(c / g.nx - gj));
        return (std::max(dx, dy) + (std::sqrt(2.0) - 1.0) * std::min(dx, dy)) * g.r;
    };
    using Entry = std::pair<double, std::int64_t>;
    std::priority_queue<Entry, std::vector<Entry>, std::greater<>> open;
    cost[static_cast<std::size_t>(start)] = 0;
    open.push({h(start), start});
    while (!open.empty()) {
        const std::int64_t c = open.top().second;
        open.pop();
        if (done[static_cast<std::size_t>(c)]) continue;
        done[static_cast<std::size_t>(c)] = 1;
        if (c == goal) break;
        const int ci = static_cast<int>(c % g.nx), cj = static_cast<int>(c / g.nx);
        for (int dj = -1; dj <= 1; ++dj)
            for (int di = -1; di <= 1; ++di) {
                if (!di && !dj) continue;
                const int i = ci + di, j = cj + dj;
                if (!g.inside(i, j)) continue;
                const std::int64_t m = static_cast<std::int64_t>(j) * g.nx + i;
                if (g.blocked[static_cast<std::size_t>(m)] || done[static_cast<std::size_t>(m)])
                    continue;
                // No corner cutting between two blocked cells.
                if (di && dj &&
                    (g.blocked[static_cast<std::size_t>(cj) * g.nx + i] ||
                     g.blocked[static_cast<std::size_t>(j) * g.nx + ci]))
                    continue;
                const double step = (di && dj ? std::sqrt(2.0) : 1.0) * g.r;
                const double nc = cost[static_cast<std::size_t>(c)] + step;
                if (nc < cost[static_cast<std::size_t>(m)]) {
                    cost[static_cast<std::size_t>(m)] = static_cast<float>(nc);
                    parent[static_cast<std::size_t>(m)] = c;
                    open.push({nc + h(m), m});
                }
            }
    }
    if (!done[static_cast<std::size_t>(goal)]) return {};
    std::vector<Point> cells;
    for (std::int64_t c = goal; c != -1; c = parent[static_cast<std::size_t>(c)])
        cells.push_back(g.centre(c));
    std::reverse(cells.begin(), cells.end());
    cells.front() = a;
    cells.back() = b;
    // Pull taut: from each kept point, jump to the furthest point still in sight.
    std::vector<Point> path{a};
    std::size_t at = 0;
    while (at + 1 < cells.size()) {
        std::size_t next = at + 1;
        for (std::size_t k = cells.size() - 1; k > at + 1; --k)
            if (line_of_sight(g, cells[at], cells[k])) {
                next = k;
                break;
            }
        path.push_back(cells[next]);
        at = next;
    }
    return path;
}

} // namespace

double profile_time_s(const std::vector<double>& len, std::vector<double> u, double acc,
                      double dec) {
    if (u.size() != len.size() + 1)
        throw Error("profile_time_s: " + std::to_string(len.size()) + " cells need " +
                    std::to_string(len.size() + 1) + " node speeds");
    for (std::size_t k = 0; k < len.size(); ++k)
        u[k + 1] = std::min(u[k + 1], std::sqrt(u[k] * u[k] + 2 * acc * len[k]));
    for (std::size_t k = len.size(); k-- > 0;)
        u[k] = std::min(u[k], std::sqrt(u[k + 1] * u[k + 1] + 2 * dec * len[k]));
    double t = 0;
    for (std::size_t k = 0; k < len.size(); ++k) {
        const double mean = 0.5 * (u[k] + u[k + 1]);
        if (!(mean > 0)) return std::numeric_limits<double>::infinity();
        t += len[k] / mean;
    }
    return t;
}

double step_limit_m(const Vehicle& v) {
    return std::min(v.ground_clearance_m, v.wheel_radius_m);
}

double step_crossing_speed_m_per_s(const Vehicle& v, double h_m) {
    return std::sqrt(kGravity_m_per_s2 * std::max(v.wheel_radius_m - h_m, 0.0));
}

LogIndex::LogIndex(std::vector<Log> logs, double bucket_m)
    : m_logs(std::move(logs)), m_size(bucket_m) {
    if (!(bucket_m > 0)) throw InputError("log index: bucket size must be > 0 m");
    if (m_logs.empty()) return;
    double x1 = -std::numeric_limits<double>::infinity(), y1 = x1;
    m_x0 = m_y0 = std::numeric_limits<double>::infinity();
    for (const auto& l : m_logs) {
        for (const double v :
             {l.a.x_m, l.a.y_m, l.b.x_m, l.b.y_m, l.height_a_m, l.height_b_m, l.diameter_m})
            if (!std::isfinite(v))
                throw InputError("log index: a log from (" + format_number(l.a.x_m) + ", " +
                                 format_number(l.a.y_m) + ") has a non-finite value");
        if (l.height_a_m < 0 || l.height_b_m < 0 || l.diameter_m < 0)
            throw InputError("log index: a log from (" + format_number(l.a.x_m) + ", " +
                             format_number(l.a.y_m) + ") has a negative height or diameter");
        m_box.push_back({std::min(l.a.x_m, l.b.x_m), std::min(l.a.y_m, l.b.y_m),
                         std::max(l.a.x_m, l.b.x_m), std::max(l.a.y_m, l.b.y_m)});
        m_x0 = std::min(m_x0, m_box.back()[0]), m_y0 = std::min(m_y0, m_box.back()[1]);
        x1 = std::max(x1, m_box.back()[2]), y1 = std::max(y1, m_box.back()[3]);
        m_max_d = std::max(m_max_d, l.diameter_m);
    }
    m_nx = bucket(x1, m_x0) + 1;
    m_ny = bucket(y1, m_y0) + 1;
    m_buckets.resize(static_cast<std::size_t>(m_nx) * m_ny);
    for (std::size_t k = 0; k < m_logs.size(); ++k) {
        const auto& bb = m_box[k];
        for (int j = bucket(bb[1], m_y0); j <= bucket(bb[3], m_y0); ++j)
            for (int i = bucket(bb[0], m_x0); i <= bucket(bb[2], m_x0); ++i)
                m_buckets[static_cast<std::size_t>(j) * m_nx + i].push_back(
                    static_cast<std::int64_t>(k));
    }
}

StemIndex::StemIndex(std::vector<Stem> stems, double bucket_m)
    : m_stems(std::move(stems)), m_size(bucket_m) {
    if (!(bucket_m > 0)) throw InputError("stem index: bucket size must be > 0 m");
    if (m_stems.empty()) return;
    double x1 = -std::numeric_limits<double>::infinity(), y1 = x1;
    m_x0 = m_y0 = std::numeric_limits<double>::infinity();
    for (const auto& s : m_stems) {
        if (!std::isfinite(s.x_m) || !std::isfinite(s.y_m) || !(s.diameter_m >= 0))
            throw InputError("stem index: a stem at (" + format_number(s.x_m) + ", " +
                             format_number(s.y_m) + ") has diameter " +
                             format_number(s.diameter_m) + " m");
        m_x0 = std::min(m_x0, s.x_m), m_y0 = std::min(m_y0, s.y_m);
        m_max_d = std::max(m_max_d, s.diameter_m);
        x1 = std::max(x1, s.x_m), y1 = std::max(y1, s.y_m);
    }
    m_nx = bucket(x1, m_x0) + 1;
    m_ny = bucket(y1, m_y0) + 1;
    m_buckets.resize(static_cast<std::size_t>(m_nx) * m_ny);
    for (std::size_t k = 0; k < m_stems.size(); ++k)
        m_buckets[static_cast<std::size_t>(bucket(m_stems[k].y_m, m_y0)) * m_nx +
                  bucket(m_stems[k].x_m, m_x0)]
            .push_back(static_cast<std::int64_t>(k));
}

namespace {

/// One line driven: the state shared by the planning rounds (the stems to avoid grow when a
/// cluster proves too heavy to push) and the steps of a round.
class LineDrive {
public:
    LineDrive(const Vehicle& v, const StemIndex& index, const LogIndex& logs, const RasterD* dem,
              Point a, Point b, const SmgOptions& opt)
        : m_v(v), m_index(index), m_stems(index.stems()), m_logs(logs), m_dem(dem), m_a(a), m_b(b),
          m_opt(opt), m_w(v.width_m), m_d_crit(critical_diameter_m(v.weight_n(), v.push_height_m)),
          m_reach(0.5 * (index.max_diameter_m() + v.width_m)), m_step(step_limit_m(v)),
          m_ground(v) {}

    LineResult run();

private:
    /// A stem the vehicle goes around: d >= d_crit, rigid, or in a cluster found too heavy.
    bool avoided(std::int64_t k) const {
        return m_stems[static_cast<std::size_t>(k)].diameter_m >= m_d_crit ||
               m_stems[static_cast<std::size_t>(k)].rigid ||
               std::binary_search(m_heavy.begin(), m_heavy.end(), k);
    }
    double elevation(Point p) const;
    /// The terrain beside the track; off the DEM's edge, the centre line's.
    double side_elevation(Point p, Point centre) const {
        if (!m_dem) return 0.0;
        const double z = m_dem->sample_bilinear(p.x_m, p.y_m);
        return std::isnan(z) ? elevation(centre) : z;
    }
    /// The planning grid around the line (within the terrain's bounds when given).
    void make_grid(double straight_m);
    /// Marks the cells an avoided stem's disk, inflated by half the vehicle's width, covers.
    void block_avoided_stems();
    /// The part of log k to drive around ([0, 1] once a drive has met its high part).
    std::pair<double, double> log_high_part(std::int64_t k) const {
        if (std::binary_search(m_high_logs.begin(), m_high_logs.end(), k)) return {0.0, 1.0};
        return mobility::log_high_part(m_logs.logs()[static_cast<std::size_t>(k)], m_step);
    }
    /// Marks the cells within half the vehicle's width and a planning cell of the logs' parts
    /// above the step limit.
    void block_high_logs();
    /// The logs under the cell from c0 along (ux, uy): the highest top met, -1 for none; false
    /// when a log's part above the step limit is met (it is avoided from the next plan on).
    bool logs_in_cell(Point c0, double len, double ux, double uy, double& top_m);
    /// Logs above the step limit whose footprint, inflated by half the vehicle's width, meets
    /// the straight line.
    std::int64_t count_avoided_logs() const;
    /// Drives `path` cell by cell; sets `m_replan` when a cluster is too heavy to push.
    void drive_path(const std::vector<Point>& path, LineResult& out);
    /// One cell of length `len` from c0 along (ux, uy); false when the drive stops there.
    bool drive_cell(Point c0, double len, double ux, double uy, LineResult& out);
    /// Obstacles whose inflated disk meets the straight line.
    std::int64_t count_avoided(double straight_m) const;
    /// False (and NO-GO) where the side slope across the track at `mid` is beyond the limit.
    bool side_slope_holds(Point mid, double ux, double uy, LineResult& out) const;
    /// The ground of the cell at `mid`; NO-GO (with the reason) where it stops the vehicle.
    GroundEffect ground_at(Point mid, LineResult& out) const;

    const Vehicle& m_v;
    const StemIndex& m_index;
    const std::vector<Stem>& m_stems;
    const LogIndex& m_logs;
    const RasterD* m_dem;
    Point m_a, m_b;
    const SmgOptions& m_opt;
    double m_w, m_d_crit, m_reach; ///< width; critical diameter; the farthest a stem blocks
    double m_step;                 ///< the highest log the vehicle climbs
    VehicleGround m_ground;
    std::vector<std::int64_t> m_heavy;     ///< stems of clusters found too heavy (sorted)
    std::vector<std::int64_t> m_high_logs; ///< logs met above the step limit (sorted)
    Grid m_g;
    // A round's drive: the stems pushed and those of the current cell; the cells' lengths and the
    // speed limits at their boundaries.
    std::vector<std::int64_t> m_pushed, m_here, m_crossed;
    std::vector<double> m_cell_len, m_node_cap;
    /// After a log, the distance still to drive at `m_slow_cap` (until the rear axle is over it).
    double m_slow_left = 0, m_slow_cap = 0;
    bool m_replan = false;
};

double LineDrive::elevation(Point p) const {
    if (!m_dem) return 0.0;
    const double z = m_dem->sample_bilinear(p.x_m, p.y_m);
    if (std::isnan(z))
        throw InputError("the line from (" + format_number(m_a.x_m) + ", " +
                         format_number(m_a.y_m) + ") to (" + format_number(m_b.x_m) + ", " +
                         format_number(m_b.y_m) + ") leaves the terrain at (" +
                         format_number(p.x_m) + ", " + format_number(p.y_m) + ")");
    return z;
}

void LineDrive::make_grid(double straight_m) {
    const Point a = m_a, b = m_b;
    m_g.r = std::max(m_opt.grid_fraction_of_width * m_w, kMinPlanningCell_m);
    double x0 = std::min(a.x_m, b.x_m) - m_opt.margin_m,
           x1 = std::max(a.x_m, b.x_m) + m_opt.margin_m;
    double y0 = std::min(a.y_m, b.y_m) - m_opt.margin_m,
           y1 = std::max(a.y_m, b.y_m) + m_opt.margin_m;
    if (m_opt.bounds_m) {
        const auto& bb = *m_opt.bounds_m;
        for (const Point p : {a, b})
            if (p.x_m < bb[0] || p.x_m > bb[2] || p.y_m < bb[1] || p.y_m > bb[3])
                throw InputError("the line end (" + format_number(p.x_m) + ", " +
                                 format_number(p.y_m) + ") is outside the terrain [" +
                                 format_number(bb[0]) + ", " + format_number(bb[2]) + "] x [" +
                                 format_number(bb[1]) + ", " + format_number(bb[3]) + "]");
        x0 = std::max(x0, bb[0]), y0 = std::max(y0, bb[1]);
        x1 = std::min(x1, bb[2]), y1 = std::min(y1, bb[3]);
    }
    m_g.x0 = x0;
    m_g.y0 = y0;
    m_g.nx = std::max(1, static_cast<int>(std::ceil((x1 - x0) / m_g.r)));
    m_g.ny = std::max(1, static_cast<int>(std::ceil((y1 - y0) / m_g.r)));
    if (static_cast<double>(m_g.nx) * m_g.ny > kMaxPlanningCells)
        throw InputError("a line of " + format_number(straight_m) + " m needs a planning grid of " +
                         std::to_string(m_g.nx) + " x " + std::to_string(m_g.ny) +
                         " cells; use shorter lines or a smaller margin");
}

void LineDrive::block_avoided_stems() {
    Grid& g = m_g;
    g.blocked.assign(static_cast<std::size_t>(g.nx) * g.ny, 0);
    m_index.for_each_in_box(g.x0 - m_reach, g.y0 - m_reach, g.x0 + g.nx * g.r + m_reach,
                            g.y0 + g.ny * g.r + m_reach, [&](std::int64_t k) {
                                if (!avoided(k)) return;
                                const Stem& s = m_stems[static_cast<std::size_t>(k)];
                                const double rad = 0.5 * s.diameter_m + 0.5 * m_w;
                                for (int j = std::max(0, g.row(s.y_m - rad));
                                     j <= std::min(g.ny - 1, g.row(s.y_m + rad)); ++j)
                                    for (int i = std::max(0, g.col(s.x_m - rad));
                                         i <= std::min(g.nx - 1, g.col(s.x_m + rad)); ++i) {
                                        const Point c =
                                            g.centre(static_cast<std::int64_t>(j) * g.nx + i);
                                        if (std::hypot(c.x_m - s.x_m, c.y_m - s.y_m) <= rad)
                                            g.blocked[static_cast<std::size_t>(j) * g.nx + i] = 1;
                                    }
                            });
}

void LineDrive::block_high_logs() {
    Grid& g = m_g;
    const double reach = 0.5 * (m_logs.max_diameter_m() + m_w) + g.r;
    m_logs.for_each_in_box(
        g.x0 - reach, g.y0 - reach, g.x0 + g.nx * g.r + reach, g.y0 + g.ny * g.r + reach,
        [&](std::int64_t k) {
            const auto [u0, u1] = log_high_part(k);
            if (u0 > u1) return;
            const Log& l = m_logs.logs()[static_cast<std::size_t>(k)];
            const Point p = point_along(l, u0), q = point_along(l, u1);
            const double rad = 0.5 * (l.diameter_m + m_w) + g.r;
            for (int j = std::max(0, g.row(std::min(p.y_m, q.y_m) - rad));
                 j <= std::min(g.ny - 1, g.row(std::max(p.y_m, q.y_m) + rad)); ++j)
                for (int i = std::max(0, g.col(std::min(p.x_m, q.x_m) - rad));
                     i <= std::min(g.nx - 1, g.col(std::max(p.x_m, q.x_m) + rad)); ++i) {
                    const auto c = static_cast<std::int64_t>(j) * g.nx + i;
                    if (point_segment_distance(g.centre(c), p, q) <= rad)
                        g.blocked[static_cast<std::size_t>(c)] = 1;
                }
        });
}

bool LineDrive::logs_in_cell(Point c0, double len, double ux, double uy, double& top_m) {
    top_m = -1;
    bool ok = true;
    const double half = 0.5 * m_w;
    const Point c1{c0.x_m + len * ux, c0.y_m + len * uy};
    m_logs.for_each_in_box(
        std::min(c0.x_m, c1.x_m) - half, std::min(c0.y_m, c1.y_m) - half,
        std::max(c0.x_m, c1.x_m) + half, std::max(c0.y_m, c1.y_m) + half, [&](std::int64_t k) {
            const Log& l = m_logs.logs()[static_cast<std::size_t>(k)];
            double lo = 0, hi = 1;
            if (!log_in_footprint(l, c0, len, ux, uy, half, lo, hi)) return;
            const auto [u0, u1] = log_high_part(k);
            if (u0 <= u1 && lo <= u1 && hi >= u0) {
                ok = false;
                m_high_logs.push_back(k);
                return;
            }
            const double dh = l.height_b_m - l.height_a_m;
            top_m = std::max({top_m, l.height_a_m + lo * dh, l.height_a_m + hi * dh});
            m_crossed.push_back(k);
        });
    if (!ok) std::sort(m_high_logs.begin(), m_high_logs.end());
    return ok;
}

bool LineDrive::side_slope_holds(Point mid, double ux, double uy, LineResult& out) const {
    // The height difference across the vehicle's track at the cell's middle (a wheel off the
    // DEM's edge falls back to the centre line).
    const double half = 0.5 * m_v.track_m;
    const double zl = side_elevation({mid.x_m - half * uy, mid.y_m + half * ux}, mid);
    const double zr = side_elevation({mid.x_m + half * uy, mid.y_m - half * ux}, mid);
    const double side = std::abs(zl - zr) / m_v.track_m;
    if (std::atan(side) <= m_v.max_side_slope_deg * std::numbers::pi / 180) return true;
    out.nogo = true;
    out.nogo_reason = "a side slope of " + format_number(side) +
                      " beyond the vehicle's side-slope limit at (" + format_number(mid.x_m) +
                      ", " + format_number(mid.y_m) + ")";
    return false;
}

bool LineDrive::drive_cell(Point c0, double len, double ux, double uy, LineResult& out) {
    const Vehicle& v = m_v;
    const double w = m_w;
    const Point c1{c0.x_m + len * ux, c0.y_m + len * uy};
    double force = 0;
    m_here.clear();
    m_index.for_each_in_box(std::min(c0.x_m, c1.x_m) - w, std::min(c0.y_m, c1.y_m) - w,
                            std::max(c0.x_m, c1.x_m) + w, std::max(c0.y_m, c1.y_m) + w,
                            [&](std::int64_t k) {
                                const Stem& st = m_stems[static_cast<std::size_t>(k)];
                                const double dx = st.x_m - c0.x_m, dy = st.y_m - c0.y_m;
                                const double t = dx * ux + dy * uy, lat = -dx * uy + dy * ux;
                                if (avoided(k) || t < 0 || t >= len || std::abs(lat) > 0.5 * w)
                                    return;
                                force += override_force_n(st.diameter_m, v.push_height_m);
                                m_here.push_back(k);
                            });
    const double grade = (elevation(c1) - elevation(c0)) / len;
    if (std::atan(grade) > v.max_climb_deg * std::numbers::pi / 180) {
        out.nogo = true;
        out.nogo_reason = "a grade of " + format_number(grade) +
                          " beyond the vehicle's climb limit at (" + format_number(c0.x_m) + ", " +
                          format_number(c0.y_m) + ")";
        return false;
    }
    const Point mid{0.5 * (c0.x_m + c1.x_m), 0.5 * (c0.y_m + c1.y_m)};
    if (!side_slope_holds(mid, ux, uy, out)) return false;
    const GroundEffect ground = ground_at(mid, out);
    if (!ground.go()) return false;
    const double base = resistance_n(v, grade, ground);
    const double mu = ground.traction_coefficient;
    const double speed = steady_speed_m_per_s(v, base + force, mu);
    if (speed <= 0) {
        if (force > 0 && steady_speed_m_per_s(v, base, mu) > 0) {
            m_heavy.insert(m_heavy.end(), m_here.begin(), m_here.end());
            std::sort(m_heavy.begin(), m_heavy.end());
            m_replan = true; // a cluster too heavy to push: go around it
        } else {
            out.nogo = true;
            out.nogo_reason =
                "a grade of " + format_number(grade) + " it cannot climb" +
                (mu < v.traction_coefficient || ground.soil_resistance > 0 ? " on this soil" : "") +
                " at (" + format_number(c0.x_m) + ", " + format_number(c0.y_m) + ")";
        }
        return false;
    }
    double top = -1;
    if (!logs_in_cell(c0, len, ux, uy, top)) {
        m_replan = true; // the high part of a log: go around it
        return false;
    }
    double cap = speed;
    if (top >= 0) { // slow from the front axle's log until the rear axle is over it
        const double vc = step_crossing_speed_m_per_s(v, top);
        m_slow_cap = m_slow_left > 0 ? std::min(m_slow_cap, vc) : vc;
        m_slow_left = len + v.wheelbase_m;
        m_node_cap.back() = std::min(m_node_cap.back(), vc);
    }
    if (m_slow_left > 0) {
        cap = std::min(cap, m_slow_cap);
        m_slow_left -= len;
    }
    m_node_cap.back() = std::min(m_node_cap.back(), cap);
    m_node_cap.push_back(cap);
    m_cell_len.push_back(len);
    out.path_m += len;
    if (force > 0) out.override_m += len;
    m_pushed.insert(m_pushed.end(), m_here.begin(), m_here.end());
    return true;
}

void LineDrive::drive_path(const std::vector<Point>& path, LineResult& out) {
    // Cells of one vehicle width along each segment; the speed limits at the cell boundaries are
    // the steady speeds of the cells on either side and, at a turn of the path, sqrt(a_lat R)
    // with R the largest arc that fits half the shorter leg (at least the vehicle's tightest
    // turn).
    m_pushed.clear();
    m_crossed.clear();
    m_slow_left = 0;
    m_cell_len.clear();
    m_node_cap.assign(1, std::numeric_limits<double>::infinity());
    m_replan = false;
    for (std::size_t s = 0; s + 1 < path.size() && !m_replan && !out.nogo; ++s) {
        const Point p = path[s], q = path[s + 1];
        const double seg = distance(p, q);
        if (!(seg > 0)) continue;
        const double ux = (q.x_m - p.x_m) / seg, uy = (q.y_m - p.y_m) / seg;
        if (s > 0) {
            const Point o = path[s - 1];
            const double prev = distance(o, p);
            const double turn = std::acos(
                std::clamp(((p.x_m - o.x_m) * ux + (p.y_m - o.y_m) * uy) / prev, -1.0, 1.0));
            if (turn > kMinTurn_rad) {
                const double radius = std::max(0.5 * std::min(prev, seg) / std::tan(0.5 * turn),
                                               m_v.min_turn_radius_m);
                m_node_cap.back() = std::min(
                    m_node_cap.back(), std::sqrt(m_v.max_lateral_acceleration_m_per_s2 * radius));
            }
        }
        for (double along = 0; along < seg; along += m_w) {
            const double len = std::min(m_w, seg - along);
            if (!drive_cell({p.x_m + along * ux, p.y_m + along * uy}, len, ux, uy, out)) break;
        }
    }
}

std::int64_t LineDrive::count_avoided(double straight_m) const {
    const Point a = m_a, b = m_b;
    std::int64_t n = 0;
    m_index.for_each_in_box(
        std::min(a.x_m, b.x_m) - m_reach, std::min(a.y_m, b.y_m) - m_reach,
        std::max(a.x_m, b.x_m) + m_reach, std::max(a.y_m, b.y_m) + m_reach, [&](std::int64_t kk) {
            if (!avoided(kk)) return;
            const auto k = static_cast<std::size_t>(kk);
            const double dx = b.x_m - a.x_m, dy = b.y_m - a.y_m;
            const double t =
                std::clamp(((m_stems[k].x_m - a.x_m) * dx + (m_stems[k].y_m - a.y_m) * dy) /
                               (straight_m * straight_m),
                           0.0, 1.0);
            const double dist =
                std::hypot(a.x_m + t * dx - m_stems[k].x_m, a.y_m + t * dy - m_stems[k].y_m);
            n += dist <= 0.5 * (m_stems[k].diameter_m + m_w);
        });
    return n;
}

std::int64_t LineDrive::count_avoided_logs() const {
    const Point a = m_a, b = m_b;
    const double reach = 0.5 * (m_logs.max_diameter_m() + m_w);
    std::int64_t n = 0;
    m_logs.for_each_in_box(
        std::min(a.x_m, b.x_m) - reach, std::min(a.y_m, b.y_m) - reach,
        std::max(a.x_m, b.x_m) + reach, std::max(a.y_m, b.y_m) + reach, [&](std::int64_t k) {
            const auto [u0, u1] = log_high_part(k);
            if (u0 > u1) return;
            const Log& l = m_logs.logs()[static_cast<std::size_t>(k)];
            n += segment_distance(a, b, point_along(l, u0), point_along(l, u1)) <=
                 0.5 * (l.diameter_m + m_w);
        });
    return n;
}

LineResult LineDrive::run() {
    LineResult out;
    const double straight = distance(m_a, m_b);
    if (!(straight > 0)) throw InputError("a line must have two different ends");
    make_grid(straight);
    bool settled = false;
    for (int round = 0; round < kMaxReplans && !settled; ++round) {
        out = LineResult{};
        out.straight_m = straight;
        block_avoided_stems();
        block_high_logs();
        if (m_g.blocked_at(m_a.x_m, m_a.y_m) || m_g.blocked_at(m_b.x_m, m_b.y_m)) {
            out.nogo = true;
            out.nogo_reason =
                "the line starts or ends next to a stem it cannot override or a log it cannot "
                "climb";
            settled = true;
            break;
        }
        const std::vector<Point> path = plan(m_g, m_a, m_b);
        if (path.empty()) {
            out.nogo = true;
            out.nogo_reason = "no path around the stems it cannot override and the logs it "
                              "cannot climb";
            settled = true;
            break;
        }
        drive_path(path, out);
        if (m_replan) continue;
        if (!out.nogo)
            out.time_s = profile_time_s(m_cell_len, m_node_cap, m_v.max_acceleration_m_per_s2,
                                        m_v.max_deceleration_m_per_s2);
        std::sort(m_pushed.begin(), m_pushed.end());
        m_pushed.erase(std::unique(m_pushed.begin(), m_pushed.end()), m_pushed.end());
        out.overridden = static_cast<std::int64_t>(m_pushed.size());
        out.pushed_stems = m_pushed;
        out.path = path;
        out.avoided = count_avoided(straight);
        std::sort(m_crossed.begin(), m_crossed.end());
        out.logs_crossed = std::unique(m_crossed.begin(), m_crossed.end()) - m_crossed.begin();
        out.logs_avoided = count_avoided_logs();
        settled = true;
    }
    if (!settled) {
        out.straight_m = straight;
        out.nogo = true;
        out.nogo_reason = "clusters too heavy to push or logs too high kept closing the path "
                          "after " +
                          std::to_string(kMaxReplans) + " plans";
    }
    if (out.nogo) {
        out.time_s = std::numeric_limits<double>::infinity();
        out.smg_m_per_s = 0;
    } else {
        out.smg_m_per_s = out.straight_m / out.time_s;
    }
    return out;
}

} // namespace

void use_soil(SmgOptions& opt, const RasterD& rci_kpa) {
    opt.ground.rci_kpa = &rci_kpa;
}

GroundEffect LineDrive::ground_at(Point mid, LineResult& out) const {
    // Without ground maps the cell is firm and dry: the vehicle's own figures.
    GroundEffect e = m_ground.effect(m_opt.ground.at(mid.x_m, mid.y_m));
    if (!e.go()) {
        out.nogo = true;
        out.nogo_reason =
            e.why + " at (" + format_number(mid.x_m) + ", " + format_number(mid.y_m) + ")";
    }
    return e;
}

LineResult drive_line(const Vehicle& v, const StemIndex& index, const LogIndex& logs,
                      const RasterD* dem, Point a, Point b, const SmgOptions& opt) {
    return LineDrive(v, index, logs, dem, a, b, opt).run();
}

LineResult drive_line(const Vehicle& v, const StemIndex& index, const RasterD* dem, Point a,
                      Point b, const SmgOptions& opt) {
    static const LogIndex none;
    return LineDrive(v, index, none, dem, a, b, opt).run();
}

} // namespace ecoterra::mobility
