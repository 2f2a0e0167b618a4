#include "ecoterra/mobility/map.hpp"

#include "ecoterra/error.hpp"
#include "ecoterra/mobility/override.hpp"
#include "stats.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace ecoterra::mobility {

namespace {

using nlohmann::json;

/// A factor limits a cell when it costs more than this share of the top speed (below it, the
/// vehicle's own power and top speed do: "none").
constexpr double kLimitShare = 0.1;
/// Lateral offsets of the lanes: at most this fraction of the vehicle's width apart (drive_line's
/// planning grid).
constexpr double kLaneStepOfWidth = 0.125;
/// Relative tolerance of "a whole multiple of the terrain's cell".
constexpr double kCellTolerance = 1e-6;

/// One heading's result in one cell.
struct Crossing {
    double speed = 0;
    Limit limit = Limit::none;
};

/// What a heading of a cell is before its ground is known.
enum class Static : std::uint8_t { open, nodata, slope, closed };

struct HeadingPlan {
    double grade = 0;
    double v_slope = 0; ///< the steady speed on its grade on firm ground
    Static state = Static::open;
    bool free_lane = false;   ///< a lane with nothing to push or climb: the ground's speed
    bool veg_blocked = false; ///< some lane is closed by a stem (or, daily, a heavy cluster)
    std::uint32_t lane_begin = 0, lane_end = 0; ///< its lanes with stems to push or logs to climb
};

/// An open lane with stems to push (the override force of each segment) or logs to climb.
struct LanePlan {
    std::uint32_t force_begin = 0;
    double top = -1; ///< the highest log top across it, m (-1: none)
};

} // namespace

/// The static part of a map (map.hpp's MapPlan).
struct MapPlan::Impl {
    const Vehicle v;
    VehicleGround vg;
    RasterD dem; ///< for the ground's grid
    int k = 1;   ///< terrain cells per map cell side
    int headings = 8;
    GridSpec grid;
    double c = 1, w = 1, d_crit = 0, step = 0, top = 0, max_grade = 0, max_side = 0;
    int nseg = 1;
    double seg_len = 1;
    std::vector<double> offsets;                 ///< lateral offsets of the lanes
    std::vector<std::pair<double, double>> dirs; ///< the headings' unit vectors (east, north)
    std::vector<HeadingPlan> plan;               ///< [cell][heading]
    std::vector<LanePlan> lanes;
    std::vector<double> forces; ///< nseg per lane

    Impl(const Vehicle& v_, const RasterD& dem_, const MapOptions& opt);
    void prepare(const StemIndex& stems, const LogIndex& logs);
    /// The ground of map cell (i, j): the median of the terrain cells it covers.
    GroundCell ground_of(const GroundMaps& g, int i, int j) const;
    /// The grade along (ux, uy) and the side slope across the track at `c` (NaN off the DEM).
    std::pair<double, double> slopes(Point c, double ux, double uy) const;
    double z_or(Point p, double fallback) const {
        const double z = dem.sample_bilinear(p.x_m, p.y_m);
        return std::isnan(z) ? fallback : z;
    }
    bool avoided(const Stem& s) const { return s.rigid || s.diameter_m >= d_crit; }
    /// Lays out one lane of a heading of the cell at `c`: false when closed (setting
    /// `veg_blocked` when a stem closes it); appends it to the lanes when it has something to
    /// push or climb, else sets `free_lane`.
    bool plan_lane(Point c, double ux, double uy, double o, const StemIndex& stems,
                   const LogIndex& logs, const std::vector<std::int64_t>& near_stems,
                   const std::vector<std::int64_t>& near_logs, HeadingPlan& h,
                   std::vector<double>& seg, std::vector<LanePlan>& lane_out,
                   std::vector<double>& force_out) const;
    void plan_cell(int i, int j, const StemIndex& stems, const LogIndex& logs,
                   std::vector<std::int64_t>& near_stems, std::vector<std::int64_t>& near_logs,
                   std::vector<double>& seg, std::vector<LanePlan>& lane_out,
                   std::vector<double>& force_out);
    /// One heading on the day's ground.
    Crossing cross(const HeadingPlan& h, const GroundEffect& g) const;
};

