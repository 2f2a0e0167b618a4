#include "ecoterra/mobility/map.hpp"

#include "ecoterra/error.hpp"
#include "ecoterra/mobility/override.hpp"

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

/// The median of `v` (which it reorders); NaN for none.
double median(std::vector<double>& v) {
    if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
    const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
    std::nth_element(v.begin(), mid, v.end());
    if (v.size() % 2 == 1) return *mid;
    return 0.5 * (*mid + *std::max_element(v.begin(), mid));
}

/// One heading's result in one cell.
struct Crossing {
    double speed = 0;
    Limit limit = Limit::none;
};

/// The map's work: the constants of the vehicle and the per-cell steps.
class MapBuilder {
public:
    MapBuilder(const Vehicle& v, const RasterD& dem, const StemIndex& stems, const LogIndex& logs,
               const GroundMaps& ground, const MapOptions& opt);
    MobilityMap build();

private:
    /// The ground of map cell (i, j): the median of the terrain cells it covers.
    GroundCell ground_of(int i, int j) const;
    /// Every heading of map cell (i, j).
    void cell(int i, int j, MobilityMap& out, std::vector<std::int64_t>& near_stems,
              std::vector<std::int64_t>& near_logs, std::vector<double>& force) const;
    /// A crossing's constants: the cell's centre, the heading, the resistance and traction of
    /// its slope and ground, the speed they allow, and the override segments.
    struct Approach {
        Point c;
        double ux, uy, base, mu, v_soil;
        int nseg;
        double seg_len;
    };
    /// One lane (lateral offset o): its speed (0: closed), and without the logs' slowing.
    struct Lane {
        double v = 0, v_vegetation = 0;
        bool blocked_by_vegetation = false;
    };
    Lane lane(const Approach& ap, double o, const std::vector<std::int64_t>& near_stems,
              const std::vector<std::int64_t>& near_logs, std::vector<double>& force) const;
    /// Crossing the cell centred at `c` along (ux, uy) on ground `g`.
    Crossing cross(Point c, double ux, double uy, const GroundEffect& g,
                   const std::vector<std::int64_t>& near_stems,
                   const std::vector<std::int64_t>& near_logs, std::vector<double>& force) const;
    /// The grade along (ux, uy) and the side slope across the track at `c` (NaN off the DEM).
    std::pair<double, double> slopes(Point c, double ux, double uy) const;
    double z_or(Point p, double fallback) const {
        const double z = m_dem.sample_bilinear(p.x_m, p.y_m);
        return std::isnan(z) ? fallback : z;
    }
    bool avoided(const Stem& s) const { return s.rigid || s.diameter_m >= m_d_crit; }

    const Vehicle& m_v;
    const RasterD& m_dem;
    const StemIndex& m_stems;
    const LogIndex& m_logs;
    const GroundMaps& m_ground;
    VehicleGround m_vg;
    int m_k = 1; ///< terrain cells per map cell side
    int m_headings = 8;
    GridSpec m_grid;
    double m_c = 1, m_w = 1, m_d_crit = 0, m_step = 0, m_top = 0;
    std::vector<double> m_offsets;                 ///< lateral offsets of the lanes
    std::vector<std::pair<double, double>> m_dirs; ///< the headings' unit vectors (east, north)
    double m_max_grade = 0, m_max_side = 0;        ///< tangents of the climb and side-slope limits
};

MapBuilder::MapBuilder(const Vehicle& v, const RasterD& dem, const StemIndex& stems,
                       const LogIndex& logs, const GroundMaps& ground, const MapOptions& opt)
    : m_v(v), m_dem(dem), m_stems(stems), m_logs(logs), m_ground(ground), m_vg(v),
      m_headings(opt.headings), m_w(v.width_m),
      m_d_crit(critical_diameter_m(v.weight_n(), v.push_height_m)), m_step(step_limit_m(v)) {
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
        m_k = static_cast<int>(std::lround(ratio));
        if (std::abs(ratio - m_k) > kCellTolerance * ratio)
            throw InputError("mobility map: cell = " + format_number(opt.cell_m) +
                             " m is not a whole multiple of the terrain's cell of " +
                             format_number(g.cell_size_m) + " m");
    }
    if (g.nx / m_k < 1 || g.ny / m_k < 1)
        throw InputError("mobility map: cell = " + format_number(opt.cell_m) +
                         " m is larger than the terrain");
    m_grid = GridSpec{g.nx / m_k, g.ny / m_k, g.cell_size_m * m_k, g.origin_x_m, g.origin_y_m};
    m_c = m_grid.cell_size_m;
    const int lanes = std::max(1, static_cast<int>(std::ceil(m_c / (kLaneStepOfWidth * m_w))));
    for (int k = 0; k <= lanes; ++k)
        m_offsets.push_back(lanes == 0 ? 0.0 : -0.5 * m_c + m_c * k / lanes);
    m_top = steady_speed_m_per_s(v, rolling_resistance_n(v, 0.0));
    for (int h = 0; h < m_headings; ++h) {
        const double th = 2 * std::numbers::pi * h / m_headings;
        m_dirs.emplace_back(std::sin(th), std::cos(th));
    }
    m_max_grade = std::tan(v.max_climb_deg * std::numbers::pi / 180);
    m_max_side = std::tan(v.max_side_slope_deg * std::numbers::pi / 180);
}

