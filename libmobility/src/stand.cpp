#include "ecoterra/mobility/stand.hpp"

#include "ecoterra/csv.hpp"
#include "ecoterra/error.hpp"
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

/// The lines, drawn from the seed; random lines are drawn again while an end is not clear of the
/// stems the vehicle cannot override (a vehicle stands there).
void draw_lines(const Vehicle& v, const StemIndex& index, const std::array<double, 4>& bounds,
                const StandLinesOptions& opt, StandMobility& m) {
    auto clear = [&](Point p) {
        bool ok = true;
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
void drive_lines(const Vehicle& v, const StemIndex& index, const RasterD& dem,
                 const SmgOptions& smg, StandMobility& m) {
    std::exception_ptr failure;
    const int n = static_cast<int>(m.lines.size());
#pragma omp parallel for schedule(dynamic)
    for (int k = 0; k < n; ++k) {
        try {
            auto& l = m.lines[static_cast<std::size_t>(k)];
            l.result = drive_line(v, index, &dem, l.a, l.b, smg);
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
    double driven = 0, straight = 0, pushed = 0;
    for (const auto& l : m.lines) {
        smg_all.push_back(l.result.smg_m_per_s);
        if (l.result.nogo) continue;
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
}

} // namespace

StandMobility analyse_stand(const Vehicle& v, const std::vector<StandStem>& stems,
                            const RasterD& dem, const StandLinesOptions& opt) {
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
    const StemIndex index(pushable, std::max(v.width_m, 1.0));
    m.stems = std::move(pushable);
    draw_lines(v, index, bounds, opt, m);
    SmgOptions smg = opt.smg;
    smg.bounds_m = bounds;
    drive_lines(v, index, dem, smg, m);
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
                  {"stems_avoided", r.avoided}};
        if (r.nogo) j["nogo_reason"] = r.nogo_reason;
        lines.push_back(std::move(j));
    }
    return {{"vehicle", to_json(v)}, {"lines", std::move(lines)}};
}

} // namespace ecoterra::mobility
