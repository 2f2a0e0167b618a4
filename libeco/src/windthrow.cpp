// Windthrow: the storm series, ForestGALES' critical wind speeds and the trees a storm fells
// (windthrow.hpp).
#include "ecoterra/eco/windthrow.hpp"

#include "ecoterra/eco/deadwood.hpp"
#include "ecoterra/error.hpp"
#include "ecoterra/json_util.hpp"
#include "ecoterra/units.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace ecoterra::eco {

using nlohmann::json;

namespace {
constexpr std::uint32_t kStateVersion = 1;
constexpr double kMaxWind = 100; ///< m/s: above any measured surface wind
// fgr_constants (ForestGALES): the annual-maximum polynomial and dispersion, Raupach's constants.
constexpr double kUc1 = -0.5903, kUc2 = 4.4345, kUc3 = -11.8633, kUc4 = 13.569, kUa = 5;
constexpr double kCd1 = 7.5, kCs = 0.003, kCr = 0.3, kVonKarman = 0.4, kCw = 2;
constexpr double kEdgeHeights = 9;    ///< tree_heights_inside_forest: past it no edge effect
constexpr double kMaxGapHeights = 10; ///< a gap's effect saturates at 10 heights
constexpr double kDragFloor = 10;     ///< m/s: the drag regression's lower limit
constexpr double kElevateTop = 1.05;  ///< fgr elevates from 1.05 x the top height
constexpr double kAnemometerM = 10;
constexpr double kThinningYears = 5; ///< a thinning's effect on the moment fades in 5 years
/// A gap is upwind ground whose canopy is under this share of the stand's mean height.
constexpr double kGapHeightFraction = 0.5;
constexpr double kTopStemsPerHa = 100; ///< top height: the mean of the 100 tallest per ha
constexpr double kFaoU2Numerator = 4.87, kFaoA = 67.8, kFaoB = 5.42; // FAO-56 Eq 47

double from_deg_to_azimuth(double from_deg) {
    // Blowing from `from` (clockwise from north) toward from + 180; counterclockwise from east.
    return deadwood::wrap_azimuth((90.0 - (from_deg + 180.0)) * std::numbers::pi / 180.0);
}

bool exposed(const Population& pop, const std::vector<Species>& species, std::size_t k,
             double min_height_m) {
    return pop.alive[k] && pop.dbh_m[k] > 0 && pop.height_m[k] >= min_height_m &&
           species[pop.species[k]].life_form == LifeForm::tree;
}
} // namespace

const ParamCatalog<WindthrowOptions>& windthrow_catalog() {
    using W = WindthrowOptions;
    static const ParamCatalog<W> c(
        "vegetation.windthrow",
        {flag<W>("enabled", &W::enabled,
                 "storms fell trees whose critical wind they exceed (docs/ecosystem.md s13)"),
         flag<W>("random_storms", &W::random_storms,
                 "a storm every year from the wind climate; false: only the storms listed"),
         number<W>("weibull_shape", &W::weibull_shape, "1", 1, 4,
                   "Weibull shape k of the hourly mean wind (ForestGALES' default 1.85)"),
         optional_number<W>("weibull_scale_m_per_s", &W::weibull_scale_m_per_s, "m/s", 0.1, 30,
                            "Weibull scale of the hourly mean wind 10 m above the zero-plane "
                            "displacement; none: from climate.wind_mean_m_per_s (FAO-56 Eq 47 "
                            "to 10 m, over Gamma(1 + 1/k))"),
         optional_number<W>("storm_from_deg", &W::storm_from_deg, "deg", 0, 360,
                            "where storms blow from, clockwise from north; none: each drawn"),
         number<W>("min_height_m", &W::min_height_m, "m", 0, 100,
                   "trees at least this tall are exposed (iLand: 4 m)"),
         flag<W>("open_surroundings", &W::open_surroundings,
                 "the area is an island of forest in the open (its upwind border is an edge); "
                 "false: the stand continues past the border"),
         flag<W>("severe_storms", &W::severe_storms,
                 "severe convective storms (downbursts, derechos) strike as a Poisson process "
                 "besides the wind climate's gales (with random_storms)"),
         number<W>("severe_return_period_yr", &W::severe_return_period_yr, "yr", 1, 1e7,
                   "mean years between severe storms at a site (Canham & Loucks 1984: "
                   "catastrophic windthrow every 1210 years in presettlement Wisconsin)"),
         number<W>("severe_gust_min_m_per_s", &W::severe_gust_min_m_per_s, "m/s", 10, kMaxWind,
                   "a severe storm's 3-s gust is at least this (large forest damage needs about "
                   "40 m/s, Gregow et al. 2017)"),
         number<W>("severe_gust_max_m_per_s", &W::severe_gust_max_m_per_s, "m/s", 10, kMaxWind,
                   "and at most this (severe windstorms average 30-50 m/s, Xi & Peet)"),
         number<W>("gust_factor", &W::gust_factor, "1", 1, 3,
                   "3-s gust over the hourly mean wind (ASCE 7-95 commentary, Durst: 1.53)")});
    return c;
}

