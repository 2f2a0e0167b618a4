// Windthrow (windthrow.hpp): the storm series follows ForestGALES' annual-maximum law (a
// statistical test), the climate's mean wind becomes the Weibull scale (checked by sampling the
// Weibull), the edge and gap factor is 1 inside the stand and rises toward an edge behind a gap;
// a storm fells exactly the trees whose critical wind it exceeds (many random stands and speeds),
// dominant and edge trees first; a felled tree leaves the pieces the mode says, along the wind;
// in the engine the series, the pieces and the carbon budget agree; bad storms are refused.
#include "ecoterra/eco/deadwood.hpp"
#include "ecoterra/eco/ecosystem.hpp"
#include "ecoterra/eco/scene_config.hpp"
#include "ecoterra/eco/windthrow.hpp"
#include "ecoterra/error.hpp"
#include "ecoterra/random.hpp"
#include "support/scenes.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

using namespace ecoterra;
using namespace ecoterra::eco;
using nlohmann::json;

namespace {

const GridSpec kArea{50, 50, 2.0, 0.0, 0.0}; // 100 m x 100 m

/// A closed stand of trees on a jittered grid: DBH 10-50 cm, heights from a slenderness of
/// 60-100, crowns from the DBH, light 0.2-1.
Population stand(std::uint64_t seed, double spacing_m = 4.0) {
    Rng rng(seed, "test.wind");
    Population pop;
    std::int64_t id = 1;
    for (double y = 1; y < kArea.height_m(); y += spacing_m)
        for (double x = 1; x < kArea.width_m(); x += spacing_m) {
            Plant p;
            p.id = id++;
            p.x_m = x + rng.uniform(-0.5, 0.5);
            p.y_m = y + rng.uniform(-0.5, 0.5);
            p.dbh_m = rng.uniform(0.1, 0.5);
            p.height_m = std::min(35.0, p.dbh_m * rng.uniform(60, 100));
            p.crown_radius_m = 2 + 6 * p.dbh_m;
            p.shade_fraction = rng.uniform(0, 0.8);
            pop.push(p);
        }
    return pop;
}

std::vector<Species> one_species() {
    std::vector<Species> sp(1);
    sp[0].name = "oak";
    return sp;
}

WindthrowOptions scripted(double wind, double from_deg, bool open = false) {
    WindthrowOptions o;
    o.random_storms = false;
    o.open_surroundings = open;
    o.storms.push_back({1, wind, from_deg});
    return o;
}

} // namespace

TEST_CASE("windthrow: the drawn annual maxima follow ForestGALES' Gumbel law of u^2",
          "[eco][windthrow][statistics]") {
    for (const double a : {3.0, 5.0, 8.6})
        for (const double k : {1.6, 1.85, 2.2}) {
            CAPTURE(a, k);
            // The inverse is the inverse.
            for (const double p : {0.01, 0.3, 0.5, 0.9, 0.999})
                CHECK(1 - wind::annual_exceedance(wind::annual_maximum(p, a, k), a, k) ==
                      Approx(p).margin(1e-12));
            // 20,000 years: the share above each of three speeds within 4 binomial sigmas.
            Rng rng(7, "test.wind.climate");
            std::vector<double> u(20000);
            for (auto& x : u) x = wind::annual_maximum(rng.uniform(), a, k);
            for (const double q : {0.5, 0.9, 0.99}) {
                const double speed = wind::annual_maximum(q, a, k);
                const double above = static_cast<double>(std::count_if(
                                         u.begin(), u.end(), [&](double x) { return x > speed; })) /
                                     static_cast<double>(u.size());
                const double p = wind::annual_exceedance(speed, a, k);
                CHECK(p == Approx(1 - q).margin(1e-12));
                CHECK(std::abs(above - p) < 4 * std::sqrt(p * (1 - p) / 20000.0));
            }
            // Stronger climates (larger scale) give stronger storms at every probability.
            CHECK(wind::annual_maximum(0.98, a * 1.1, k) > wind::annual_maximum(0.98, a, k));
        }
}

