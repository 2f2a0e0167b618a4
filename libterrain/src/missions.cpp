#include "ecoterra/terrain/missions.hpp"

#include "ecoterra/error.hpp"
#include "ecoterra/random.hpp"
#include "ecoterra/terrain/roughness.hpp"

#include <cmath>
#include <iomanip>
#include <numbers>
#include <sstream>

namespace ecoterra::terrain {

namespace {
constexpr const char* kClassNames[3] = {"low", "semi", "high"};
/// Path sampling step, in cells.
constexpr double kPathStepCells = 0.5;
} // namespace

void MissionOptions::validate() const {
    if (count < 1) throw InputError("missions: --count must be >= 1, got " + std::to_string(count));
    if (!(length_m > 0) || !std::isfinite(length_m))
        throw InputError("missions: --length must be > 0 m");
    if (!(border_m >= 0) || !std::isfinite(border_m))
        throw InputError("missions: --border must be >= 0 m");
    if (max_attempts_per_mission < 1) throw InputError("missions: attempts must be >= 1");
}

namespace {

/// Low-roughness cells inside the border: where missions start.
std::vector<std::int64_t> mission_starts(const RasterU8& closed, const MissionOptions& opt) {
    const GridSpec& g = closed.grid();
    const double x0 = g.origin_x_m + opt.border_m, x1 = g.origin_x_m + g.width_m() - opt.border_m;
    const double y0 = g.origin_y_m + opt.border_m, y1 = g.origin_y_m + g.height_m() - opt.border_m;
    std::vector<std::int64_t> starts;
    for (int j = 0; j < g.ny; ++j)
        for (int i = 0; i < g.nx; ++i) {
            const double x = g.x_of(i), y = g.y_of(j);
            if (closed(i, j) == static_cast<std::uint8_t>(RoughnessClass::low) && x >= x0 &&
                x <= x1 && y >= y0 && y <= y1)
                starts.push_back(static_cast<std::int64_t>(j) * g.nx + i);
        }
    if (starts.empty() && !opt.allow_fewer)
        throw InputError("missions: no low-roughness cell lies inside the " +
                         format_number(opt.border_m) + " m border");
    if (opt.length_m > std::hypot(x1 - x0, y1 - y0))
        throw InputError("missions: a " + format_number(opt.length_m) +
                         " m mission does not fit in this " + format_number(g.width_m()) + " x " +
                         format_number(g.height_m()) + " m terrain less its " +
                         format_number(opt.border_m) + " m border");
    return starts;
}

/// The classes a mission's straight line crosses (sampled every kPathStepCells cells); false
/// when it crosses no-data (a DEM's hole or outer no-data: not a place to drive).
bool classes_along(const RasterU8& classes, const MissionOptions& opt, Mission& m) {
    const double sx = m.start_x_m, sy = m.start_y_m, gx = m.goal_x_m, gy = m.goal_y_m;
    const int steps = std::max(
        1, static_cast<int>(std::ceil(opt.length_m / (kPathStepCells * classes.cell_size()))));
    std::array<int, 3> n{0, 0, 0};
    for (int k = 0; k <= steps; ++k) {
        const double t = static_cast<double>(k) / steps;
        const auto c = classes.cell_at(sx + t * (gx - sx), sy + t * (gy - sy));
        if (c[0] < 0) continue;
        const std::uint8_t v = classes(c[0], c[1]);
        if (v >= 3) return false;
        ++n[v];
    }
    const int tot = n[0] + n[1] + n[2];
    for (int q = 0; q < 3; ++q) {
        m.class_fraction[q] = tot ? static_cast<double>(n[q]) / tot : 0.0;
        if (n[q] == 0) continue;
        if (!m.classes_crossed.empty()) m.classes_crossed.push_back('|');
        m.classes_crossed.append(kClassNames[q]);
    }
    return true;
}

} // namespace

std::vector<Mission> plan_missions(const RasterU8& closed, const RasterU8& classes,
                                   const MissionOptions& opt) {
    opt.validate();
    if (!(closed.grid() == classes.grid()))
        throw InputError("missions: the closed and raw class maps differ in grid");
    const GridSpec& g = closed.grid();
    const double x0 = g.origin_x_m + opt.border_m, x1 = g.origin_x_m + g.width_m() - opt.border_m;
    const double y0 = g.origin_y_m + opt.border_m, y1 = g.origin_y_m + g.height_m() - opt.border_m;
    const std::vector<std::int64_t> starts = mission_starts(closed, opt);
    Rng rng(opt.seed, "terrain.missions");
    std::vector<Mission> out;
    if (starts.empty()) return out; // allow_fewer: no low cell to start from
    const std::int64_t max_attempts =
        static_cast<std::int64_t>(opt.max_attempts_per_mission) * opt.count;
    std::int64_t attempts = 0;
    while (static_cast<int>(out.size()) < opt.count) {
        if (++attempts > max_attempts) {
            if (opt.allow_fewer) break;
            throw InputError("missions: found only " + std::to_string(out.size()) + " of " +
                             std::to_string(opt.count) + " missions in " +
                             std::to_string(max_attempts) +
                             " attempts; the terrain has too little low/semi area for this "
                             "length and border");
        }
        const std::int64_t s = starts[rng.below(starts.size())];
        const int si = static_cast<int>(s % g.nx), sj = static_cast<int>(s / g.nx);
        const double heading = rng.uniform(0.0, 360.0);
        const double th = heading * std::numbers::pi / 180.0;
        const double sx = g.x_of(si), sy = g.y_of(sj);
        const double gx = sx + opt.length_m * std::cos(th), gy = sy + opt.length_m * std::sin(th);
        if (!(gx >= x0 && gx <= x1 && gy >= y0 && gy <= y1)) continue;
        const auto gc = closed.cell_at(gx, gy);
        if (gc[0] < 0) continue;
        const std::uint8_t goal_class = closed(gc[0], gc[1]);
        if (goal_class != static_cast<std::uint8_t>(RoughnessClass::low) &&
            goal_class != static_cast<std::uint8_t>(RoughnessClass::semi))
            continue;
        Mission m;
        m.id = static_cast<int>(out.size()) + 1;
        m.start_x_m = sx;
        m.start_y_m = sy;
        m.goal_x_m = gx;
        m.goal_y_m = gy;
        m.heading_deg = heading;
        m.length_m = opt.length_m;
        if (classes_along(classes, opt, m)) out.push_back(m);
    }
    return out;
}

std::string missions_csv(const std::vector<Mission>& missions) {
    std::ostringstream s;
    s << "id,start_x_m,start_y_m,goal_x_m,goal_y_m,heading_deg,length_m,"
         "fraction_low,fraction_semi,fraction_high,classes_crossed\n";
    s << std::setprecision(10);
    for (const auto& m : missions)
        s << m.id << ',' << m.start_x_m << ',' << m.start_y_m << ',' << m.goal_x_m << ','
          << m.goal_y_m << ',' << m.heading_deg << ',' << m.length_m << ',' << m.class_fraction[0]
          << ',' << m.class_fraction[1] << ',' << m.class_fraction[2] << ',' << m.classes_crossed
          << '\n';
    return s.str();
}

} // namespace ecoterra::terrain