WindthrowOptions read_windthrow(const json& j, int years) {
    const std::string where = "vegetation.windthrow";
    if (!j.is_object()) throw InputError(where + " must be an object, got " + j.dump());
    WindthrowOptions w = windthrow_catalog().read(j, WindthrowOptions{}, {"storms"});
    if (w.severe_gust_max_m_per_s < w.severe_gust_min_m_per_s)
        throw InputError(where + ".severe_gust_max_m_per_s = " +
                         format_number(w.severe_gust_max_m_per_s) + " is below " + where +
                         ".severe_gust_min_m_per_s = " + format_number(w.severe_gust_min_m_per_s));
    if (!j.contains("storms")) return w;
    const json& st = j.at("storms");
    if (!st.is_array()) throw InputError(where + ".storms must be an array, got " + st.dump());
    for (std::size_t k = 0; k < st.size(); ++k) {
        const std::string at = where + ".storms[" + std::to_string(k) + "]";
        const json& o = st[k];
        if (!o.is_object()) throw InputError(at + " must be an object, got " + o.dump());
        require_known_keys(o, {"year", "wind_m_per_s", "from_deg"}, at);
        auto number = [&](const char* key, double lo, double hi) {
            if (!o.contains(key)) throw InputError(at + "." + key + ": missing");
            return get_number(o, key, 0, at, lo, hi);
        };
        StormSpec s;
        const double y = number("year", 1, years);
        if (y != std::floor(y))
            throw InputError(at + ".year = " + format_number(y) + " is not a whole year");
        s.year = static_cast<int>(y);
        for (const auto& o2 : w.storms)
            if (o2.year == s.year)
                throw InputError(at + ".year = " + std::to_string(s.year) +
                                 ": another storm is already listed for that year");
        s.wind_m_per_s = number("wind_m_per_s", 0, kMaxWind);
        if (o.contains("from_deg")) s.from_deg = number("from_deg", 0, 360);
        w.storms.push_back(s);
    }
    return w;
}

json to_json(const WindthrowOptions& w) {
    json j = windthrow_catalog().to_json(w);
    json st = json::array();
    for (const auto& s : w.storms) {
        json o = {{"year", s.year}, {"wind_m_per_s", s.wind_m_per_s}};
        if (s.from_deg) o["from_deg"] = *s.from_deg;
        st.push_back(std::move(o));
    }
    j["storms"] = std::move(st);
    return j;
}