TEST_CASE("windthrow: severe convective storms strike as a Poisson process at the return period, "
          "with gusts uniform in their band turned into hourly means by the gust factor",
          "[eco][windthrow][statistics]") {
    for (const double period : {20.0, 1210.0})
        for (const std::uint64_t seed : {1ULL, 99ULL}) {
            CAPTURE(period, seed);
            WindthrowOptions o;
            o.severe_return_period_yr = period;
            const int years = 200000;
            double n = 0, sum = 0, sum_sq = 0, east = 0;
            const double lo = o.severe_gust_min_m_per_s / o.gust_factor;
            const double hi = o.severe_gust_max_m_per_s / o.gust_factor;
            for (int y = 1; y <= years; ++y) {
                const wind::SevereDraw d = wind::severe_storm(o, seed, y);
                REQUIRE(d.from_deg >= 0);
                REQUIRE(d.from_deg < 360);
                if (d.wind_m_per_s == 0) continue;
                REQUIRE(d.wind_m_per_s >= lo);
                REQUIRE(d.wind_m_per_s <= hi);
                n += 1;
                sum += d.wind_m_per_s;
                sum_sq += d.wind_m_per_s * d.wind_m_per_s;
                east += d.from_deg < 180;
            }
            // The count within 4 binomial sigmas of years / period.
            const double p = 1 / period;
            CHECK(std::abs(n - years * p) < 4 * std::sqrt(years * p * (1 - p)));
            // The speeds' mean and variance those of the uniform band (4 sigmas of the mean).
            const double mean = sum / n, sd = (hi - lo) / std::sqrt(12.0);
            CHECK(std::abs(mean - (lo + hi) / 2) < 4 * sd / std::sqrt(n));
            CHECK(std::sqrt(sum_sq / n - mean * mean) == Approx(sd).epsilon(0.15));
            // Directions uniform: half from the eastern half of the compass (4 sigmas).
            CHECK(std::abs(east / n - 0.5) < 4 * 0.5 / std::sqrt(n));
            // Stateless: a year's draw is the same whenever it is asked for.
            CHECK(wind::severe_storm(o, seed, 777).wind_m_per_s ==
                  wind::severe_storm(o, seed, 777).wind_m_per_s);
            // Turned off, no year has one.
            o.severe_storms = false;
            bool any = false;
            for (int y = 1; y <= 2000; ++y)
                any = any || wind::severe_storm(o, seed, y).wind_m_per_s;
            CHECK_FALSE(any);
        }
}

TEST_CASE("windthrow: a year's storm is the stronger of the gale and the severe storm, and a "
          "listed storm replaces both",
          "[eco][windthrow]") {
    const Population pop = stand(5);
    const std::vector<Species> sp = one_species();
    WindthrowOptions o;
    o.weibull_scale_m_per_s = 3.0;
    o.severe_return_period_yr = 1; // a severe storm every year
    o.storms.push_back({4, 12.0, 90.0});
    Windthrow w(o, 11);
    int severe = 0;
    for (int y = 1; y <= 6; ++y) {
        std::vector<char> dead(pop.size(), 0);
        const StormResult r = w.strike(pop, sp, kArea, y, dead, 1, 2);
        CAPTURE(y);
        const wind::SevereDraw d = wind::severe_storm(o, 11, y);
        if (y == 4) {
            CHECK(r.wind_m_per_s == 12);
            CHECK_FALSE(r.severe);
        } else {
            CHECK(r.severe);
            CHECK(r.wind_m_per_s == d.wind_m_per_s);
            // A 26 m/s storm and more: the stand's 10-50 cm trees mostly fall.
            CHECK(r.uprooted + r.broken > 0.5 * static_cast<double>(pop.size()));
            ++severe;
        }
    }
    CHECK(severe == 5);
    // Without random storms, neither gales nor severe storms are drawn.
    o.random_storms = false;
    Windthrow quiet(o, 11);
    std::vector<char> dead(pop.size(), 0);
    CHECK(quiet.strike(pop, sp, kArea, 2, dead, 1, 2).wind_m_per_s == 0);
}