namespace {

/// The map's summary figures (`counts`: the cell-headings of each limiting factor) and its
/// rasters' CRS.
void summarise(MobilityMap& m, const std::array<double, kLimitKinds>& counts,
               const std::string& crs) {
    const double cells = static_cast<double>(m.grid.nx) * m.grid.ny;
    const double nh = static_cast<double>(m.headings_deg.size());
    double speed = 0, go = 0, any = 0;
    for (int j = 0; j < m.grid.ny; ++j)
        for (int i = 0; i < m.grid.nx; ++i) {
            speed += m.speed_mean_m_per_s(i, j);
            go += m.go_fraction(i, j) * nh;
            any += m.go_fraction(i, j) > 0 ? 1 : 0;
        }
    double headings = 0;
    for (const double n : counts) headings += n;
    m.crs_wkt = crs;
    for (auto& r : m.speed_m_per_s) r.set_crs_wkt(crs);
    for (auto& r : m.limit) r.set_crs_wkt(crs);
    for (RasterD* r : {&m.speed_mean_m_per_s, &m.go_fraction, &m.rci_kpa, &m.water_depth_m})
        r->set_crs_wkt(crs);
    m.limiting.set_crs_wkt(crs);
    m.mean_speed_m_per_s = speed / cells;
    m.go_share = go / (cells * nh);
    m.any_go_share = any / cells;
    for (std::size_t q = 0; q < counts.size(); ++q)
        m.limit_share[q] = headings > 0 ? counts[q] / headings : 0.0;
}

} // namespace

MapPlan::Impl::Impl(const Vehicle& v_, const RasterD& dem_, const MapOptions& opt)
    : v(v_), vg(v), dem(dem_), headings(opt.headings), w(v.width_m),
      d_crit(critical_diameter_m(v.weight_n(), v.push_height_m)), step(step_limit_m(v)) {
    const GridSpec& g = dem.grid();
    if (opt.headings < 1 || opt.headings > 360)
        throw InputError("mobility map: headings = " + std::to_string(opt.headings) +
                         " must be within 1..360");
    if (opt.cell_m != 0) {
        const double ratio = opt.cell_m / g.cell_size_m;
        if (!(opt.cell_m > 0) || ratio < 1 - kCellTolerance)
            throw InputError("mobility map: cell = " + format_number(opt.cell_m) +
                             " m is finer than the terrain's (hydrology) cell of " +
                             format_number(g.cell_size_m) + " m");
        k = static_cast<int>(std::lround(ratio));
        if (std::abs(ratio - k) > kCellTolerance * ratio)
            throw InputError("mobility map: cell = " + format_number(opt.cell_m) +
                             " m is not a whole multiple of the terrain's cell of " +
                             format_number(g.cell_size_m) + " m");
    }
    if (g.nx / k < 1 || g.ny / k < 1)
        throw InputError("mobility map: cell = " + format_number(opt.cell_m) +
                         " m is larger than the terrain");
    grid = GridSpec{g.nx / k, g.ny / k, g.cell_size_m * k, g.origin_x_m, g.origin_y_m};
    c = grid.cell_size_m;
    const int n = std::max(1, static_cast<int>(std::ceil(c / (kLaneStepOfWidth * w))));
    for (int q = 0; q <= n; ++q) offsets.push_back(-0.5 * c + c * q / n);
    top = steady_speed_m_per_s(v, rolling_resistance_n(v, 0.0));
    for (int h = 0; h < headings; ++h) {
        const double th = 2 * std::numbers::pi * h / headings;
        dirs.emplace_back(std::sin(th), std::cos(th));
    }
    max_grade = std::tan(v.max_climb_deg * std::numbers::pi / 180);
    max_side = std::tan(v.max_side_slope_deg * std::numbers::pi / 180);
    // Segments of one vehicle width along the cell (one width-long segment centred on a shorter
    // cell).
    nseg = std::max(1, static_cast<int>(std::ceil(c / w - 1e-9)));
    seg_len = std::max(c / nseg, w);
}

GroundCell MapPlan::Impl::ground_of(const GroundMaps& gm, int i, int j) const {
    const GridSpec& g = dem.grid();
    if (k == 1) return gm.at(g.x_of(i), g.y_of(j));
    std::vector<double> rci, water;
    int fine = 0;
    for (int jj = j * k; jj < (j + 1) * k; ++jj)
        for (int ii = i * k; ii < (i + 1) * k; ++ii) {
            const GroundCell cell = gm.at(g.x_of(ii), g.y_of(jj));
            if (!std::isnan(cell.rci_kpa)) rci.push_back(cell.rci_kpa);
            water.push_back(cell.water_depth_m);
            fine += cell.fine_grained ? 1 : 0;
        }
    GroundCell out;
    out.rci_kpa =
        rci.empty() ? std::numeric_limits<double>::quiet_NaN() : detail::quantile(rci, 0.5);
    out.water_depth_m = detail::quantile(water, 0.5);
    out.fine_grained = 2 * fine >= k * k;
    return out;
}

