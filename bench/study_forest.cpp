// Validation study of the ecosystem model (docs/validation.md s3), over many seeds:
//
//  A. The paper's central result (paper 002 s5.2, Fig 8): the 1 ha humid subtropical quickstart
//     grown to 11.5 m2/ha (50 ft2/acre), coupled against light-only competition. For each seed
//     (terrain and simulation seeds both vary) it prints the years taken, stems/ha, the share of
//     stems in small (< 10 cm), medium (10-25 cm) and large (>= 25 cm) classes and the
//     negative-exponential fit; then the mean 5 cm histogram of each mode and its fit. Modes:
//     coupled, light_only (crown radius as the overlap circle) and light_mavs (light-only with
//     MAVS's competitive radius).
//  B. Self-thinning (Reineke 1933): dense unmanaged stands, planted at --density stems/ha with
//     diameters up to 5 cm, grown for --years years. Over the years after the stem count of trees
//     >= 5 cm peaked and until Dq peaked (the even-aged phase), the least-squares slope of ln N
//     against ln Dq (trees >= 5 cm) is compared with Reineke's -1.605, over the whole phase and
//     over its late half.
//
//  C. Water and stand over a century (issue 27): the quickstart, coupled, --century years
//     (100), for each seed the water partition of the first decade (a young, sparse stand) and of
//     the last 20 years (mature): evapotranspiration / rain, transpiration / evapotranspiration,
//     interception / rain, soil evaporation / rain, and runoff + drainage / rain; then the basal
//     area at the end and the largest species' share of it. --paper002 runs it with paper 002's
//     soil water (evapotranspiration, drainage and interception as the paper prescribes) and its
//     growth and shading (vegetation.growth = paper002, vegetation.shading = blocking). A
//     second table gives the stand's dynamics from the same runs (struct Dynamics below:
//     composition by age, mortality of trees >= 5 cm, increments of the tallest and shortest
//     quarters and of the crown classes by light, dominant and suppressed; docs/validation.md
//     s2c).
//  D. Bare ground (issue 27: "bare ground in the humid climate evaporates at most half of the
//     year's rain"): data/scenes/hydro_quickstart.json with no vegetation (vegetation.density =
//     0) for 10 years, for each seed (weather seed s, terrain seed 100 + s) the soil evaporation's
//     share of the rain over the ten years and its lowest and highest year; then the mean (sd).
//     Only with --only-bare, or --bare beside the others.
//
// Usage: study_forest [--seeds N] [--years Y] [--density D] [--century Y] [--paper002]
//                     [--only-central | --only-thinning | --only-water | --only-bare] [--bare]
//                     [--scene FILE]
//                     [--set key=value ...]
// --scene runs another scene instead of the quickstart (e.g. data/scenes/southeastern_pine.json:
// its own ecosystem and soil, with the study's seeds); --set changes a key of the scene for every
// run (as `ecoterra run --set`).
#include "ecoterra/eco/ecosystem.hpp"
#include "ecoterra/eco/stand_metrics.hpp"
#include "ecoterra/hydro/scene.hpp"
#include "ecoterra/io/atomic_file.hpp"
#include "ecoterra/json_util.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>

using namespace ecoterra;
using nlohmann::json;