namespace wind {

double weibull_scale_from_u2(double u2, double k) {
    const double u10 = u2 * std::log(kFaoA * kAnemometerM - kFaoB) / kFaoU2Numerator;
    return u10 / std::tgamma(1 + 1 / k);
}

namespace {
/// Mode U and dispersion of the annual maximum of u^2 (fgr annual_exceedance_prob).
std::pair<double, double> gumbel_u2(double a, double k) {
    const double uc = ((kUc1 * k + kUc2) * k + kUc3) * k + kUc4;
    const double mode = (uc * a) * (uc * a);
    return {mode, mode / kUa};
}
} // namespace

double annual_exceedance(double u, double a, double k) {
    const auto [mode, disp] = gumbel_u2(a, k);
    return 1 - std::exp(-std::exp(-(u * u - mode) / disp));
}

double annual_maximum(double p, double a, double k) {
    const auto [mode, disp] = gumbel_u2(a, k);
    p = std::clamp(p, 1e-300, 1 - 1e-16);
    return std::sqrt(std::max(0.0, mode - disp * std::log(-std::log(p))));
}

SevereDraw severe_storm(const WindthrowOptions& o, std::uint64_t seed, int year) {
    Rng r(seed, "eco.wind.severe", static_cast<std::uint64_t>(year));
    const double p = r.uniform(), s = r.uniform(), d = r.uniform();
    SevereDraw out;
    out.from_deg = 360 * d;
    if (o.severe_storms && p < 1 / o.severe_return_period_yr) {
        const double gust =
            o.severe_gust_min_m_per_s + (o.severe_gust_max_m_per_s - o.severe_gust_min_m_per_s) * s;
        out.wind_m_per_s = gust / o.gust_factor;
    }
    return out;
}

double edge_gap_factor(double spacing, double h, double dist_edge, double gap) {
    const double s = std::clamp(spacing / h, 0.075, 0.45);
    const double a = 2.7193 * s - 0.061, b = -1.273 * s + 0.9701, c = 1.1127 * s + 0.0311;
    const double inside = std::pow(c, kEdgeHeights);
    const double x = std::min(dist_edge, kEdgeHeights * h) / h;
    const double gap_factor = std::pow(std::min(gap / h, kMaxGapHeights) / kMaxGapHeights, 0.3467);
    return (a + b * inside + b * (std::pow(c, x) - inside) * gap_factor) / (a + b * inside);
}

double turning_moment_coefficient(double dbh, double h, double c) {
    const double x = dbh * dbh * h;
    return (124.252 - 17.285 * c) * x;
}

double hegyi_from_light(double light) {
    return std::clamp(3.733 - 6.467 * light, 0.5, 3.41);
}

void displacement_and_roughness(const StandAero& a, double uh, double& d, double& z0) {
    const double u = std::max(uh, kDragFloor);
    const double breadth = a.crown_width_m * a.drag_c * std::pow(u, -a.drag_n) / 2;
    const double lambda = 2 * breadth * a.crown_depth_m / (a.spacing_m * a.spacing_m);
    const double r = std::sqrt(kCd1 * std::max(lambda, 1e-9));
    const double h = a.mean_height_m;
    d = h * (1 - (1 - std::exp(-r)) / r);
    const double gamma = 1 / std::sqrt(kCs + kCr * std::min(lambda, 0.6) / 2);
    z0 = (h - d) * std::exp(-kVonKarman * gamma + std::log(kCw) - 1 + 1 / kCw);
}

double u10_from_uh(const StandAero& a, double uh) {
    double d = 0, z0 = 0;
    displacement_and_roughness(a, uh, d, z0);
    const double top = std::max(kElevateTop * a.top_height_m, d + 2 * z0);
    // z0 stays under 0.14 h; only a canopy over ~70 m would put 10 m inside the roughness layer.
    return uh * std::log(std::max(kAnemometerM / z0, 1.01)) / std::log((top - d) / z0);
}

double crown_depth_m(const Species& s, double h) {
    return std::clamp(s.wind_crown_depth_intercept_m + s.wind_crown_depth_per_height * h, 0.1 * h,
                      h);
}

double breaking_moment_nm(const Species& s, double dbh, double h) {
    const double action = std::max(h - crown_depth_m(s, h) / 2, 2 * kBreastHeightM);
    const double dbase = dbh * std::cbrt(action / (action - kBreastHeightM));
    return s.wind_mor_pa * s.wind_knot_factor * std::numbers::pi * dbase * dbase * dbase / 32;
}

double overturning_moment_nm(const Species& s, double dbh, double h) {
    // The stem's volume from its dry mass (allometry's form factor) at its own height.
    const double volume = allometry::stem_mass_kg(s, dbh) / s.wood_density_kg_per_m3 * h /
                          std::max(allometry::height_m(s, dbh), 1e-9);
    return s.wind_creg_n_m_per_kg * s.wind_green_density_kg_per_m3 * volume;
}

TreeWind tree_wind(const Species& s, double dbh, double h, double light, const StandAero& stand,
                   double dist_edge, double gap, double tmr) {
    TreeWind t;
    t.hegyi = hegyi_from_light(light);
    t.edge_gap_factor = edge_gap_factor(stand.spacing_m, stand.mean_height_m, dist_edge, gap);
    const double tmc = std::max(turning_moment_coefficient(dbh, h, t.hegyi), 1e-9);
    const double load = tmc * t.edge_gap_factor * tmr;
    const double uh_break = std::sqrt(breaking_moment_nm(s, dbh, h) / load);
    const double uh_over = std::sqrt(overturning_moment_nm(s, dbh, h) / load);
    t.breakage_m_per_s = u10_from_uh(stand, uh_break);
    t.overturning_m_per_s = u10_from_uh(stand, uh_over);
    return t;
}

} // namespace wind