std::pair<double, double> MapPlan::Impl::slopes(Point p, double ux, double uy) const {
    const double zc = dem.sample_bilinear(p.x_m, p.y_m);
    if (std::isnan(zc)) return {std::nan(""), std::nan("")};
    const double half = 0.5 * std::max(c, w);
    const double zf = dem.sample_bilinear(p.x_m + half * ux, p.y_m + half * uy);
    const double zb = dem.sample_bilinear(p.x_m - half * ux, p.y_m - half * uy);
    double grade = 0;
    if (!std::isnan(zf) && !std::isnan(zb))
        grade = (zf - zb) / (2 * half);
    else if (!std::isnan(zf))
        grade = (zf - zc) / half;
    else if (!std::isnan(zb))
        grade = (zc - zb) / half;
    const double t = 0.5 * v.track_m;
    const double zl = z_or({p.x_m - t * uy, p.y_m + t * ux}, zc);
    const double zr = z_or({p.x_m + t * uy, p.y_m - t * ux}, zc);
    return {grade, std::abs(zl - zr) / v.track_m};
}

bool MapPlan::Impl::plan_lane(Point p, double ux, double uy, double o, const StemIndex& stems,
                              const LogIndex& logs, const std::vector<std::int64_t>& near_stems,
                              const std::vector<std::int64_t>& near_logs, HeadingPlan& h,
                              std::vector<double>& seg, std::vector<LanePlan>& lane_out,
                              std::vector<double>& force_out) const {
    seg.assign(static_cast<std::size_t>(nseg), 0.0);
    bool any = false;
    for (const std::int64_t q : near_stems) {
        const Stem& s = stems.stems()[static_cast<std::size_t>(q)];
        // The stem in the lane's frame: along from the cell's centre, across from the lane.
        const double dx = s.x_m - p.x_m, dy = s.y_m - p.y_m;
        const double along = dx * ux + dy * uy, lat = -dx * uy + dy * ux - o;
        if (avoided(s)) {
            // Closer to the lane's centre line (a segment of the cell's length) than (d + w)/2.
            const double beyond = std::max(0.0, std::abs(along) - 0.5 * c);
            const double reach = 0.5 * (s.diameter_m + w);
            if (beyond * beyond + lat * lat >= reach * reach) continue;
            h.veg_blocked = h.veg_blocked || !s.rigid;
            return false;
        }
        if (std::abs(lat) > 0.5 * w) continue;
        const double t = along + 0.5 * c;
        for (int q2 = 0; q2 < nseg; ++q2) {
            const double mid = (q2 + 0.5) * c / nseg;
            if (t >= mid - 0.5 * seg_len && t < mid + 0.5 * seg_len) {
                seg[static_cast<std::size_t>(q2)] +=
                    override_force_n(s.diameter_m, v.push_height_m);
                any = true;
            }
        }
    }
    double top_m = -1;
    const Point a{p.x_m - 0.5 * c * ux - o * uy, p.y_m - 0.5 * c * uy + o * ux};
    for (const std::int64_t q : near_logs) {
        const Log& l = logs.logs()[static_cast<std::size_t>(q)];
        double lo = 0, hi = 1;
        if (!log_in_footprint(l, a, c, ux, uy, 0.5 * w, lo, hi)) continue;
        const auto [u0, u1] = log_high_part(l, step);
        if (u0 <= u1 && lo <= u1 && hi >= u0) return false; // a log too high to climb
        const double dh = l.height_b_m - l.height_a_m;
        top_m = std::max({top_m, l.height_a_m + lo * dh, l.height_a_m + hi * dh});
    }
    if (!any && top_m < 0) {
        h.free_lane = true;
        return true;
    }
    lane_out.push_back({static_cast<std::uint32_t>(force_out.size()), top_m});
    force_out.insert(force_out.end(), seg.begin(), seg.end());
    return true;
}