namespace {

constexpr double kTargetBa = 11.5; // m2/ha, the paper's 50 ft2/acre
constexpr double kThinningMinDbhM = 0.05;
constexpr double kInventoryMinDbhM = 0.127; // 5 in: FIA's growing-stock trees

struct Line {
    double slope = 0, intercept = 0, r2 = 0;
};

Line fit(const std::vector<double>& x, const std::vector<double>& y) {
    const double n = static_cast<double>(x.size());
    double sx = 0, sy = 0, sxx = 0, sxy = 0, syy = 0;
    for (std::size_t i = 0; i < x.size(); ++i) {
        sx += x[i], sy += y[i], sxx += x[i] * x[i], sxy += x[i] * y[i], syy += y[i] * y[i];
    }
    Line l;
    const double vx = sxx - sx * sx / n, vy = syy - sy * sy / n, cxy = sxy - sx * sy / n;
    l.slope = cxy / vx;
    l.intercept = (sy - l.slope * sx) / n;
    l.r2 = vy > 0 ? cxy * cxy / (vx * vy) : 0;
    return l;
}

struct Share {
    double small = 0, medium = 0, large = 0;
};

Share shares(const eco::StandMetrics& m) {
    Share s;
    for (std::size_t i = 0; i < m.histogram.size(); ++i) {
        const double lo = static_cast<double>(i) * m.class_width_cm;
        const auto c = static_cast<double>(m.histogram[i]);
        (lo < 10 ? s.small : lo < 25 ? s.medium : s.large) += c;
    }
    const double t = std::max(s.small + s.medium + s.large, 1.0);
    s.small /= t, s.medium /= t, s.large /= t;
    return s;
}

void central_result(const json& base, const std::filesystem::path& dir, int seeds) {
    std::printf("A. Grown to %.1f m2/ha: coupled against light-only, %d seeds\n\n", kTargetBa,
                seeds);
    std::printf("%-11s %4s %5s %8s %7s %7s %7s %7s %6s\n", "mode", "seed", "years", "stems/ha",
                "small", "medium", "large", "q/5cm", "R2");
    for (const char* mode : {"coupled", "light_only", "light_mavs"}) {
        std::vector<double> mean_hist;
        double mean_years = 0, mean_stems = 0;
        Share mean_share;
        int reverse_j = 0;
        for (int seed = 1; seed <= seeds; ++seed) {
            json q = base;
            const std::string name = mode;
            q["vegetation"]["competition"] = name == "coupled" ? "coupled" : "light_only";
            q["vegetation"]["light_only_radius"] = name == "light_mavs" ? "mavs" : "crown";
            q["simulation"]["seed"] = seed;
            q["terrain"]["generate"]["seed"] = 100 + seed;
            const auto sc = eco::load_eco_scene(q, dir);
            eco::Ecosystem e(sc);
            while (e.years_done() < 300 && e.stand().basal_area_m2_per_ha < kTargetBa) e.run_year();
            const auto m = e.stand();
            const Share s = shares(m);
            std::printf("%-11s %4d %5d %8.0f %6.0f%% %6.0f%% %6.0f%% %7.2f %6.2f\n", mode, seed,
                        e.years_done(), m.stems_per_ha, 100 * s.small, 100 * s.medium,
                        100 * s.large, m.q_per_class, m.r2);
            if (mean_hist.size() < m.histogram.size()) mean_hist.resize(m.histogram.size(), 0.0);
            for (std::size_t i = 0; i < m.histogram.size(); ++i)
                mean_hist[i] += static_cast<double>(m.histogram[i]) / seeds;
            mean_years += e.years_done() / static_cast<double>(seeds);
            mean_stems += m.stems_per_ha / seeds;
            mean_share.small += s.small / seeds;
            mean_share.medium += s.medium / seeds;
            mean_share.large += s.large / seeds;
            reverse_j += m.fit_valid && m.r2 >= 0.8 && m.q_per_class > 1.2;
        }
        std::vector<double> x, y;
        for (std::size_t i = 0; i < mean_hist.size(); ++i)
            if (mean_hist[i] > 0) {
                x.push_back((static_cast<double>(i) + 0.5) * 5.0);
                y.push_back(std::log(mean_hist[i]));
            }
        const Line l = fit(x, y);
        std::printf("%-10s mean: %.1f years, %.0f stems/ha, small %.0f%% medium %.0f%% large "
                    "%.0f%%; reverse-J (R2 >= 0.8, q > 1.2) in %d of %d seeds\n",
                    mode, mean_years, mean_stems, 100 * mean_share.small, 100 * mean_share.medium,
                    100 * mean_share.large, reverse_j, seeds);
        std::printf("%-10s mean histogram (stems/ha per 5 cm class):", mode);
        for (double v : mean_hist) std::printf(" %.1f", v);
        std::printf("\n%-10s fit of the mean histogram: q = %.2f per 5 cm, R2 = %.2f\n\n", mode,
                    std::exp(-5.0 * l.slope), l.r2);
    }
}

struct Thinning {
    std::size_t peak = 0, top = 0;
    double n_peak = 0, dq_peak = 0, n_top = 0, dq_top = 0;
    Line all, late;
};

// The thinning phase runs from the year the stem count peaked to the year Dq peaked: after that
// the first cohort's deaths at its maximum age let a new one in.
Thinning thinning_phase(const std::vector<double>& n, const std::vector<double>& dq) {
    Thinning t;
    for (std::size_t i = 0; i < n.size(); ++i)
        if (n[i] > n[t.peak]) t.peak = i;
    t.top = t.peak;
    for (std::size_t i = t.peak; i < dq.size(); ++i)
        if (dq[i] > dq[t.top]) t.top = i;
    std::vector<double> x, y;
    for (std::size_t i = t.peak; i <= t.top; ++i)
        if (n[i] > 0 && dq[i] > 0) {
            x.push_back(std::log(dq[i]));
            y.push_back(std::log(n[i]));
        }
    if (x.size() >= 3) t.all = fit(x, y);
    const auto half = static_cast<std::ptrdiff_t>(x.size() / 2);
    const std::vector<double> xl(x.begin() + half, x.end()), yl(y.begin() + half, y.end());
    if (xl.size() >= 3) t.late = fit(xl, yl);
    t.n_peak = n[t.peak], t.dq_peak = dq[t.peak], t.n_top = n[t.top], t.dq_top = dq[t.top];
    return t;
}

struct Mean {
    double sum = 0, sum2 = 0;
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    int n = 0;
    void add(double v) {
        sum += v, sum2 += v * v, ++n;
        lo = std::min(lo, v), hi = std::max(hi, v);
    }
    double mean() const { return sum / n; }
    double sd() const { return std::sqrt(std::max(sum2 / n - mean() * mean(), 0.0)); }
};

void self_thinning(const json& base, const std::filesystem::path& dir, int seeds, int years,
                   double density) {
    std::printf("B. Self-thinning: planted at %.0f stems/ha (dbh up to 5 cm), %d years\n"
                "   stand = all trees >= %.0f cm (with ingrowth); cohort = the planted trees that "
                "reached breast height\n\n",
                density, years, 100 * kThinningMinDbhM);
    std::printf("%4s %-7s %5s %8s %7s %5s %8s %7s %7s %6s %7s\n", "seed", "", "peak", "N peak",
                "Dq", "top", "N", "Dq", "slope", "R2", "late");
    Mean stand_all, stand_late, cohort_all, cohort_late;
    for (int seed = 1; seed <= seeds; ++seed) {
        json q = base;
        q["simulation"]["seed"] = seed;
        q["terrain"]["generate"]["seed"] = 100 + seed;
        q["vegetation"]["initial"] = {{"random", {{"stems_per_ha", density}, {"max_dbh_m", 0.05}}}};
        const auto sc = eco::load_eco_scene(q, dir);
        eco::Ecosystem e(sc);
        std::int64_t last_planted = 0;
        for (const std::int64_t id : e.plants().id) last_planted = std::max(last_planted, id);
        const double area_ha = e.plant_grid().width_m() * e.plant_grid().height_m() / 1e4;
        std::vector<double> n_stand, dq_stand, n_cohort, dq_cohort;
        for (int y = 0; y < years; ++y) {
            e.run_year();
            double ns = 0, ds = 0, nc = 0, dc = 0;
            const auto& pop = e.plants();
            for (std::size_t k = 0; k < pop.size(); ++k) {
                const double d = pop.dbh_m[k], d2 = d * d;
                if (d >= kThinningMinDbhM) ns += 1, ds += d2;
                if (pop.id[k] <= last_planted && d > 0) nc += 1, dc += d2;
            }
            n_stand.push_back(ns / area_ha);
            dq_stand.push_back(ns > 0 ? std::sqrt(ds / ns) : 0.0);
            n_cohort.push_back(nc / area_ha);
            dq_cohort.push_back(nc > 0 ? std::sqrt(dc / nc) : 0.0);
        }
        const Thinning ts = thinning_phase(n_stand, dq_stand);
        const Thinning tc = thinning_phase(n_cohort, dq_cohort);
        for (const auto& [name, t] : {std::pair{"stand", ts}, std::pair{"cohort", tc}})
            std::printf("%4d %-7s %5zu %8.0f %5.1fcm %5zu %8.0f %5.1fcm %7.3f %6.2f %7.3f\n", seed,
                        name, t.peak + 1, t.n_peak, 100 * t.dq_peak, t.top + 1, t.n_top,
                        100 * t.dq_top, t.all.slope, t.all.r2, t.late.slope);
        stand_all.add(ts.all.slope);
        stand_late.add(ts.late.slope);
        cohort_all.add(tc.all.slope);
        cohort_late.add(tc.late.slope);
    }
    std::printf("mean slope of ln N against ln Dq over %d seeds (Reineke: -1.605):\n", seeds);
    std::printf("  stand:  %.3f (sd %.3f), late half %.3f (sd %.3f)\n", stand_all.mean(),
                stand_all.sd(), stand_late.mean(), stand_late.sd());
    std::printf("  cohort: %.3f (sd %.3f), late half %.3f (sd %.3f)\n", cohort_all.mean(),
                cohort_all.sd(), cohort_late.mean(), cohort_late.sd());
}

/// The water partition of years [first, last] (1-based) from a run's yearly series, mm/yr.
struct Partition {
    double rain = 0, evaporation = 0, transpiration = 0, interception = 0, out = 0;
    double et() const { return evaporation + transpiration + interception; }
};

Partition partition(const Table& yearly, int first, int last) {
    Partition p;
    auto mean = [&](const char* column) {
        const auto& v = yearly.column(column);
        double sum = 0;
        for (int y = first; y <= last; ++y) sum += v[static_cast<std::size_t>(y - 1)];
        return sum / (last - first + 1);
    };
    p.rain = mean("rain_mm");
    p.evaporation = mean("evaporation_mm");
    p.transpiration = mean("transpiration_mm");
    p.interception = mean("interception_mm");
    p.out = mean("runoff_out_mm") + mean("drainage_out_mm") + mean("groundwater_out_mm");
    return p;
}

/// Each species' share of the basal area of the living trees (0 where there is none).
std::vector<double> basal_area_shares(const eco::Ecosystem& e) {
    const auto& pop = e.plants();
    const auto& species = e.scene().ecosystem.species;
    std::vector<double> dbh;
    std::vector<int> of;
    for (std::size_t k = 0; k < pop.size(); ++k)
        if (pop.alive[k] && species[pop.species[k]].life_form == eco::LifeForm::tree) {
            dbh.push_back(pop.dbh_m[k]);
            of.push_back(pop.species[k]);
        }
    const auto by = eco::stand_metrics_by_species(
        dbh, of, species.size(), e.plant_grid().width_m() * e.plant_grid().height_m());
    double total = 0;
    for (const auto& m : by) total += m.basal_area_m2_per_ha;
    std::vector<double> share;
    for (const auto& m : by) share.push_back(total > 0 ? m.basal_area_m2_per_ha / total : 0.0);
    return share;
}

/// Stand dynamics of one run (part C's second table): the species' shares of basal area at
/// fixed ages, the yearly mortality of trees >= 5 cm over the closed stand (the last 40 years) and
/// the diameter increment of dominant (tallest quarter) against suppressed (shortest quarter)
/// trees >= 5 cm over the last 10 years.
struct Dynamics {
    static constexpr std::array<int, 6> kAges{10, 25, 50, 100, 150, 200};
    std::vector<std::string> names;
    std::vector<std::vector<double>> share; // [age][species]
    int years = 0, mortality_from = 0, increment_from = 0;
    double at_risk = 0, deaths = 0;
    std::unordered_map<std::int64_t, std::array<double, 3>> start; // id -> (dbh, height, shade)
    std::array<double, 4> by_shade_mm{}, by_shade_n{};             // shade 0-.2-.5-.8-1
    std::unordered_set<std::int64_t> risk;
    double dominant_mm = 0, suppressed_mm = 0, all_mm = 0;
    double inventory_mm = 0; // trees >= 12.7 cm (5 in) at the start, FIA's growing-stock size

