#include "ecoterra/mobility/stand.hpp"

#include "ecoterra/csv.hpp"
#include "ecoterra/error.hpp"
#include "ecoterra/mobility/map.hpp"
#include "ecoterra/mobility/override.hpp"
#include "ecoterra/random.hpp"
#include "ecoterra/units.hpp"
#include "stats.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <numbers>

namespace ecoterra::mobility {

namespace {

using detail::mean;
using detail::quantile;
using nlohmann::json;
/// Random lines: draws per line before the length is declared not to fit.
constexpr int kMaxDraws = 10000;
/// Stems thicker than this are refused (a line end's clearance looks this far), m.
constexpr double kMaxObstacleDiameter_m = 10.0;

} // namespace

std::vector<StandStem> read_stem_csv(const std::filesystem::path& path) {
    CsvReader csv(path, "stem list");
    const int cx = csv.column("x_m"), cy = csv.column("y_m"), ccm = csv.column("dbh_cm"),
              cm = csv.column("dbh_m"), ch = csv.column("height_m"), cl = csv.column("life_form"),
              csd = csv.column("stem_diameter_cm");
    if (cl >= 0 && csd < 0)
        throw InputError(path.string() + ": a life_form column needs a stem_diameter_cm column "
                                         "(a shrub's or object's diameter at the ground)");
    if (cx < 0 || cy < 0 || (ccm < 0 && cm < 0))
        throw InputError(path.string() +
                         ": the header must name x_m, y_m and dbh_cm (or dbh_m), "
                         "got '" +
                         csv.header_line() + "'");
    std::vector<StandStem> out;
    while (csv.next()) {
        StandStem s;
        s.x_m = csv.number(cx, "x_m");
        s.y_m = csv.number(cy, "y_m");
        s.dbh_m =
            ccm >= 0 ? csv.number(ccm, "dbh_cm", true) / kCmPerM : csv.number(cm, "dbh_m", true);
        s.height_m =
            ch >= 0 ? csv.number(ch, "height_m", true) : std::numeric_limits<double>::quiet_NaN();
        if (cl >= 0) {
            const std::string form = csv.text(cl);
            if (form == "shrub")
                s.kind = StemKind::shrub;
            else if (form == "object")
                s.kind = StemKind::object;
            else if (form != "tree")
                throw InputError(csv.where() + ": life_form = '" + form +
                                 "' is not tree, shrub or object");
            if (s.kind != StemKind::tree) {
                s.base_diameter_m = csv.number(csd, "stem_diameter_cm", true) / kCmPerM;
                s.dbh_m = 0;
            }
        }
        out.push_back(s);
    }
    return out;
}

void StandDeadWood::add(int piece, bool standing, Point base, Point end, double dbh_m,
                        double height_m, double end_height_m) {
    if (piece == 1) // a stump: a step as high as it is (a log of no length)
        logs.push_back({base, base, height_m, height_m, dbh_m});
    else if (standing) // a snag as tall as it stands (its top lost, or snapped)
        snags.push_back({base.x_m, base.y_m, dbh_m, height_m, StemKind::snag});
    else // a log; a root plate (piece 4) a wall as wide as it is high
        logs.push_back({base, end, height_m, end_height_m, piece == 4 ? height_m : dbh_m});
    if (piece != 4 || standing) return;
    // The plate's diameter is its height on edge; it lies from the base to `end`, its thickness
    // windward; the pit is the disc beyond it.
    const double t = std::hypot(end.x_m - base.x_m, end.y_m - base.y_m), r = 0.5 * height_m;
    if (!(t > 0) || !(r > 0)) return;
    const double ux = (end.x_m - base.x_m) / t, uy = (end.y_m - base.y_m) / t;
    pits.push_back({base.x_m + (t + r) * ux, base.y_m + (t + r) * uy, r, 0.5 * t});
}

RasterD pit_depths(const GridSpec& g, const std::vector<Pit>& pits, double ox, double oy) {
    RasterD depth(g, 0.0);
    for (const auto& p : pits)
        cells_within(g, p.x_m - ox, p.y_m - oy, p.radius_m,
                     [&](int i, int j) { depth(i, j) = std::max(depth(i, j), p.depth_m); });
    return depth;
}

void carve_pits(RasterD& dem, const std::vector<Pit>& pits) {
    if (pits.empty()) return;
    const RasterD d = pit_depths(dem.grid(), pits);
    for (std::int64_t k = 0; k < dem.size(); ++k) dem.data()[k] -= d.data()[k];
}

StandDeadWood read_deadwood_csv(const std::filesystem::path& path) {
    CsvReader csv(path, "dead-wood list");
    const char* names[] = {"standing", "x_m",           "y_m",      "end_x_m",  "end_y_m",
                           "dbh_m",    "tree_height_m", "length_m", "height_m", "end_height_m"};
    std::array<int, 10> c{};
    for (std::size_t k = 0; k < c.size(); ++k) {
        c[k] = csv.column(names[k]);
        if (c[k] < 0)
            throw InputError(path.string() + ": the header must name " + names[k] +
                             " (the CSV of `ecoterra export deadwood`), got '" + csv.header_line() +
                             "'");
    }
    const int cpiece = csv.column("piece"); // optional: 1 a stump
    StandDeadWood out;
    while (csv.next()) {
        const double standing = csv.number(c[0], names[0], true);
        if (standing != 0 && standing != 1)
            throw InputError(csv.where() + ": standing = " + format_number(standing) +
                             " is not 0 (a log) or 1 (a snag)");
        const double x = csv.number(c[1], names[1]), y = csv.number(c[2], names[2]);
        const double dbh = csv.number(c[5], names[5], true);
        csv.number(c[6], names[6], true); // tree_height_m: checked; a snag stands height_m
        const double length = csv.number(c[7], names[7], true);
        const double h0 = csv.number(c[8], names[8], true), h1 = csv.number(c[9], names[9], true);
        const double piece = cpiece >= 0 ? csv.number(cpiece, "piece", true) : 0;
        if (piece != 0 && piece != 1 && piece != 2 && piece != 3 && piece != 4)
            throw InputError(csv.where() + ": piece = " + format_number(piece) +
                             " is not 0 (a stem), 1 (a stump), 2 (a top), 3 (a snapped stem) or 4 "
                             "(a root plate)");
        if (piece == 1 || standing == 1) { // a stump or a snag: at its base
            out.add(static_cast<int>(piece), standing == 1, {x, y}, {x, y}, dbh, h0, h1);
            continue;
        }
        const Point b{csv.number(c[3], names[3]), csv.number(c[4], names[4])};
        const double span = std::hypot(b.x_m - x, b.y_m - y);
        if (std::abs(span - length) > 1e-3 * std::max(1.0, length))
            throw InputError(csv.where() + ": length_m = " + format_number(length) +
                             " but the ends are " + format_number(span) + " m apart");
        out.add(static_cast<int>(piece), false, {x, y}, b, dbh, h0, h1);
    }
    return out;
}

namespace {

/// The stems as the vehicle meets them (a tree's or shrub's diameter at the push height, an
/// object's footprint); counts the trees, shrubs and objects and the basal area into `m`.
std::vector<Stem> stems_at_push_height(const Vehicle& v, const std::vector<StandStem>& stems,
                                       const GridSpec& g, StandMobility& m) {
    std::vector<Stem> pushable;
    double basal_m2 = 0;
    std::int64_t inside = 0;
    for (const auto& s : stems) {
        if (g.contains_point(s.x_m, s.y_m)) ++inside;
        if (s.kind == StemKind::snag) ++m.snags;
        if (s.kind == StemKind::tree && s.dbh_m > 0) {
            ++m.trees;
            basal_m2 += std::numbers::pi * s.dbh_m * s.dbh_m / 4;
        }
        if (std::max(s.dbh_m, s.base_diameter_m) > kMaxObstacleDiameter_m)
            throw InputError(
                "a stem at (" + format_number(s.x_m) + ", " + format_number(s.y_m) +
                ") has a diameter of " + format_number(std::max(s.dbh_m, s.base_diameter_m)) +
                " m (more than " + format_number(kMaxObstacleDiameter_m) + " m: cm given as m?)");
        if (s.kind == StemKind::object) {
            ++m.objects;
            if (s.base_diameter_m > 0) pushable.push_back({s.x_m, s.y_m, s.base_diameter_m, true});
            continue;
        }
        double d = 0;
        if (s.kind == StemKind::shrub) {
            ++m.shrubs;
            // A shrub's stem tapers from its diameter at the ground to 0 at its top.
            d = std::isnan(s.height_m) ? s.base_diameter_m
                                       : diameter_at_height_from_base_m(
                                             s.base_diameter_m, s.height_m, v.push_height_m);
        } else {
            d = std::isnan(s.height_m) ? s.dbh_m
                                       : diameter_at_height_m(s.dbh_m, s.height_m, v.push_height_m);
        }
        if (d > 0) pushable.push_back({s.x_m, s.y_m, d});
    }
    if (!stems.empty() && inside == 0)
        throw InputError("none of the " + std::to_string(stems.size()) +
                         " stems lies on the terrain [" + format_number(g.origin_x_m) + ", " +
                         format_number(g.origin_x_m + g.width_m()) + "] x [" +
                         format_number(g.origin_y_m) + ", " +
                         format_number(g.origin_y_m + g.height_m()) + "] m");
    m.basal_area_m2_per_ha = basal_m2 / m.area_ha;
    return pushable;
}

/// True when no log's part above the step limit lies within half the vehicle's width of p.
bool clear_of_high_logs(const Vehicle& v, const LogIndex& logs, Point p) {
    const double limit = step_limit_m(v);
    const double reach = 0.5 * (v.width_m + logs.max_diameter_m());
    bool ok = true;
    logs.for_each_in_box(
        p.x_m - reach, p.y_m - reach, p.x_m + reach, p.y_m + reach, [&](std::int64_t k) {
            const Log& l = logs.logs()[static_cast<std::size_t>(k)];
            if (std::max(l.height_a_m, l.height_b_m) <= limit) return;
            // The whole log, conservatively (its high part is within it).
            if (point_segment_distance(p, l.a, l.b) <= 0.5 * (v.width_m + l.diameter_m)) ok = false;
        });
    return ok;
}

/// The lines, drawn from the seed; random lines are drawn again while an end is not clear of the
/// stems the vehicle cannot override (a vehicle stands there).
void draw_lines(const Vehicle& v, const StemIndex& index, const LogIndex& logs,
                const std::array<double, 4>& bounds, const StandLinesOptions& opt,
                StandMobility& m) {
    auto clear = [&](Point p) {
        bool ok = clear_of_high_logs(v, logs, p);
        const double reach = 0.5 * v.width_m + 0.5 * kMaxObstacleDiameter_m;
        index.for_each_in_box(
            p.x_m - reach, p.y_m - reach, p.x_m + reach, p.y_m + reach, [&](std::int64_t k) {
                const Stem& s = index.stems()[static_cast<std::size_t>(k)];
                if (s.diameter_m >= m.critical_diameter_m &&
                    std::hypot(s.x_m - p.x_m, s.y_m - p.y_m) <= 0.5 * (s.diameter_m + v.width_m))
                    ok = false;
            });
        return ok;
    };
    const double w = bounds[2] - bounds[0], h = bounds[3] - bounds[1];
    m.lines.resize(static_cast<std::size_t>(opt.lines));
    if (opt.layout == LineLayout::transects) {
        if (opt.length_m > w)
            throw InputError("--length " + format_number(opt.length_m) +
                             " m is longer than the terrain is wide (" + format_number(w) + " m)");
        for (int k = 0; k < opt.lines; ++k) {
            const double y = bounds[1] + (k + 0.5) * h / opt.lines;
            const double x = bounds[0] + 0.5 * (w - opt.length_m);
            m.lines[static_cast<std::size_t>(k)].a = {x, y};
            m.lines[static_cast<std::size_t>(k)].b = {x + opt.length_m, y};
        }
        return;
    }
    Rng rng(opt.seed, "mobility.lines");
    for (auto& l : m.lines) {
        for (int draws = 0;; ++draws) {
            if (draws == kMaxDraws)
                throw InputError("lines of " + format_number(opt.length_m) +
                                 " m with both ends clear of stems do not fit in the terrain (" +
                                 format_number(w) + " x " + format_number(h) +
                                 " m inside a cell of the edge)");
            const double x = bounds[0] + rng.uniform() * w, y = bounds[1] + rng.uniform() * h;
            const double t = 2 * std::numbers::pi * rng.uniform();
            const Point b{x + opt.length_m * std::cos(t), y + opt.length_m * std::sin(t)};
            if (b.x_m >= bounds[0] && b.x_m <= bounds[2] && b.y_m >= bounds[1] &&
                b.y_m <= bounds[3] && clear({x, y}) && clear(b)) {
                l.a = {x, y};
                l.b = b;
                break;
            }
        }
    }
}

/// Each line driven (in parallel; each line's result depends on its line only).
void drive_lines(const Vehicle& v, const StemIndex& index, const LogIndex& logs, const RasterD& dem,
                 const SmgOptions& smg, StandMobility& m) {
    std::exception_ptr failure;
    const int n = static_cast<int>(m.lines.size());
#pragma omp parallel for schedule(dynamic)
    for (int k = 0; k < n; ++k) {
        try {
            auto& l = m.lines[static_cast<std::size_t>(k)];
            l.result = drive_line(v, index, logs, &dem, l.a, l.b, smg);
        } catch (...) {
#pragma omp critical
            if (!failure) failure = std::current_exception();
        }
    }
    if (failure) std::rethrow_exception(failure);
}

/// The figures over the lines: SMG statistics, NOGO share, override and detour shares.
void summarise_lines(StandMobility& m) {
    std::vector<double> smg_all, smg_go;
    double driven = 0, straight = 0, pushed = 0, crossed = 0, avoided_logs = 0;
    for (const auto& l : m.lines) {
        smg_all.push_back(l.result.smg_m_per_s);
        avoided_logs += static_cast<double>(l.result.logs_avoided);
        if (l.result.nogo) continue;
        crossed += static_cast<double>(l.result.logs_crossed);
        smg_go.push_back(l.result.smg_m_per_s);
        driven += l.result.path_m;
        straight += l.result.straight_m;
        pushed += l.result.override_m;
    }
    m.smg_mean_m_per_s = mean(smg_all);
    m.smg_mean_go_m_per_s = mean(smg_go);
    m.smg_median_m_per_s = quantile(smg_all, 0.5);
    m.smg_p10_m_per_s = quantile(smg_all, 0.1);
    m.smg_p90_m_per_s = quantile(smg_all, 0.9);
    m.nogo_fraction =
        1.0 - static_cast<double>(smg_go.size()) / static_cast<double>(m.lines.size());
    m.override_fraction = driven > 0 ? pushed / driven : 0.0;
    m.detour_fraction = driven > 0 ? (driven - straight) / driven : 0.0;
    m.log_crossings_per_100m = driven > 0 ? 100 * crossed / driven : 0.0;
    m.logs_avoided_per_line = avoided_logs / static_cast<double>(m.lines.size());
}

} // namespace

const std::vector<std::pair<std::string, StemEffects>>& stem_effects_names() {
    static const std::vector<std::pair<std::string, StemEffects>> n{
        {"both", StemEffects::both},
        {"override_only", StemEffects::override_only},
        {"avoidance_only", StemEffects::avoidance_only}};
    return n;
}

StandMobility analyse_stand(const Vehicle& v, const std::vector<StandStem>& stems,
                            const RasterD& dem, const StandLinesOptions& opt,
                            const std::vector<Log>& logs) {
    if (opt.lines < 1) throw InputError("--lines must be >= 1, got " + std::to_string(opt.lines));
    if (!(opt.length_m > 0))
        throw InputError("--length must be > 0 m, got " + format_number(opt.length_m));
    const GridSpec& g = dem.grid();
    const double c = g.cell_size_m; // lines keep a cell from the edge (bilinear elevations)
    const std::array<double, 4> bounds{g.origin_x_m + c, g.origin_y_m + c,
                                       g.origin_x_m + g.width_m() - c,
                                       g.origin_y_m + g.height_m() - c};
    StandMobility m;
    m.area_ha = g.width_m() * g.height_m() / kM2PerHa;
    m.critical_diameter_m = critical_diameter_m(v.weight_n(), v.push_height_m);
    std::vector<Stem> pushable = stems_at_push_height(v, stems, g, m);
    if (opt.effects != StemEffects::both)
        std::erase_if(pushable, [&](const Stem& s) {
            const bool avoided = s.rigid || s.diameter_m >= m.critical_diameter_m;
            return avoided == (opt.effects == StemEffects::override_only);
        });
    const StemIndex index(pushable, std::max(v.width_m, 1.0));
    m.stems = std::move(pushable);
    const LogIndex log_index(logs, std::max(v.width_m, 2.0));
    m.logs = static_cast<std::int64_t>(logs.size());
    m.log_list = logs;
    m.step_limit_m = step_limit_m(v);
    draw_lines(v, index, log_index, bounds, opt, m);
    SmgOptions smg = opt.smg;
    smg.bounds_m = bounds;
    drive_lines(v, index, log_index, dem, smg, m);
    summarise_lines(m);
    return m;
}

json to_json(const StandMobility& m, const Vehicle& v) {
    json lines = json::array();
    for (const auto& l : m.lines) {
        const auto& r = l.result;
        json j = {{"x0_m", l.a.x_m},
                  {"y0_m", l.a.y_m},
                  {"x1_m", l.b.x_m},
                  {"y1_m", l.b.y_m},
                  {"straight_m", r.straight_m},
                  {"nogo", r.nogo},
                  {"smg_m_per_s", r.smg_m_per_s},
                  {"path_m", r.nogo ? json() : json(r.path_m)},
                  {"time_s", r.nogo ? json() : json(r.time_s)},
                  {"override_m", r.override_m},
                  {"stems_overridden", r.overridden},
                  {"stems_avoided", r.avoided},
                  {"logs_crossed", r.logs_crossed},
                  {"logs_avoided", r.logs_avoided}};
        if (r.nogo) j["nogo_reason"] = r.nogo_reason;
        lines.push_back(std::move(j));
    }
    return {{"vehicle", to_json(v)}, {"lines", std::move(lines)}};
}

namespace {
/// The stand's stems at the vehicle's push height, indexed (the counts are not needed).
StemIndex push_height_index(const Vehicle& v, const std::vector<StandStem>& stems,
                            const RasterD& dem) {
    StandMobility counts;
    counts.area_ha = dem.grid().width_m() * dem.grid().height_m() / kM2PerHa;
    return StemIndex(stems_at_push_height(v, stems, dem.grid(), counts), std::max(v.width_m, 1.0));
}
} // namespace

MapPlan::MapPlan(const Vehicle& v, const RasterD& dem, const std::vector<StandStem>& stems,
                 const std::vector<Log>& logs, const MapOptions& opt)
    : MapPlan(v, dem, push_height_index(v, stems, dem), LogIndex(logs, std::max(v.width_m, 2.0)),
              opt) {}

MobilityMap mobility_map(const Vehicle& v, const RasterD& dem, const std::vector<StandStem>& stems,
                         const std::vector<Log>& logs, const GroundMaps& ground,
                         const MapOptions& opt) {
    return MapPlan(v, dem, stems, logs, opt).map(ground);
}

} // namespace ecoterra::mobility