TEST_CASE("windthrow: the climate's mean wind at 2 m becomes a Weibull scale whose mean is the "
          "wind at 10 m",
          "[eco][windthrow]") {
    for (const double u2 : {1.0, 2.0, 4.5})
        for (const double k : {1.5, 1.85, 2.5}) {
            CAPTURE(u2, k);
            const double a = wind::weibull_scale_from_u2(u2, k);
            // FAO-56 Eq 47 the other way: u2 = u10 4.87 / ln(67.8 x 10 - 5.42).
            const double u10 = u2 * std::log(67.8 * 10 - 5.42) / 4.87;
            Rng rng(3, "test.weibull");
            double sum = 0;
            const int n = 200000;
            for (int i = 0; i < n; ++i) sum += a * std::pow(-std::log(1 - rng.uniform()), 1 / k);
            CHECK(sum / n == Approx(u10).epsilon(0.01));
        }
}

TEST_CASE("windthrow: the edge and gap factor is 1 inside the stand and largest at an edge "
          "behind a wide gap",
          "[eco][windthrow]") {
    for (const double h : {10.0, 20.0, 30.0})
        for (const double spacing : {2.0, 4.0, 8.0}) {
            CAPTURE(h, spacing);
            CHECK(wind::edge_gap_factor(spacing, h, 9 * h, 10 * h) == Approx(1).margin(1e-12));
            CHECK(wind::edge_gap_factor(spacing, h, 50 * h, 3 * h) == Approx(1).margin(1e-12));
            CHECK(wind::edge_gap_factor(spacing, h, 0, 0) == Approx(1).margin(1e-12));
            // At the edge of a gap of 10 heights or more: (A + B) / (A + B C^9) (Gardiner et al.
            // 2000, with s = spacing / height within [0.075, 0.45]).
            const double s = std::clamp(spacing / h, 0.075, 0.45);
            const double A = 2.7193 * s - 0.061, B = -1.273 * s + 0.9701, C = 1.1127 * s + 0.0311;
            CHECK(wind::edge_gap_factor(spacing, h, 0, 20 * h) ==
                  Approx((A + B) / (A + B * std::pow(C, 9))));
            double last = 1e9;
            for (double x = 0; x <= 9 * h; x += h / 2) { // falls with the distance from the edge
                const double f = wind::edge_gap_factor(spacing, h, x, 10 * h);
                CHECK(f <= last + 1e-12);
                CHECK(f >= 1 - 1e-12);
                last = f;
            }
            double prev = 0;
            for (double g = 0; g <= 12 * h; g += h) { // rises with the gap
                const double f = wind::edge_gap_factor(spacing, h, 0, g);
                CHECK(f >= prev - 1e-12);
                prev = f;
            }
        }
}