void MapPlan::Impl::plan_cell(int i, int j, const StemIndex& stems, const LogIndex& logs,
                              std::vector<std::int64_t>& near_stems,
                              std::vector<std::int64_t>& near_logs, std::vector<double>& seg,
                              std::vector<LanePlan>& lane_out, std::vector<double>& force_out) {
    const Point p{grid.x_of(i), grid.y_of(j)};
    // Everything within reach of a lane through the cell, in any heading.
    const double reach = 0.5 * std::sqrt(2.0) * std::max(c, w) + 0.5 * w;
    const double rs = reach + 0.5 * stems.max_diameter_m();
    near_stems.clear();
    stems.for_each_in_box(p.x_m - rs, p.y_m - rs, p.x_m + rs, p.y_m + rs,
                          [&](std::int64_t q) { near_stems.push_back(q); });
    near_logs.clear();
    logs.for_each_in_box(p.x_m - reach, p.y_m - reach, p.x_m + reach, p.y_m + reach,
                         [&](std::int64_t q) { near_logs.push_back(q); });
    for (int hd = 0; hd < headings; ++hd) {
        HeadingPlan& h = plan[(static_cast<std::size_t>(j) * grid.nx + i) * headings + hd];
        const auto [ux, uy] = dirs[static_cast<std::size_t>(hd)];
        const auto [grade, side] = slopes(p, ux, uy);
        h.grade = grade;
        if (std::isnan(grade)) {
            h.state = Static::nodata;
            continue;
        }
        if (grade > max_grade || side > max_side) {
            h.state = Static::slope;
            continue;
        }
        const double firm = rolling_resistance_n(v, grade) + grade_resistance_n(v, grade);
        h.v_slope = std::min(top, steady_speed_m_per_s(v, firm));
        h.lane_begin = static_cast<std::uint32_t>(lane_out.size());
        const std::size_t force_begin = force_out.size();
        bool open = false;
        for (const double o : offsets) {
            open = plan_lane(p, ux, uy, o, stems, logs, near_stems, near_logs, h, seg, lane_out,
                             force_out) ||
                   open;
            if (h.free_lane) break; // the best a lane can be
        }
        if (h.free_lane) { // the others cannot beat it
            lane_out.resize(h.lane_begin);
            force_out.resize(force_begin);
        }
        h.lane_end = static_cast<std::uint32_t>(lane_out.size());
        if (!open) h.state = Static::closed;
    }
}

void MapPlan::Impl::prepare(const StemIndex& stems, const LogIndex& logs) {
    plan.assign(static_cast<std::size_t>(grid.size()) * headings, HeadingPlan{});
    // Rows are planned on their own and their lanes joined in row order: any thread count gives
    // the same plan.
    std::vector<std::vector<LanePlan>> row_lanes(static_cast<std::size_t>(grid.ny));
    std::vector<std::vector<double>> row_forces(static_cast<std::size_t>(grid.ny));
#pragma omp parallel
    {
        std::vector<std::int64_t> near_stems, near_logs;
        std::vector<double> seg;
#pragma omp for schedule(dynamic, 4)
        for (int j = 0; j < grid.ny; ++j)
            for (int i = 0; i < grid.nx; ++i)
                plan_cell(i, j, stems, logs, near_stems, near_logs, seg,
                          row_lanes[static_cast<std::size_t>(j)],
                          row_forces[static_cast<std::size_t>(j)]);
    }
    for (int j = 0; j < grid.ny; ++j) {
        const auto lane0 = static_cast<std::uint32_t>(lanes.size());
        const auto force0 = static_cast<std::uint32_t>(forces.size());
        for (LanePlan l : row_lanes[static_cast<std::size_t>(j)]) {
            l.force_begin += force0;
            lanes.push_back(l);
        }
        forces.insert(forces.end(), row_forces[static_cast<std::size_t>(j)].begin(),
                      row_forces[static_cast<std::size_t>(j)].end());
        for (int i = 0; i < grid.nx; ++i)
            for (int hd = 0; hd < headings; ++hd) {
                HeadingPlan& h = plan[(static_cast<std::size_t>(j) * grid.nx + i) * headings + hd];
                h.lane_begin += lane0;
                h.lane_end += lane0;
            }
    }
}