GroundCell MapBuilder::ground_of(int i, int j) const {
    const GridSpec& g = m_dem.grid();
    if (m_k == 1) return m_ground.at(g.x_of(i), g.y_of(j));
    std::vector<double> rci, water;
    int fine = 0;
    for (int jj = j * m_k; jj < (j + 1) * m_k; ++jj)
        for (int ii = i * m_k; ii < (i + 1) * m_k; ++ii) {
            const GroundCell c = m_ground.at(g.x_of(ii), g.y_of(jj));
            if (!std::isnan(c.rci_kpa)) rci.push_back(c.rci_kpa);
            water.push_back(c.water_depth_m);
            fine += c.fine_grained ? 1 : 0;
        }
    GroundCell c;
    c.rci_kpa = median(rci);
    c.water_depth_m = median(water);
    c.fine_grained = 2 * fine >= m_k * m_k;
    return c;
}

std::pair<double, double> MapBuilder::slopes(Point c, double ux, double uy) const {
    const double zc = m_dem.sample_bilinear(c.x_m, c.y_m);
    if (std::isnan(zc)) return {std::nan(""), std::nan("")};
    const double half = 0.5 * std::max(m_c, m_w);
    const double zf = m_dem.sample_bilinear(c.x_m + half * ux, c.y_m + half * uy);
    const double zb = m_dem.sample_bilinear(c.x_m - half * ux, c.y_m - half * uy);
    double grade = 0;
    if (!std::isnan(zf) && !std::isnan(zb))
        grade = (zf - zb) / (2 * half);
    else if (!std::isnan(zf))
        grade = (zf - zc) / half;
    else if (!std::isnan(zb))
        grade = (zc - zb) / half;
    const double t = 0.5 * m_v.track_m;
    const double zl = z_or({c.x_m - t * uy, c.y_m + t * ux}, zc);
    const double zr = z_or({c.x_m + t * uy, c.y_m - t * ux}, zc);
    return {grade, std::abs(zl - zr) / m_v.track_m};
}

MapBuilder::Lane MapBuilder::lane(const Approach& ap, double o,
                                  const std::vector<std::int64_t>& near_stems,
                                  const std::vector<std::int64_t>& near_logs,
                                  std::vector<double>& force) const {
    const Vehicle& v = m_v;
    const auto [c, ux, uy, base, mu, v_soil, nseg, seg_len] = ap;
    Lane out;
    force.assign(static_cast<std::size_t>(nseg), 0.0);
    for (const std::int64_t k : near_stems) {
        const Stem& s = m_stems.stems()[static_cast<std::size_t>(k)];
        // The stem in the lane's frame: along from the cell's centre, across from the lane.
        const double dx = s.x_m - c.x_m, dy = s.y_m - c.y_m;
        const double along = dx * ux + dy * uy, lat = -dx * uy + dy * ux - o;
        if (avoided(s)) {
            // Closer to the lane's centre line (a segment of the cell's length) than (d + w)/2.
            const double beyond = std::max(0.0, std::abs(along) - 0.5 * m_c);
            const double reach = 0.5 * (s.diameter_m + m_w);
            if (beyond * beyond + lat * lat >= reach * reach) continue;
            out.blocked_by_vegetation = !s.rigid;
            return out;
        }
        if (std::abs(lat) > 0.5 * m_w) continue;
        const double t = along + 0.5 * m_c;
        for (int q = 0; q < nseg; ++q) {
            const double mid = (q + 0.5) * m_c / nseg;
            if (t >= mid - 0.5 * seg_len && t < mid + 0.5 * seg_len)
                force[static_cast<std::size_t>(q)] +=
                    override_force_n(s.diameter_m, v.push_height_m);
        }
    }
    double time = 0;
    for (const double f : force) {
        const double sp = f > 0 ? std::min(v_soil, steady_speed_m_per_s(v, base + f, mu)) : v_soil;
        if (!(sp > 0)) {
            out.blocked_by_vegetation = true; // a cluster too heavy to push
            return out;
        }
        time += m_c / nseg / sp;
    }
    double top = -1;
    const Point a{c.x_m - 0.5 * m_c * ux - o * uy, c.y_m - 0.5 * m_c * uy + o * ux};
    for (const std::int64_t k : near_logs) {
        const Log& l = m_logs.logs()[static_cast<std::size_t>(k)];
        double lo = 0, hi = 1;
        if (!log_in_footprint(l, a, m_c, ux, uy, 0.5 * m_w, lo, hi)) continue;
        const auto [u0, u1] = log_high_part(l, m_step);
        if (u0 <= u1 && lo <= u1 && hi >= u0) return out; // a log too high to climb
        const double dh = l.height_b_m - l.height_a_m;
        top = std::max({top, l.height_a_m + lo * dh, l.height_a_m + hi * dh});
    }
    out.v_vegetation = out.v = m_c / time;
    if (top >= 0) { // the slow crossing lasts until the rear axle is over the log
        const double cap = step_crossing_speed_m_per_s(v, top);
        const double slow = std::min(m_c, v.wheelbase_m + seg_len);
        out.v = m_c / (slow / std::min(cap, out.v) + (m_c - slow) / out.v);
    }
    return out;
}