TEST_CASE("windthrow: a storm fells exactly the trees whose critical wind it exceeds",
          "[eco][windthrow][property]") {
    const auto sp = one_species();
    for (std::uint64_t seed = 1; seed <= 6; ++seed)
        for (const double from : {0.0, 135.0, 270.0})
            for (const bool open : {false, true}) {
                CAPTURE(seed, from, open);
                const Population pop = stand(seed);
                Windthrow probe(scripted(0, from, open), 1);
                const double to = (90.0 - (from + 180.0)) * std::numbers::pi / 180.0;
                const auto cw = probe.critical_winds(pop, sp, kArea, to, 1);
                std::vector<double> c;
                for (const auto& t : cw) c.push_back(t.critical_m_per_s());
                std::vector<double> sorted = c;
                std::sort(sorted.begin(), sorted.end());
                for (const double q : {0.1, 0.5, 0.9}) {
                    const double u = sorted[static_cast<std::size_t>(q * sorted.size())];
                    Windthrow w(scripted(u, from, open), 1);
                    std::vector<char> dead(pop.size(), 0);
                    dead[0] = 3; // already dead this year: left as it is
                    const StormResult r = w.strike(pop, sp, kArea, 1, dead, 7, 8);
                    CHECK(r.wind_m_per_s == u);
                    double up = 0, br = 0;
                    for (std::size_t k = 1; k < pop.size(); ++k) {
                        CAPTURE(k, c[k]);
                        const bool felled = c[k] <= u;
                        CHECK((dead[k] != 0) == felled);
                        if (felled) CHECK(dead[k] == (cw[k].uproots() ? 7 : 8));
                        up += dead[k] == 7;
                        br += dead[k] == 8;
                    }
                    CHECK(dead[0] == 3);
                    CHECK(r.uprooted == up);
                    CHECK(r.broken == br);
                }
            }
}

TEST_CASE("windthrow: dominant trees, trees at an edge and slender trees go first, stocky ones "
          "uproot, slender ones break",
          "[eco][windthrow]") {
    const Species s = one_species()[0];
    wind::StandAero a;
    a.mean_height_m = 22, a.top_height_m = 25, a.spacing_m = 4, a.crown_width_m = 5;
    a.crown_depth_m = 10;
    const auto t = [&](double dbh, double h, double light, double dist, double gap) {
        return wind::tree_wind(s, dbh, h, light, a, dist, gap, 1.0);
    };
    for (const double dbh : {0.15, 0.3, 0.5}) {
        CAPTURE(dbh);
        const double h = std::min(30.0, 70 * dbh);
        // Full light (a dominant) against deep shade (suppressed, Hegyi 3.41).
        CHECK(t(dbh, h, 1.0, 200, 0).critical_m_per_s() <
              t(dbh, h, 0.2, 200, 0).critical_m_per_s());
        // At the edge of a wide gap against deep inside.
        CHECK(t(dbh, h, 0.6, 0, 250).critical_m_per_s() <
              t(dbh, h, 0.6, 200, 0).critical_m_per_s());
        // A slender stem breaks, a stocky one uproots.
        CHECK_FALSE(t(dbh, 140 * dbh, 0.6, 200, 0).uproots());
        CHECK(t(dbh, 30 * dbh, 0.6, 200, 0).uproots());
    }
    // A stand on an island: its upwind border is an edge, its lee is not.
    const auto sp = one_species();
    Population pop = stand(4);
    for (std::size_t k = 0; k < pop.size(); ++k) pop.shade_fraction[k] = 0.3;
    Windthrow w(scripted(0, 270, true), 1); // from the west: the west border is the edge
    const auto cw = w.critical_winds(pop, sp, kArea, 0.0, 1);
    double west = 0, east = 0, nw = 0, ne = 0;
    for (std::size_t k = 0; k < pop.size(); ++k) {
        if (pop.x_m[k] < 10) west += cw[k].edge_gap_factor, ++nw;
        if (pop.x_m[k] > 90) east += cw[k].edge_gap_factor, ++ne;
    }
    CHECK(west / nw > 1.5);
    CHECK(east / ne < 1.2);
    // Surrounded by forest, the same border is no edge (the canopy wraps around).
    Windthrow closed(scripted(0, 270, false), 1);
    const auto cc = closed.critical_winds(pop, sp, kArea, 0.0, 1);
    double wc = 0;
    for (std::size_t k = 0; k < pop.size(); ++k)
        if (pop.x_m[k] < 10) wc += cc[k].edge_gap_factor;
    CHECK(wc / nw < 1.2);
}