Crossing MapPlan::Impl::cross(const HeadingPlan& h, const GroundEffect& g) const {
    if (h.state == Static::nodata) return {0, Limit::nodata};
    if (h.state == Static::slope) return {0, Limit::slope};
    if (!g.go()) return {0, g.nogo};
    const double base = resistance_n(v, h.grade, g);
    const double v_soil =
        std::min(h.v_slope, steady_speed_m_per_s(v, base, g.traction_coefficient));
    if (!(v_soil > 0)) return {0, h.v_slope > 0 ? Limit::soil : Limit::slope};
    double best = h.free_lane ? v_soil : 0, best_veg = best;
    bool veg_blocked = h.veg_blocked;
    for (std::uint32_t q = h.lane_begin; q < h.lane_end && !h.free_lane; ++q) {
        const LanePlan& l = lanes[q];
        double time = 0;
        bool open = true;
        for (int s = 0; s < nseg; ++s) {
            const double f = forces[l.force_begin + static_cast<std::uint32_t>(s)];
            const double sp =
                f > 0 ? std::min(v_soil, steady_speed_m_per_s(v, base + f, g.traction_coefficient))
                      : v_soil;
            if (!(sp > 0)) {
                open = false;
                veg_blocked = true; // a cluster too heavy to push on this ground
                break;
            }
            time += c / nseg / sp;
        }
        if (!open) continue;
        const double v_veg = c / time;
        double v_lane = v_veg;
        if (l.top >= 0) { // the slow crossing lasts until the rear axle is over the log
            const double cap = step_crossing_speed_m_per_s(v, l.top);
            const double slow = std::min(c, v.wheelbase_m + seg_len);
            v_lane = c / (slow / std::min(cap, v_veg) + (c - slow) / v_veg);
        }
        if (v_lane > best) best = v_lane, best_veg = v_veg;
    }
    if (!(best > 0)) return {0, veg_blocked ? Limit::vegetation : Limit::obstacle};
    // The limiting factor: the one that costs the most speed, if it costs more than 10 %.
    const std::array<std::pair<double, Limit>, 4> drops{{{top - h.v_slope, Limit::slope},
                                                         {h.v_slope - v_soil, Limit::soil},
                                                         {v_soil - best_veg, Limit::vegetation},
                                                         {best_veg - best, Limit::obstacle}}};
    const auto worst = *std::max_element(drops.begin(), drops.end(),
                                         [](auto x, auto y) { return x.first < y.first; });
    return {best, worst.first > kLimitShare * top ? worst.second : Limit::none};
}

MapPlan::MapPlan(const Vehicle& v, const RasterD& dem, const StemIndex& stems, const LogIndex& logs,
                 const MapOptions& opt)
    : m(std::make_unique<Impl>(v, dem, opt)) {
    m->prepare(stems, logs);
}

MapPlan::~MapPlan() = default;
MapPlan::MapPlan(MapPlan&&) noexcept = default;

const GridSpec& MapPlan::grid() const {
    return m->grid;
}

MobilityMap MapPlan::map(const GroundMaps& ground, bool per_heading) const {
    const Impl& p = *m;
    MobilityMap out;
    out.grid = p.grid;
    for (int h = 0; h < p.headings; ++h) {
        out.headings_deg.push_back(360.0 * h / p.headings);
        if (!per_heading) continue;
        out.speed_m_per_s.emplace_back(out.grid, 0.0);
        out.limit.emplace_back(out.grid, static_cast<std::uint8_t>(Limit::nodata));
    }
    out.speed_mean_m_per_s = RasterD(out.grid, 0.0);
    out.go_fraction = RasterD(out.grid, 0.0);
    out.limiting = RasterU8(out.grid, static_cast<std::uint8_t>(Limit::nodata));
    out.rci_kpa = RasterD(out.grid, std::numeric_limits<double>::quiet_NaN());
    out.water_depth_m = RasterD(out.grid, 0.0);
    out.top_speed_m_per_s = p.top;
    // The cell-headings of each limiting factor, per row (added in row order).
    std::vector<std::array<double, kLimitKinds>> rows(static_cast<std::size_t>(out.grid.ny));
    // Cells are independent: any thread count gives the same map.
#pragma omp parallel for schedule(dynamic, 4)
    for (int j = 0; j < out.grid.ny; ++j)
        for (int i = 0; i < out.grid.nx; ++i) {
            const GroundCell gc = p.ground_of(ground, i, j);
            out.rci_kpa(i, j) = gc.rci_kpa;
            out.water_depth_m(i, j) = gc.water_depth_m;
            const GroundEffect g = p.vg.effect(gc); // without maps: firm, dry ground
            std::array<int, kLimitKinds> count{};
            double sum = 0;
            int go = 0;
            for (int hd = 0; hd < p.headings; ++hd) {
                const HeadingPlan& h =
                    p.plan[(static_cast<std::size_t>(j) * out.grid.nx + i) * p.headings + hd];
                const Crossing x = p.cross(h, g);
                if (per_heading) {
                    out.speed_m_per_s[static_cast<std::size_t>(hd)](i, j) = x.speed;
                    out.limit[static_cast<std::size_t>(hd)](i, j) =
                        static_cast<std::uint8_t>(x.limit);
                }
                sum += x.speed;
                go += x.speed > 0 ? 1 : 0;
                if (x.limit != Limit::nodata) ++count[static_cast<std::size_t>(x.limit)];
            }
            for (int q = 0; q < kLimitKinds; ++q)
                rows[static_cast<std::size_t>(j)][static_cast<std::size_t>(q)] +=
                    count[static_cast<std::size_t>(q)];
            out.speed_mean_m_per_s(i, j) = sum / p.headings;
            out.go_fraction(i, j) = static_cast<double>(go) / p.headings;
            const auto most = std::max_element(count.begin(), count.end());
            out.limiting(i, j) = *most == 0 ? static_cast<std::uint8_t>(Limit::nodata)
                                            : static_cast<std::uint8_t>(most - count.begin());
        }
    std::array<double, kLimitKinds> counts{};
    for (const auto& r : rows)
        for (int q = 0; q < kLimitKinds; ++q)
            counts[static_cast<std::size_t>(q)] += r[static_cast<std::size_t>(q)];
    summarise(out, counts, p.dem.crs_wkt());
    return out;
}