    Dynamics(const std::vector<eco::Species>& species, int y) : years(y) {
        for (const auto& s : species) names.push_back(s.name);
        mortality_from = std::max(1, years - 39);
        increment_from = std::max(1, years - 9);
    }
    static bool counted(const eco::Population& pop, std::size_t k,
                        const std::vector<eco::Species>& sp) {
        return pop.alive[k] && sp[pop.species[k]].life_form == eco::LifeForm::tree &&
               pop.dbh_m[k] >= kThinningMinDbhM;
    }
    void before_year(const eco::Ecosystem& e) {
        const int year = e.years_done() + 1;
        const auto& pop = e.plants();
        const auto& sp = e.scene().ecosystem.species;
        risk.clear();
        for (std::size_t k = 0; k < pop.size(); ++k) {
            if (!counted(pop, k, sp)) continue;
            if (year >= mortality_from) risk.insert(pop.id[k]);
            if (year == increment_from)
                start[pop.id[k]] = {pop.dbh_m[k], pop.height_m[k], pop.shade_fraction[k]};
        }
    }
    void after_year(const eco::Ecosystem& e) {
        const int year = e.years_done();
        const auto& pop = e.plants();
        std::unordered_set<std::int64_t> alive;
        for (std::size_t k = 0; k < pop.size(); ++k)
            if (pop.alive[k]) alive.insert(pop.id[k]);
        at_risk += static_cast<double>(risk.size());
        for (const auto id : risk) deaths += alive.count(id) ? 0 : 1;
        if (std::find(kAges.begin(), kAges.end(), year) != kAges.end())
            share.push_back(basal_area_shares(e));
        if (year == years) increments(pop);
    }
    void increments(const eco::Population& pop) {
        std::vector<std::pair<double, double>> h_inc; // (start height, mm/yr)
        const double span = years - increment_from + 1;
        double inv_sum = 0, inv_n = 0;
        for (std::size_t k = 0; k < pop.size(); ++k) {
            const auto it = start.find(pop.id[k]);
            if (!pop.alive[k] || it == start.end()) continue;
            const auto& [d0, h0, s0] = it->second;
            const double mm = 1000 * (pop.dbh_m[k] - d0) / span;
            h_inc.push_back({h0, mm});
            if (d0 >= kInventoryMinDbhM) inv_sum += mm, inv_n += 1;
            const int b = s0 < 0.2 ? 0 : s0 < 0.5 ? 1 : s0 < 0.8 ? 2 : 3;
            by_shade_mm[b] += mm;
            by_shade_n[b] += 1;
        }
        inventory_mm = inv_n > 0 ? inv_sum / inv_n : 0;
        std::sort(h_inc.begin(), h_inc.end());
        const std::size_t q = h_inc.size() / 4;
        if (q == 0) return;
        double lo = 0, hi = 0, all = 0;
        for (std::size_t i = 0; i < q; ++i) lo += h_inc[i].second;
        for (std::size_t i = h_inc.size() - q; i < h_inc.size(); ++i) hi += h_inc[i].second;
        for (const auto& v : h_inc) all += v.second;
        suppressed_mm = lo / q, dominant_mm = hi / q;
        all_mm = all / static_cast<double>(h_inc.size());
    }
    double mortality() const { return at_risk > 0 ? deaths / at_risk : 0; }
};

void print_dynamics(const std::vector<Dynamics>& runs, int years) {
    if (runs.empty()) return;
    const auto& names = runs[0].names;
    std::printf("   stand dynamics: share of basal area by species at each age; mortality of trees "
                ">= 5 cm per year over years %d-%d; diameter increment (mm/yr) of trees >= 5 cm "
                "over years %d-%d, tallest and shortest quarter\n\n",
                runs[0].mortality_from, years, runs[0].increment_from, years);
    std::printf("%4s %-5s", "seed", "age");
    for (const auto& n : names) std::printf(" %14.14s", n.c_str());
    std::printf(" | %9s %7s %7s %7s %6s\n", "mortality", "all", "top", "bottom", "ratio");
    std::vector<std::vector<Mean>> mean_share;
    Mean mort, all, dom, sup, ratio, inventory;
    Mean open, overtopped, crown_ratio; // crown classes by the light at mid-crown
    for (std::size_t r = 0; r < runs.size(); ++r) {
        const auto& d = runs[r];
        mean_share.resize(d.share.size(), std::vector<Mean>(names.size()));
        for (std::size_t a = 0; a < d.share.size(); ++a) {
            std::printf("%4zu %-5d", r + 1, Dynamics::kAges[a]);
            for (std::size_t s = 0; s < names.size(); ++s) {
                std::printf(" %13.0f%%", 100 * d.share[a][s]);
                mean_share[a][s].add(d.share[a][s]);
            }
            if (a + 1 == d.share.size()) {
                std::printf(" | %8.2f%% %7.2f %7.2f %7.2f %6.1f", 100 * d.mortality(), d.all_mm,
                            d.dominant_mm, d.suppressed_mm,
                            d.dominant_mm / std::max(d.suppressed_mm, 1e-3));
                for (int b = 0; b < 4; ++b)
                    std::printf(" s%d:%.0f/%.2f", b, d.by_shade_n[b],
                                d.by_shade_mm[b] / std::max(d.by_shade_n[b], 1.0));
            }
            std::printf("\n");
        }
        mort.add(d.mortality());
        all.add(d.all_mm);
        inventory.add(d.inventory_mm);
        dom.add(d.dominant_mm);
        sup.add(d.suppressed_mm);
        ratio.add(d.dominant_mm / std::max(d.suppressed_mm, 1e-3));
        if (d.by_shade_n[0] > 0 && d.by_shade_n[3] > 0) {
            open.add(d.by_shade_mm[0] / d.by_shade_n[0]);
            overtopped.add(d.by_shade_mm[3] / d.by_shade_n[3]);
            crown_ratio.add((d.by_shade_mm[0] / d.by_shade_n[0]) /
                            std::max(d.by_shade_mm[3] / d.by_shade_n[3], 1e-3));
        }
    }
    std::printf("mean share of basal area over %zu seeds (sd):\n", runs.size());
    for (std::size_t a = 0; a < mean_share.size(); ++a) {
        std::printf("  %3d yr:", Dynamics::kAges[a]);
        for (std::size_t s = 0; s < names.size(); ++s)
            std::printf(" %s %.0f%% (%.0f)", names[s].c_str(), 100 * mean_share[a][s].mean(),
                        100 * mean_share[a][s].sd());
        std::printf("\n");
    }
    std::printf(
        "mean mortality %.2f%%/yr (sd %.2f); diameter increment %.2f mm/yr, tallest quarter "
        "%.2f, shortest %.2f, ratio %.1f (sd %.1f)\n\n",
        100 * mort.mean(), 100 * mort.sd(), all.mean(), dom.mean(), sup.mean(), ratio.mean(),
        ratio.sd());
    std::printf("diameter increment of trees >= 12.7 cm (5 in, the inventories' size) at the "
                "start: %.2f mm/yr (sd %.2f, %.2f-%.2f)\n\n",
                inventory.mean(), inventory.sd(), inventory.lo, inventory.hi);
    // Crown classes as foresters define them, by the light a crown receives: open-grown or
    // dominant (shade fraction < 0.2 at the start of the period) against overtopped (>= 0.8).
    std::printf("crown classes by light (shade at the start, s0 < 0.2, s3 >= 0.8), over %d of %zu "
                "seeds with both: dominant %.2f mm/yr, suppressed %.2f, ratio %.2f (sd %.2f; "
                "%.2f-%.2f)\n\n",
                open.n, runs.size(), open.mean(), overtopped.mean(), crown_ratio.mean(),
                crown_ratio.sd(), crown_ratio.lo, crown_ratio.hi);
}

void water_and_stand(const json& base, const std::filesystem::path& dir, int seeds, int years,
                     bool paper) {
    std::printf("C. Water and stand over %d years (%s soil water), %d seeds\n", years,
                paper ? "paper 002's" : "the default", seeds);
    std::printf(
        "   per period: rain mm/yr, ET/rain, T/ET, interception/rain, soil evaporation/rain,"
        " runoff+drainage/rain\n\n");
    std::printf("%4s %-9s %6s %6s %6s %6s %6s %6s | %-9s %6s %6s %6s %6s %6s %6s | %6s %-12s\n",
                "seed", "years", "rain", "ET/P", "T/ET", "I/P", "E/P", "out/P", "years", "rain",
                "ET/P", "T/ET", "I/P", "E/P", "out/P", "BA", "largest");
    Mean et, t_et, ip, ba, top, stems, shrubs, cover;
    std::vector<Dynamics> dynamics;
    const int late0 = std::max(1, years - 19);
    for (int seed = 1; seed <= seeds; ++seed) {
        json q = base;
        q["simulation"]["seed"] = seed;
        q["terrain"]["generate"]["seed"] = 100 + seed;
        if (paper) {
            q["vegetation"]["growth"] = "paper002";
            q["vegetation"]["shading"] = "blocking";
            q["hydrology"]["evapotranspiration"] = "paper002";
            q["hydrology"]["drainage"] = "none";
            q["hydrology"]["interception"] = "none";
        }
        const auto sc = eco::load_eco_scene(q, dir);
        eco::Ecosystem e(sc);
        Dynamics dyn(sc.ecosystem.species, years);
        for (int y = 0; y < years; ++y) {
            dyn.before_year(e);
            e.run_year();
            dyn.after_year(e);
        }
        dynamics.push_back(dyn);
        const Partition a = partition(e.yearly(), 1, std::min(10, years));
        const Partition b = partition(e.yearly(), late0, years);
        const auto& species = sc.ecosystem.species;
        const auto shares = basal_area_shares(e);
        const auto best = static_cast<std::size_t>(std::max_element(shares.begin(), shares.end()) -
                                                   shares.begin());
        const double share = shares[best];
        const double stand_ba = e.stand().basal_area_m2_per_ha;
        char label[32];
        std::snprintf(label, sizeof label, "%d-%d", late0, years);
        std::printf("%4d %-9s %6.0f %6.2f %6.2f %6.2f %6.2f %6.2f | %-9s %6.0f %6.2f %6.2f %6.2f "
                    "%6.2f %6.2f | %6.1f %s %.0f%%\n",
                    seed, "1-10", a.rain, a.et() / a.rain, a.transpiration / a.et(),
                    a.interception / a.rain, a.evaporation / a.rain, a.out / a.rain, label, b.rain,
                    b.et() / b.rain, b.transpiration / b.et(), b.interception / b.rain,
                    b.evaporation / b.rain, b.out / b.rain, stand_ba, species[best].name.c_str(),
                    100 * share);
        et.add(b.et() / b.rain);
        t_et.add(b.transpiration / b.et());
        ip.add(b.interception / b.rain);
        ba.add(stand_ba);
        top.add(share);
        const eco::UndergrowthMetrics u = e.undergrowth();
        stems.add(e.stand().stems_per_ha);
        shrubs.add(u.shrubs_per_ha);
        cover.add(u.shrub_crown_cover_fraction);
    }
    std::printf(
        "mean over %d seeds, years %d-%d: ET/P %.3f (sd %.3f), T/ET %.3f (sd %.3f), I/P "
        "%.3f (sd %.3f); basal area at %d years %.1f m2/ha (sd %.1f); largest species %.0f%% "
        "of it (sd %.0f)\n\n",
        seeds, late0, years, et.mean(), et.sd(), t_et.mean(), t_et.sd(), ip.mean(), ip.sd(), years,
        ba.mean(), ba.sd(), 100 * top.mean(), 100 * top.sd());
    std::printf("at %d years: trees %.0f /ha (sd %.0f, %.0f-%.0f); shrubs %.0f /ha (sd %.0f, "
                "%.0f-%.0f), their crowns covering %.1f%% of the ground (sd %.1f, %.1f-%.1f)\n\n",
                years, stems.mean(), stems.sd(), stems.lo, stems.hi, shrubs.mean(), shrubs.sd(),
                shrubs.lo, shrubs.hi, 100 * cover.mean(), 100 * cover.sd(), 100 * cover.lo,
                100 * cover.hi);
    print_dynamics(dynamics, years);
}

void bare_ground(const json& base, const std::filesystem::path& dir, int seeds) {
    constexpr int kYears = 10;
    std::printf("D. Bare ground (vegetation.density = 0), %d years, %d seeds: soil evaporation / "
                "rain\n\n%4s %8s %8s %8s %8s\n",
                kYears, seeds, "seed", "rain", "E/P", "lowest", "highest");
    Mean share;
    for (int seed = 1; seed <= seeds; ++seed) {
        json q = base;
        q["vegetation"] = json{{"density", 0.0}};
        q["simulation"]["seed"] = seed;
        q["terrain"]["generate"]["seed"] = 100 + seed;
        const hydro::HydroScene sc = hydro::load_hydro_scene(q, dir);
        hydro::HydrologyModel model(sc.dem, sc.soil, sc.vegetation_density, sc.options, sc.climate);
        hydro::WeatherGenerator weather(sc.climate, sc.seed);
        Mean yearly;
        double rain = 0, evaporation = 0;
        for (int y = 0; y < kYears; ++y) {
            double p = 0, e = 0; // m3
            for (int d = 0; d < hydro::kDaysPerYear; ++d) {
                const hydro::DailyFluxes f = model.step(weather.next());
                p += f.rain;
                e += f.evaporation;
            }
            yearly.add(e / p);
            rain += p;
            evaporation += e;
        }
        const double area = sc.dem.grid().width_m() * sc.dem.grid().height_m();
        std::printf("%4d %8.0f %8.3f %8.3f %8.3f\n", seed, rain / area * 1000.0 / kYears,
                    evaporation / rain, yearly.lo, yearly.hi);
        share.add(evaporation / rain);
    }
    std::printf("mean over %d seeds: soil evaporation %.3f of the rain (sd %.3f, %.3f-%.3f)\n\n",
                seeds, share.mean(), share.sd(), share.lo, share.hi);
}

} // namespace