TEST_CASE("windthrow: an uprooted tree lies downwind with its root plate on edge, a broken one "
          "leaves half its mass standing and its top downwind",
          "[eco][windthrow][deadwood]") {
    namespace dw = eco::deadwood;
    const auto sp = one_species();
    Population pop;
    Plant p;
    p.id = 1, p.x_m = 50, p.y_m = 50, p.dbh_m = 0.4, p.height_m = 25;
    pop.push(p);
    p.id = 2, p.x_m = 20;
    pop.push(p);
    for (const double to : {0.0, 1.0, 4.0}) {
        CAPTURE(to);
        DeadWood d(DeadWoodOptions{}, 3);
        d.set_storm_azimuth(to);
        const std::vector<char> causes = {static_cast<char>(DeathCause::wind_uprooted),
                                          static_cast<char>(DeathCause::wind_broken)};
        d.take_dead(pop, sp, &causes, true, 5);
        const double mass = allometry::stem_mass_kg(sp[0], 0.4);
        CHECK(d.sums().input_kg == Approx(2 * mass));
        REQUIRE(d.pieces().size() == 4);
        auto angle = [](double a, double b) {
            return std::abs(std::remainder(a - b, 2 * std::numbers::pi));
        };
        const DeadStem& log = d.pieces()[0];
        const DeadStem& plate = d.pieces()[1];
        CHECK(log.standing == 0);
        CHECK(log.length_m == 25);
        CHECK(log.mass0_kg == Approx(mass));
        CHECK(angle(log.azimuth_rad, to) <= std::numbers::pi / 8 + 1e-12);
        CHECK(plate.piece == static_cast<std::uint8_t>(PieceKind::root_plate));
        CHECK(plate.mass0_kg == 0);
        CHECK(angle(plate.azimuth_rad, log.azimuth_rad + std::numbers::pi) < 1e-9);
        CHECK(root_plate_diameter_m(0.4) == Approx(4.8));
        CHECK(plate.length_m == Approx(1.0));
        const DeadStem& snag = d.pieces()[2];
        const DeadStem& top = d.pieces()[3];
        CHECK(snag.piece == static_cast<std::uint8_t>(PieceKind::snapped));
        CHECK(snag.standing == 1);
        CHECK(dw::stem_volume_fraction_below(25, snag.length_m) == Approx(0.5));
        CHECK(snag.mass0_kg + top.mass0_kg == Approx(mass));
        CHECK(top.offset_m == Approx(snag.length_m));
        CHECK(top.length_m == Approx(25 - snag.length_m));
        CHECK(std::hypot(top.x_m - 20, top.y_m - 50) == Approx(snag.length_m));
        CHECK(angle(top.azimuth_rad, to) <= std::numbers::pi / 8 + 1e-12);
        // The snapped snag never grows back; it falls; the plate goes when a log would.
        RasterD flat(GridSpec{50, 50, 2.0, 0.0, 0.0}, 0.0);
        const double z = snag.length_m;
        bool plate_gone = false;
        for (int y = 6; y < 200; ++y) {
            d.step_year(sp, flat, y);
            bool plate_here = false;
            for (const auto& q : d.pieces()) {
                if (q.piece == static_cast<std::uint8_t>(PieceKind::snapped))
                    CHECK(q.length_m <= z + 1e-12);
                plate_here |= q.piece == static_cast<std::uint8_t>(PieceKind::root_plate);
            }
            if (!plate_here && !plate_gone) {
                plate_gone = true;
                const double k = sp[0].deadwood_decay_rate_per_yr;
                CHECK((y - 5) * k >= -std::log(0.05));
                CHECK((y - 6) * k < -std::log(0.05));
            }
        }
        CHECK(plate_gone);
    }
}