Crossing MapBuilder::cross(Point c, double ux, double uy, const GroundEffect& g,
                           const std::vector<std::int64_t>& near_stems,
                           const std::vector<std::int64_t>& near_logs,
                           std::vector<double>& force) const {
    const Vehicle& v = m_v;
    const auto [grade, side] = slopes(c, ux, uy);
    if (std::isnan(grade)) return {0, Limit::nodata};
    if (grade > m_max_grade || side > m_max_side) return {0, Limit::slope};
    if (!g.go()) return {0, g.nogo};
    const double firm = rolling_resistance_n(v, grade) + grade_resistance_n(v, grade);
    const double v_slope = std::min(m_top, steady_speed_m_per_s(v, firm));
    const double base = resistance_n(v, grade, g);
    const double v_soil = std::min(v_slope, steady_speed_m_per_s(v, base, g.traction_coefficient));
    if (!(v_soil > 0)) return {0, v_slope > 0 ? Limit::soil : Limit::slope};
    // Segments of one vehicle width along the cell (one width-long segment centred on a shorter
    // cell).
    const int nseg = std::max(1, static_cast<int>(std::ceil(m_c / m_w - 1e-9)));
    const Approach ap{
        c, ux, uy, base, g.traction_coefficient, v_soil, nseg, std::max(m_c / nseg, m_w)};
    Lane best;
    bool veg_blocked = false;
    for (const double o : m_offsets) {
        const Lane l = lane(ap, o, near_stems, near_logs, force);
        veg_blocked = veg_blocked || l.blocked_by_vegetation;
        if (l.v > best.v) best = l;
    }
    if (!(best.v > 0)) return {0, veg_blocked ? Limit::vegetation : Limit::obstacle};
    // The limiting factor: the one that costs the most speed, if it costs more than 10 %.
    const std::array<std::pair<double, Limit>, 4> drops{
        {{m_top - v_slope, Limit::slope},
         {v_slope - v_soil, Limit::soil},
         {v_soil - best.v_vegetation, Limit::vegetation},
         {best.v_vegetation - best.v, Limit::obstacle}}};
    const auto worst = *std::max_element(drops.begin(), drops.end(),
                                         [](auto x, auto y) { return x.first < y.first; });
    return {best.v, worst.first > kLimitShare * m_top ? worst.second : Limit::none};
}

void MapBuilder::cell(int i, int j, MobilityMap& out, std::vector<std::int64_t>& near_stems,
                      std::vector<std::int64_t>& near_logs, std::vector<double>& force) const {
    const Point c{m_grid.x_of(i), m_grid.y_of(j)};
    const GroundCell gc = ground_of(i, j);
    out.rci_kpa(i, j) = gc.rci_kpa;
    out.water_depth_m(i, j) = gc.water_depth_m;
    GroundEffect g;
    if (m_ground.empty())
        g.traction_coefficient = m_v.traction_coefficient;
    else
        g = m_vg.effect(gc);
    // Everything within reach of a lane through the cell, in any heading.
    const double reach = 0.5 * std::sqrt(2.0) * std::max(m_c, m_w) + 0.5 * m_w;
    const double rs = reach + 0.5 * m_stems.max_diameter_m();
    near_stems.clear();
    m_stems.for_each_in_box(c.x_m - rs, c.y_m - rs, c.x_m + rs, c.y_m + rs,
                            [&](std::int64_t k) { near_stems.push_back(k); });
    near_logs.clear();
    m_logs.for_each_in_box(c.x_m - reach, c.y_m - reach, c.x_m + reach, c.y_m + reach,
                           [&](std::int64_t k) { near_logs.push_back(k); });
    std::array<int, kLimitKinds> count{};
    double sum = 0;
    int go = 0;
    for (int h = 0; h < m_headings; ++h) {
        const auto [ux, uy] = m_dirs[static_cast<std::size_t>(h)];
        const Crossing x = cross(c, ux, uy, g, near_stems, near_logs, force);
        out.speed_m_per_s[static_cast<std::size_t>(h)](i, j) = x.speed;
        out.limit[static_cast<std::size_t>(h)](i, j) = static_cast<std::uint8_t>(x.limit);
        sum += x.speed;
        go += x.speed > 0 ? 1 : 0;
        if (x.limit != Limit::nodata) ++count[static_cast<std::size_t>(x.limit)];
    }
    out.speed_mean_m_per_s(i, j) = sum / m_headings;
    out.go_fraction(i, j) = static_cast<double>(go) / m_headings;
    const auto most = std::max_element(count.begin(), count.end());
    out.limiting(i, j) = *most == 0 ? static_cast<std::uint8_t>(Limit::nodata)
                                    : static_cast<std::uint8_t>(most - count.begin());
}