double exposed_spacing_m(const Population& pop, const std::vector<Species>& species, double area_m2,
                         double min_height_m) {
    std::size_t n = 0;
    for (std::size_t k = 0; k < pop.size(); ++k) n += exposed(pop, species, k, min_height_m);
    return n ? std::sqrt(area_m2 / static_cast<double>(n)) : 0.0;
}

namespace {

wind::StandAero stand_aero(const Population& pop, const std::vector<Species>& species,
                           double area_m2, double min_h) {
    wind::StandAero a;
    std::vector<double> heights;
    double cw = 0, cd = 0, dc = 0, dn = 0;
    for (std::size_t k = 0; k < pop.size(); ++k) {
        if (!exposed(pop, species, k, min_h)) continue;
        const Species& s = species[pop.species[k]];
        const double h = pop.height_m[k];
        heights.push_back(h);
        cw += 2 * pop.crown_radius_m[k];
        cd += wind::crown_depth_m(s, h);
        dc += s.wind_drag_c;
        dn += s.wind_drag_n;
    }
    if (heights.empty()) return a;
    const double n = static_cast<double>(heights.size());
    double sum = 0;
    for (const double h : heights) sum += h;
    a.mean_height_m = sum / n;
    a.spacing_m = std::sqrt(area_m2 / n);
    a.crown_width_m = cw / n, a.crown_depth_m = cd / n, a.drag_c = dc / n, a.drag_n = dn / n;
    const std::size_t top = std::clamp<std::size_t>(
        static_cast<std::size_t>(std::lround(kTopStemsPerHa * area_m2 / kM2PerHa)), 1,
        heights.size());
    std::partial_sort(heights.begin(), heights.begin() + static_cast<std::ptrdiff_t>(top),
                      heights.end(), std::greater<>());
    double t = 0;
    for (std::size_t k = 0; k < top; ++k) t += heights[k];
    a.top_height_m = t / static_cast<double>(top);
    return a;
}

/// The canopy's height on a grid over the area: the tallest crown over each cell.
RasterD canopy_height(const Population& pop, const std::vector<Species>& species,
                      const GridSpec& area) {
    GridSpec g = area;
    const double cell = std::max(1.0, area.cell_size_m);
    g.cell_size_m = cell;
    g.nx = std::max(1, static_cast<int>(std::ceil(area.width_m() / cell)));
    g.ny = std::max(1, static_cast<int>(std::ceil(area.height_m() / cell)));
    RasterD top(g, 0.0);
    for (std::size_t k = 0; k < pop.size(); ++k) {
        if (!pop.alive[k] || species[pop.species[k]].life_form != LifeForm::tree) continue;
        const double r = std::max(pop.crown_radius_m[k], 0.5 * cell);
        const double x = pop.x_m[k] - g.origin_x_m, y = pop.y_m[k] - g.origin_y_m;
        const int i0 = static_cast<int>(std::floor((x - r) / cell));
        const int i1 = static_cast<int>(std::floor((x + r) / cell));
        const int j0 = static_cast<int>(std::floor((y - r) / cell));
        const int j1 = static_cast<int>(std::floor((y + r) / cell));
        for (int j = std::max(j0, 0); j <= std::min(j1, g.ny - 1); ++j)
            for (int i = std::max(i0, 0); i <= std::min(i1, g.nx - 1); ++i) {
                const double dx = (i + 0.5) * cell - x, dy = (j + 0.5) * cell - y;
                if (dx * dx + dy * dy <= r * r) top(i, j) = std::max(top(i, j), pop.height_m[k]);
            }
    }
    return top;
}

/// From (x, y), upwind (against `to_az`): the distance to the first gap and the gap's length,
/// both capped where their effect ends. Past the border the canopy wraps around (forest around)
/// or is open (an edge with an unbounded gap).
std::pair<double, double> upwind_edge(const RasterD& top, double x, double y, double to_az,
                                      double gap_below_m, double stand_h, bool open) {
    const GridSpec& g = top.grid();
    const double step = g.cell_size_m;
    const double ux = -std::cos(to_az) * step, uy = -std::sin(to_az) * step;
    const double max_edge = kEdgeHeights * stand_h, max_gap = kMaxGapHeights * stand_h;
    double dist = 0, gap = 0;
    bool in_gap = false;
    for (double s = step;; s += step) {
        double px = x + ux * s / step - g.origin_x_m, py = y + uy * s / step - g.origin_y_m;
        const bool outside = px < 0 || py < 0 || px >= g.width_m() || py >= g.height_m();
        if (outside && open) {
            if (!in_gap) dist = s;
            return {dist, max_gap};
        }
        px -= g.width_m() * std::floor(px / g.width_m());
        py -= g.height_m() * std::floor(py / g.height_m());
        const int i = std::min(static_cast<int>(px / step), g.nx - 1);
        const int j = std::min(static_cast<int>(py / step), g.ny - 1);
        const bool low = top(i, j) < gap_below_m;
        if (!in_gap) {
            if (low) {
                in_gap = true;
                dist = s;
            } else if (s >= max_edge) {
                return {max_edge, 0.0};
            }
        } else {
            if (!low) return {dist, gap};
            gap += step;
            if (gap >= max_gap) return {dist, max_gap};
        }
    }
}

} // namespace