MobilityMap mobility_map(const Vehicle& v, const RasterD& dem, const StemIndex& stems,
                         const LogIndex& logs, const GroundMaps& ground, const MapOptions& opt) {
    return MapPlan(v, dem, stems, logs, opt).map(ground);
}

void MapSeason::add(const MobilityMap& day) {
    if (m_days == 0) {
        m_grid = day.grid;
        m_crs = day.crs_wkt;
        m_go.assign(static_cast<std::size_t>(m_grid.size()), 0);
    } else if (day.grid.nx != m_grid.nx || day.grid.ny != m_grid.ny) {
        throw Error("MapSeason: a day's map is not on the season's grid");
    }
    const std::size_t n = static_cast<std::size_t>(m_grid.size());
    m_speed.reserve(m_speed.size() + n);
    for (int j = 0; j < m_grid.ny; ++j)
        for (int i = 0; i < m_grid.nx; ++i) {
            m_speed.push_back(static_cast<float>(day.speed_mean_m_per_s(i, j)));
            m_go[static_cast<std::size_t>(j) * m_grid.nx + i] += day.go_fraction(i, j) > 0 ? 1 : 0;
        }
    ++m_days;
}

RasterD MapSeason::go_share_of_days() const {
    RasterD r(m_grid, 0.0);
    r.set_crs_wkt(m_crs);
    for (int j = 0; j < m_grid.ny; ++j)
        for (int i = 0; i < m_grid.nx; ++i)
            r(i, j) = m_days > 0
                          ? static_cast<double>(m_go[static_cast<std::size_t>(j) * m_grid.nx + i]) /
                                m_days
                          : 0.0;
    return r;
}

RasterD MapSeason::speed_quantile_m_per_s(double q) const {
    RasterD r(m_grid, 0.0);
    r.set_crs_wkt(m_crs);
    const std::size_t n = static_cast<std::size_t>(m_grid.size());
    std::vector<double> v(static_cast<std::size_t>(m_days));
    for (int j = 0; j < m_grid.ny && m_days > 0; ++j)
        for (int i = 0; i < m_grid.nx; ++i) {
            const std::size_t c = static_cast<std::size_t>(j) * m_grid.nx + i;
            for (int d = 0; d < m_days; ++d)
                v[static_cast<std::size_t>(d)] = m_speed[static_cast<std::size_t>(d) * n + c];
            r(i, j) = detail::quantile(v, q);
        }
    return r;
}

json to_json(const MobilityMap& m) {
    json shares = json::object();
    for (int k = 0; k < kLimitKinds; ++k)
        shares[limit_name(static_cast<Limit>(k))] = m.limit_share[static_cast<std::size_t>(k)];
    return {{"cells", {{"nx", m.grid.nx}, {"ny", m.grid.ny}}},
            {"cell_size_m", m.grid.cell_size_m},
            {"origin_m", {m.grid.origin_x_m, m.grid.origin_y_m}},
            {"headings_deg", m.headings_deg},
            {"mean_speed_m_per_s", m.mean_speed_m_per_s},
            {"top_speed_m_per_s", m.top_speed_m_per_s},
            {"go_share_of_cell_headings", m.go_share},
            {"go_share_of_cells_any_heading", m.any_go_share},
            {"limiting_factor_share_of_cell_headings", shares}};
}

} // namespace ecoterra::mobility