TEST_CASE("windthrow in the engine: a storm's fallen trees are the wind pieces, the budget "
          "closes, the run repeats itself",
          "[eco][windthrow][engine]") {
    for (const std::string mode : {"coupled", "light_only"}) {
        CAPTURE(mode);
        auto j = test::small_scene(8, mode);
        j["vegetation"]["windthrow"] = {
            {"storms", {{{"year", 6}, {"wind_m_per_s", 24}, {"from_deg", 225}}}}};
        const EcoScene sc = load_eco_scene(j, test::data_dir() / "scenes");
        Ecosystem e(sc), again(sc);
        double felled = 0;
        for (int y = 1; y <= 8; ++y) {
            e.run_year();
            again.run_year();
            const Table& t = e.yearly();
            const std::size_t r = t.rows() - 1;
            CHECK(t.column("storm_wind_m_per_s")[r] ==
                  again.yearly().column("storm_wind_m_per_s")[r]);
            if (y == 6) CHECK(t.column("storm_wind_m_per_s")[r] == 24);
            const double up = t.column("windthrow_uprooted")[r];
            const double br = t.column("windthrow_broken")[r];
            felled += up + br;
            // The year's wind-felled trees of dead-wood size are the year's wind pieces.
            std::int64_t plates = 0, snapped = 0;
            for (const auto& d : e.dead_wood().pieces())
                if (d.year_died == y) {
                    plates += d.piece == static_cast<std::uint8_t>(PieceKind::root_plate);
                    snapped += d.piece == static_cast<std::uint8_t>(PieceKind::snapped);
                }
            CHECK(plates <= up);
            CHECK(snapped <= br);
        }
        CHECK(felled > 0);
        CHECK(e.carbon_residual_relative() < 1e-9);
        CHECK(e.plants().bitwise_equal(again.plants()));
    }
}

TEST_CASE("windthrow: bad storms and keys are refused, naming the key and the value",
          "[eco][windthrow][input]") {
    auto refuse = [](const json& w, const std::string& what) {
        auto j = test::small_scene(20);
        j["vegetation"]["windthrow"] = w;
        CAPTURE(w.dump());
        CHECK_THROWS_WITH(load_eco_scene(j, test::data_dir() / "scenes"), Catch::Contains(what));
    };
    refuse({{"storms", {{{"year", 21}, {"wind_m_per_s", 30}}}}},
           "vegetation.windthrow.storms[0].year = 21 is outside [1, 20]");
    refuse({{"storms", {{{"year", 3}, {"wind_m_per_s", -2}}}}},
           "vegetation.windthrow.storms[0].wind_m_per_s = -2");
    refuse({{"storms", {{{"year", 3}, {"wind_m_per_s", 250}}}}}, "wind_m_per_s = 250 is outside");
    refuse({{"storms", {{{"year", 3}}}}}, "storms[0].wind_m_per_s: missing");
    refuse({{"storms", {{{"year", 3}, {"wind_m_per_s", 30}}, {{"year", 3}, {"wind_m_per_s", 20}}}}},
           "storms[1].year = 3: another storm");
    refuse({{"storms", {{{"year", 3}, {"wind_m_per_s", 30}, {"from_deg", 400}}}}},
           "from_deg = 400");
    refuse({{"storms", {{{"year", 3}, {"speed", 30}}}}}, "unknown");
    refuse({{"weibull_shape", 0.2}}, "vegetation.windthrow.weibull_shape = 0.2");
    refuse({{"weibull_scale_m_per_s", -1}}, "vegetation.windthrow.weibull_scale_m_per_s = -1");
    refuse({{"gusts", true}}, "gusts");
    refuse({{"severe_return_period_yr", 0}}, "vegetation.windthrow.severe_return_period_yr = 0");
    refuse({{"severe_gust_min_m_per_s", 45}, {"severe_gust_max_m_per_s", 42}},
           "vegetation.windthrow.severe_gust_max_m_per_s = 42 is below "
           "vegetation.windthrow.severe_gust_min_m_per_s = 45");
    refuse({{"gust_factor", 0.5}}, "vegetation.windthrow.gust_factor = 0.5");
    refuse(json::array(), "vegetation.windthrow must be an object");
}