Windthrow::Windthrow(const WindthrowOptions& options, std::uint64_t seed)
    : m_opt(options), m_seed(seed), m_rng(seed, "eco.wind") {}

void Windthrow::thinned(double spacing_before_m, int year) {
    if (!(spacing_before_m > 0)) return;
    m_spacing_before_m = spacing_before_m;
    m_thin_year = year;
}

std::vector<wind::TreeWind> Windthrow::critical_winds(const Population& pop,
                                                      const std::vector<Species>& species,
                                                      const GridSpec& area, double to_az,
                                                      int year) const {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    std::vector<wind::TreeWind> out(pop.size(), wind::TreeWind{nan, nan, nan, nan});
    const double area_m2 = area.width_m() * area.height_m();
    const wind::StandAero aero = stand_aero(pop, species, area_m2, m_opt.min_height_m);
    if (!(aero.mean_height_m > 0)) return out;
    // ForestGALES' simple turning-moment ratio for the five years after a thinning.
    double tmr = 1;
    const double since = year - m_thin_year;
    if (m_spacing_before_m > 0 && since >= 0 && since <= kThinningYears)
        tmr = 0.99 * aero.spacing_m / m_spacing_before_m * (1 - since / kThinningYears) +
              since / kThinningYears;
    const RasterD top = canopy_height(pop, species, area);
    const double gap_below = kGapHeightFraction * aero.mean_height_m;
    for (std::size_t k = 0; k < pop.size(); ++k) {
        if (!exposed(pop, species, k, m_opt.min_height_m)) continue;
        const auto [dist, gap] = upwind_edge(top, pop.x_m[k], pop.y_m[k], to_az, gap_below,
                                             aero.mean_height_m, m_opt.open_surroundings);
        out[k] = wind::tree_wind(species[pop.species[k]], pop.dbh_m[k], pop.height_m[k],
                                 1 - pop.shade_fraction[k], aero, dist, gap, tmr);
    }
    return out;
}