int main(int argc, char** argv) {
    int seeds = 10, years = 80, century = 100;
    double density = 4000;
    bool central = true, thinning = true, water = true, paper = false, bare = false;
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--only-bare") == 0) central = thinning = water = false;
        if (std::strcmp(argv[i], "--only-bare") == 0 || std::strcmp(argv[i], "--bare") == 0)
            bare = true;
        if (std::strcmp(argv[i], "--only-central") == 0) thinning = water = false;
        if (std::strcmp(argv[i], "--only-thinning") == 0) central = water = false;
        if (std::strcmp(argv[i], "--only-water") == 0) central = thinning = false;
        if (std::strcmp(argv[i], "--paper002") == 0) paper = true;
    }
    for (int i = 1; i + 1 < argc; ++i) {
        if (std::strcmp(argv[i], "--seeds") == 0)
            seeds = std::atoi(argv[++i]);
        else if (std::strcmp(argv[i], "--years") == 0)
            years = std::atoi(argv[++i]);
        else if (std::strcmp(argv[i], "--density") == 0)
            density = std::atof(argv[++i]);
        else if (std::strcmp(argv[i], "--century") == 0)
            century = std::atoi(argv[++i]);
    }
    if (seeds < 1 || years < 3 || density <= 0 || century < 10) {
        std::fprintf(stderr,
                     "study_forest: --seeds >= 1, --years >= 3, --density > 0, --century >= 10\n");
        return 2;
    }
    const std::filesystem::path data = ECOTERRA_DATA_DIR;
    std::filesystem::path scene = data / "scenes/quickstart.json";
    for (int i = 1; i + 1 < argc; ++i)
        if (std::strcmp(argv[i], "--scene") == 0) scene = argv[++i];
    json q = json::parse(io::read_text(scene));
    std::vector<std::string> overrides;
    for (int i = 1; i + 1 < argc; ++i)
        if (std::strcmp(argv[i], "--set") == 0) overrides.emplace_back(argv[++i]);
    apply_overrides(q, overrides);
    if (central) central_result(q, scene.parent_path(), seeds);
    if (thinning) self_thinning(q, scene.parent_path(), seeds, years, density);
    if (water) water_and_stand(q, scene.parent_path(), seeds, century, paper);
    if (bare) {
        const std::filesystem::path hydro_scene = data / "scenes/hydro_quickstart.json";
        json h = json::parse(io::read_text(hydro_scene));
        apply_overrides(h, overrides);
        bare_ground(h, hydro_scene.parent_path(), seeds);
    }
    return 0;
}