MobilityMap MapBuilder::build() {
    MobilityMap m;
    m.grid = m_grid;
    for (int h = 0; h < m_headings; ++h) {
        m.headings_deg.push_back(360.0 * h / m_headings);
        m.speed_m_per_s.emplace_back(m.grid, 0.0);
        m.limit.emplace_back(m.grid, static_cast<std::uint8_t>(Limit::nodata));
    }
    m.speed_mean_m_per_s = RasterD(m.grid, 0.0);
    m.go_fraction = RasterD(m.grid, 0.0);
    m.limiting = RasterU8(m.grid, static_cast<std::uint8_t>(Limit::nodata));
    m.rci_kpa = RasterD(m.grid, std::numeric_limits<double>::quiet_NaN());
    m.water_depth_m = RasterD(m.grid, 0.0);
    m.top_speed_m_per_s = m_top;
    // Rows are independent: any thread count gives the same map.
#pragma omp parallel
    {
        std::vector<std::int64_t> near_stems, near_logs;
        std::vector<double> force;
#pragma omp for schedule(dynamic, 4)
        for (int j = 0; j < m.grid.ny; ++j)
            for (int i = 0; i < m.grid.nx; ++i) cell(i, j, m, near_stems, near_logs, force);
    }
    const double cells = static_cast<double>(m.grid.nx) * m.grid.ny;
    std::array<double, kLimitKinds> count{};
    double speed = 0, go = 0, any = 0, headings = 0;
    for (int j = 0; j < m.grid.ny; ++j)
        for (int i = 0; i < m.grid.nx; ++i) {
            speed += m.speed_mean_m_per_s(i, j);
            go += m.go_fraction(i, j) * m_headings;
            any += m.go_fraction(i, j) > 0 ? 1 : 0;
            for (const auto& l : m.limit) {
                if (l(i, j) == static_cast<std::uint8_t>(Limit::nodata)) continue;
                count[l(i, j)] += 1;
                headings += 1;
            }
        }
    const std::string& crs = m.crs_wkt = m_dem.crs_wkt();
    for (auto& r : m.speed_m_per_s) r.set_crs_wkt(crs);
    for (auto& r : m.limit) r.set_crs_wkt(crs);
    for (RasterD* r : {&m.speed_mean_m_per_s, &m.go_fraction, &m.rci_kpa, &m.water_depth_m})
        r->set_crs_wkt(crs);
    m.limiting.set_crs_wkt(crs);
    m.mean_speed_m_per_s = speed / cells;
    m.go_share = go / (cells * m_headings);
    m.any_go_share = any / cells;
    for (std::size_t k = 0; k < count.size(); ++k)
        m.limit_share[k] = headings > 0 ? count[k] / headings : 0.0;
    return m;
}

} // namespace

MobilityMap mobility_map(const Vehicle& v, const RasterD& dem, const StemIndex& stems,
                         const LogIndex& logs, const GroundMaps& ground, const MapOptions& opt) {
    return MapBuilder(v, dem, stems, logs, ground, opt).build();
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
    for (std::size_t c = 0; c < n && m_days > 0; ++c) {
        for (int d = 0; d < m_days; ++d)
            v[static_cast<std::size_t>(d)] = m_speed[static_cast<std::size_t>(d) * n + c];
        std::sort(v.begin(), v.end());
        // Linear between order statistics (the "type 7" quantile of R and numpy).
        const double h = q * (m_days - 1);
        const auto lo = static_cast<std::size_t>(std::floor(h));
        const std::size_t hi = std::min(lo + 1, v.size() - 1);
        r(static_cast<int>(c % static_cast<std::size_t>(m_grid.nx)),
          static_cast<int>(c / static_cast<std::size_t>(m_grid.nx))) =
            v[lo] + (h - static_cast<double>(lo)) * (v[hi] - v[lo]);
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