StormResult Windthrow::strike(const Population& pop, const std::vector<Species>& species,
                              const GridSpec& area, int year, std::vector<char>& dead,
                              char uprooted, char broken) {
    StormResult r;
    if (!m_opt.enabled) return r;
    // Two draws every year, used or not: the series is the stand's no matter what.
    const double p = m_rng.uniform(), q = m_rng.uniform();
    double from = m_opt.storm_from_deg ? *m_opt.storm_from_deg : 360 * q;
    if (m_opt.random_storms && m_opt.weibull_scale_m_per_s)
        r.wind_m_per_s = wind::annual_maximum(p, *m_opt.weibull_scale_m_per_s, m_opt.weibull_shape);
    if (m_opt.random_storms) {
        const wind::SevereDraw sv = wind::severe_storm(m_opt, m_seed, year);
        if (sv.wind_m_per_s > r.wind_m_per_s) {
            r.wind_m_per_s = sv.wind_m_per_s;
            r.severe = true;
            if (!m_opt.storm_from_deg) from = sv.from_deg;
        }
    }
    for (const auto& s : m_opt.storms)
        if (s.year == year) {
            r.wind_m_per_s = s.wind_m_per_s;
            r.severe = false;
            if (s.from_deg) from = *s.from_deg;
        }
    r.to_azimuth_rad = from_deg_to_azimuth(from);
    if (!(r.wind_m_per_s > 0)) return r;
    const std::vector<wind::TreeWind> cw =
        critical_winds(pop, species, area, r.to_azimuth_rad, year);
    const double per_ha = kM2PerHa / (area.width_m() * area.height_m());
    for (std::size_t k = 0; k < pop.size(); ++k) {
        if (dead[k] || std::isnan(cw[k].breakage_m_per_s)) continue;
        if (r.wind_m_per_s < cw[k].critical_m_per_s()) continue;
        const bool up = cw[k].uproots();
        dead[k] = up ? uprooted : broken;
        (up ? r.uprooted : r.broken) += 1;
        r.basal_area_m2_per_ha += std::numbers::pi / 4 * pop.dbh_m[k] * pop.dbh_m[k] * per_ha;
    }
    return r;
}

void Windthrow::save(ArchiveWriter& a) const {
    a.put(kStateVersion);
    a.put(m_rng.state());
    a.put(m_spacing_before_m);
    a.put(m_thin_year);
}

void Windthrow::load(ArchiveReader& a) {
    const auto v = a.get<std::uint32_t>();
    if (v != kStateVersion)
        throw CheckpointError("checkpoint section 'windthrow' has state version " +
                              std::to_string(v) + ", this ecoterra reads version " +
                              std::to_string(kStateVersion));
    m_rng.set_state(a.get<std::array<std::uint64_t, 4>>());
    m_spacing_before_m = a.get<double>();
    m_thin_year = a.get<int>();
}

} // namespace ecoterra::eco
