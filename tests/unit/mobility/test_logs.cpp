// Logs as steps (docs/mobility.md s4.3): a log no higher than the step limit is climbed at the
// speed the wheel stays on its edge, over the closed-form speed profile; a higher log is driven
// around (its end, or the part of a tapered log low enough to climb) or is NOGO; crossings follow
// Buffon's law in a random field of logs; the log index finds each log once.
#include "support/temp_dir.hpp"

#include "ecoterra/error.hpp"
#include "ecoterra/mobility/override.hpp"
#include "ecoterra/mobility/smg.hpp"
#include "ecoterra/mobility/stand.hpp"
#include "ecoterra/random.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>
#include <numbers>

using namespace ecoterra;
using namespace ecoterra::mobility;

namespace {

Vehicle mrzr() {
    return load_vehicle(test::data_dir() / "vehicles/mrzr4.json");
}

LineResult drive(const std::vector<Log>& logs, Point a = {0, 0}, Point b = {100, 0}) {
    return drive_line(mrzr(), StemIndex({}, 2.0), LogIndex(logs, 2.0), nullptr, a, b);
}

/// Time to go from speed u to the cap v0 (or as far as the distance allows) at rate a over D.
double ramp_time(double u, double v0, double a, double D) {
    const double top = std::sqrt(u * u + 2 * a * D);
    if (top <= v0) return (top - u) / a;
    return (v0 - u) / a + (D - (v0 * v0 - u * u) / (2 * a)) / v0;
}

/// Closed-form time of a 100 m flat line at the steady speed v0 with the speed held at vc over
/// [x_in, x_out]: braking at the vehicle's rate before, speeding up after.
double slow_zone_time(const Vehicle& v, double v0, double vc, double x_in, double x_out) {
    return ramp_time(vc, v0, v.max_deceleration_m_per_s2, x_in) + (x_out - x_in) / vc +
           ramp_time(vc, v0, v.max_acceleration_m_per_s2, 100 - x_out);
}

/// A log across the line at x, from y0 to y1, with its top at h0 and h1.
Log across(double x, double y0, double y1, double h0, double h1, double d = 0.3) {
    return {{x, y0}, {x, y1}, h0, h1, d};
}

} // namespace

TEST_CASE("logs: the step limit and the crossing speed of the shipped vehicles",
          "[mobility][logs]") {
    const Vehicle m = mrzr();
    const Vehicle h = load_vehicle(test::data_dir() / "vehicles/husky_a200.json");
    // min(ground clearance, wheel radius): the MRZR's clearance 0.30 m, the Husky's 0.13 m
    // (reference deadwood.md s6: 0.25-0.3 and 0.08-0.13 m).
    CHECK(step_limit_m(m) == Approx(0.30));
    CHECK(step_limit_m(h) == Approx(0.13));
    // sqrt(g (r - h)): at the ground sqrt(g r), falling to 0 at the wheel radius.
    CHECK(step_crossing_speed_m_per_s(m, 0) == Approx(std::sqrt(9.80665 * 0.3302)));
    CHECK(step_crossing_speed_m_per_s(m, 0.1) == Approx(std::sqrt(9.80665 * 0.2302)));
    CHECK(step_crossing_speed_m_per_s(m, 0.3302) == 0);
    CHECK(step_crossing_speed_m_per_s(m, 0.2) < step_crossing_speed_m_per_s(m, 0.1));
}

TEST_CASE("logs: a climbable log slows the line over the closed-form profile, a higher one is "
          "slower still",
          "[mobility][logs]") {
    const Vehicle v = mrzr();
    const double v0 = steady_speed_m_per_s(v, 0);
    const auto open = drive({});
    REQUIRE(open.smg_m_per_s == Approx(v0));
    double last_smg = open.smg_m_per_s;
    for (const double h : {0.05, 0.1, 0.2, 0.28}) {
        CAPTURE(h);
        const auto r = drive({across(50, -30, 30, h, h)});
        REQUIRE_FALSE(r.nogo);
        CHECK(r.logs_crossed == 1);
        CHECK(r.logs_avoided == 0);
        CHECK(r.path_m == Approx(100));
        // The speed is held at sqrt(g (r - h)) from the front wheels' arrival at the log until
        // the rear wheels are over it: at least [50, 50 + wheelbase], at most from a cell (one
        // vehicle width) before to two cells after.
        const double vc = step_crossing_speed_m_per_s(v, h);
        const double t_min = slow_zone_time(v, v0, vc, 50, 50 + v.wheelbase_m);
        const double t_max =
            slow_zone_time(v, v0, vc, 50 - v.width_m, 50 + v.wheelbase_m + 2 * v.width_m);
        CHECK(r.time_s >= t_min * (1 - 1e-9));
        CHECK(r.time_s <= t_max * (1 + 1e-9));
        CHECK(r.smg_m_per_s < last_smg);
        last_smg = r.smg_m_per_s;
    }
    // Two logs cost twice one for a vehicle that is back at its top speed between them (the
    // Husky, 1 m/s, speeding up at 5 m/s2); a log beside the line costs nothing.
    const Vehicle husky = load_vehicle(test::data_dir() / "vehicles/husky_a200.json");
    auto husky_drive = [&](const std::vector<Log>& logs) {
        return drive_line(husky, StemIndex({}, 2.0), LogIndex(logs, 2.0), nullptr, {0, 0},
                          {100, 0});
    };
    const double h0 = husky_drive({}).time_s;
    const double one = husky_drive({across(30, -30, 30, 0.1, 0.1)}).time_s - h0;
    const auto two = husky_drive({across(30, -30, 30, 0.1, 0.1), across(70, -30, 30, 0.1, 0.1)});
    CHECK(two.logs_crossed == 2);
    CHECK(one > 0);
    CHECK(two.time_s - h0 == Approx(2 * one).epsilon(1e-6));
    const auto beside = drive({{{10, 3}, {90, 3}, 0.1, 0.1, 0.3}});
    CHECK(beside.logs_crossed == 0);
    CHECK(beside.time_s == Approx(open.time_s));
}

TEST_CASE("logs: a log above the step limit is driven around its end, a tapered one where it is "
          "low enough, a wall of them is NOGO",
          "[mobility][logs]") {
    const Vehicle v = mrzr();
    // A 0.45 m log from y = -40 to y = 5 across the line: around its north end, a capsule of
    // radius R = (d + W) / 2 plus a planning cell; tangents and an arc, as around a disk.
    const double d = 0.45, R = 0.5 * (d + v.width_m) + 0.125 * v.width_m;
    const auto high = drive({across(50, -40, 5, d, d, d)});
    REQUIRE_FALSE(high.nogo);
    CHECK(high.logs_crossed == 0);
    CHECK(high.logs_avoided == 1);
    const double D = std::hypot(50.0, 5.0);
    const double expect =
        2 * std::sqrt(D * D - R * R) + 2 * R * (std::atan2(5.0, 50.0) + std::asin(R / D));
    CHECK(high.path_m == Approx(expect).epsilon(3e-3));
    // Tapered from 0.45 m at y = -30 to 0.15 m at y = 30: above the MRZR's 0.30 m south of y = 0.
    // The line at y = -10 goes north to climb it where it is low enough.
    const auto taper = drive({across(50, -30, 30, 0.45, 0.15, 0.45)}, {0, -10}, {100, -10});
    REQUIRE_FALSE(taper.nogo);
    CHECK(taper.logs_crossed == 1);
    CHECK(taper.logs_avoided == 1);
    CHECK(taper.path_m > 100.5);
    CHECK(taper.path_m < high.path_m + 10);
    // The same log reversed: the line at y = +10 crosses it straight.
    const auto low_end = drive({across(50, -30, 30, 0.45, 0.15, 0.45)}, {0, 10}, {100, 10});
    CHECK(low_end.logs_crossed == 1);
    CHECK(low_end.logs_avoided == 0);
    CHECK(low_end.path_m == Approx(100));
    // A high log across the whole planning area: NOGO, named.
    const auto wall = drive({across(50, -60, 60, 0.5, 0.5, 0.5)});
    CHECK(wall.nogo);
    CHECK(wall.smg_m_per_s == 0);
    CHECK_THAT(wall.nogo_reason, Catch::Contains("logs it cannot climb"));
    // A line that starts on a high log: NOGO.
    CHECK(drive({across(0.5, -10, 10, 0.5, 0.5, 0.5)}).nogo);
}

TEST_CASE("logs: a stand with one log of each of three heights across every transect",
          "[mobility][logs][stand]") {
    const Vehicle v = mrzr();
    const RasterD dem(GridSpec{100, 100, 1.0, 0.0, 0.0}, 0.0);
    // 0.1 m across the whole stand at x = 30, 0.28 m at x = 50, 0.45 m (above the limit) at x = 70
    // from y = 35 to y = 65.
    const std::vector<Log> logs = {across(30, -1, 101, 0.1, 0.1), across(50, -1, 101, 0.28, 0.28),
                                   across(70, 35, 65, 0.45, 0.45, 0.45)};
    StandLinesOptions opt;
    opt.layout = LineLayout::transects;
    opt.lines = 20;
    opt.length_m = 90;
    const auto with = analyse_stand(v, {}, dem, opt, logs);
    const auto without = analyse_stand(v, {}, dem, opt);
    CHECK(with.logs == 3);
    CHECK(with.step_limit_m == Approx(0.30));
    const double reach = 0.5 * (0.45 + v.width_m);
    for (const auto& l : with.lines) {
        const double y = l.a.y_m;
        CAPTURE(y);
        REQUIRE_FALSE(l.result.nogo);
        CHECK(l.result.logs_crossed == 2);
        const bool across_high = y >= 35 - reach && y <= 65 + reach;
        CHECK(l.result.logs_avoided == (across_high ? 1 : 0));
        if (y > 37 && y < 63) CHECK(l.result.path_m > 90.1);
        if (y < 30 || y > 70) CHECK(l.result.path_m == Approx(90));
    }
    CHECK(with.smg_mean_m_per_s < without.smg_mean_m_per_s);
    double driven = 0;
    for (const auto& l : with.lines) driven += l.result.path_m;
    CHECK(with.log_crossings_per_100m == Approx(100 * 2 * 20 / driven));
    CHECK(with.logs_avoided_per_line > 0);
}

TEST_CASE("logs: crossings in a random field of logs follow Buffon's law",
          "[mobility][logs][property]") {
    // Logs of length L at uniform positions and headings, n per m2: a straight footprint of length
    // l and width W meets on average n (l W + 2 L (l + W) / pi) of them (the mean area of the
    // footprint swept by a randomly turned segment).
    const Vehicle v = mrzr();
    const double side = 120, L = 8, n = 0.02, len = 50;
    const RasterD dem(GridSpec{120, 120, 1.0, 0.0, 0.0}, 0.0);
    double crossings = 0, lines = 0;
    for (std::uint64_t seed = 1; seed <= 6; ++seed) {
        Rng rng(seed, "test.logs");
        std::vector<Log> logs;
        const double lo = -L, hi = side + L;
        const auto count = static_cast<int>(n * (hi - lo) * (hi - lo));
        for (int k = 0; k < count; ++k) {
            const double x = rng.uniform(lo, hi), y = rng.uniform(lo, hi);
            const double t = rng.uniform(0, 2 * std::numbers::pi);
            logs.push_back({{x, y}, {x + L * std::cos(t), y + L * std::sin(t)}, 0.05, 0.05, 0.1});
        }
        StandLinesOptions opt;
        opt.lines = 60;
        opt.length_m = len;
        opt.seed = seed;
        const auto m = analyse_stand(v, {}, dem, opt, logs);
        REQUIRE(m.detour_fraction == 0);
        for (const auto& l : m.lines) crossings += static_cast<double>(l.result.logs_crossed);
        lines += static_cast<double>(m.lines.size());
    }
    const double W = v.width_m;
    const double expect = n * (len * W + 2 * L * (len + W) / std::numbers::pi) * lines;
    CAPTURE(crossings, expect);
    CHECK(std::abs(crossings - expect) < 4 * std::sqrt(expect));
}

TEST_CASE("logs: the log index reports each log in a box once, as a search of all of them does",
          "[mobility][logs][property]") {
    Rng rng(11, "test.logindex");
    std::vector<Log> logs;
    for (int k = 0; k < 400; ++k) {
        const double x = rng.uniform(0, 100), y = rng.uniform(0, 100);
        const double t = rng.uniform(0, 2 * std::numbers::pi), l = rng.uniform(0, 25);
        logs.push_back({{x, y}, {x + l * std::cos(t), y + l * std::sin(t)}, 0.1, 0.1, 0.2});
    }
    for (const double bucket : {0.7, 2.0, 9.0, 60.0}) {
        const LogIndex index(logs, bucket);
        for (int q = 0; q < 200; ++q) {
            const double x0 = rng.uniform(-20, 120), y0 = rng.uniform(-20, 120);
            const double x1 = x0 + rng.uniform(0, 30), y1 = y0 + rng.uniform(0, 30);
            std::vector<std::int64_t> got, want;
            index.for_each_in_box(x0, y0, x1, y1, [&](std::int64_t k) { got.push_back(k); });
            for (std::size_t k = 0; k < logs.size(); ++k) {
                const Log& l = logs[k];
                if (std::max(l.a.x_m, l.b.x_m) >= x0 && std::min(l.a.x_m, l.b.x_m) <= x1 &&
                    std::max(l.a.y_m, l.b.y_m) >= y0 && std::min(l.a.y_m, l.b.y_m) <= y1)
                    want.push_back(static_cast<std::int64_t>(k));
            }
            std::sort(got.begin(), got.end());
            CAPTURE(bucket, q);
            CHECK(got == want);
        }
    }
    CHECK_THROWS_WITH(LogIndex({{{0, 0}, {1, 0}, -0.1, 0.1, 0.1}}, 1.0),
                      Catch::Contains("negative height"));
}

TEST_CASE("logs: dead-wood lists are read by their header, bad values are named",
          "[mobility][logs][input]") {
    test::TempDir dir;
    auto write = [&](const std::string& body) {
        const auto p = dir.path() / "dead.csv";
        std::ofstream(p) << "id,standing,x_m,y_m,end_x_m,end_y_m,dbh_m,tree_height_m,length_m,"
                            "height_m,end_height_m,species_name\n"
                         << body;
        return p;
    };
    const auto ok = read_deadwood_csv(write("1,1,5,5,5,5,0.3,20,15,15,15,Pine\n"
                                            "2,0,10,10,13,14,0.25,18,5,0.25,0.18,Pine\n"));
    REQUIRE(ok.snags.size() == 1);
    REQUIRE(ok.logs.size() == 1);
    CHECK(ok.snags[0].kind == StemKind::snag);
    CHECK(ok.snags[0].dbh_m == 0.3);
    CHECK(ok.snags[0].height_m == 15); // as tall as it stands, not as the tree was
    CHECK(ok.logs[0].b.x_m == 13);
    CHECK(ok.logs[0].height_b_m == 0.18);
    CHECK_THROWS_WITH(read_deadwood_csv(write("2,0,10,10,13,14,0.25,18,-5,0.25,0.18,Pine\n")),
                      Catch::Contains("dead.csv") && Catch::Contains("length_m") &&
                          Catch::Contains("-5"));
    CHECK_THROWS_WITH(read_deadwood_csv(write("2,0,10,10,13,14,0.25,18,7,0.25,0.18,Pine\n")),
                      Catch::Contains("length_m = 7") && Catch::Contains("5 m apart"));
    CHECK_THROWS_WITH(read_deadwood_csv(write("2,2,10,10,13,14,0.25,18,5,0.25,0.18,Pine\n")),
                      Catch::Contains("standing = 2"));
    CHECK_THROWS_WITH(read_deadwood_csv(write("2,0,10,10,13,14,0.25,18,5,abc,0.18,Pine\n")),
                      Catch::Contains("height_m"));
    const auto p = dir.path() / "short.csv";
    std::ofstream(p) << "x_m,y_m,dbh_m\n1,2,0.3\n";
    CHECK_THROWS_WITH(read_deadwood_csv(p),
                      Catch::Contains("short.csv") && Catch::Contains("standing"));
}

TEST_CASE("stand effects: the lines meet only the stems overridden, or only those avoided",
          "[mobility][stand][effects]") {
    const Vehicle v = mrzr();
    const RasterD dem(GridSpec{60, 60, 1.0, 0.0, 0.0}, 0.0);
    const double dc = critical_diameter_m(v.weight_n(), v.push_height_m);
    for (std::uint64_t seed = 1; seed <= 4; ++seed) {
        Rng rng(seed, "test.effects");
        std::vector<StandStem> stems;
        for (int k = 0; k < 300; ++k)
            stems.push_back({rng.uniform(0.0, 60.0), rng.uniform(0.0, 60.0),
                             rng.uniform(0.02, 3 * dc), std::nan(""), StemKind::tree, 0});
        StandLinesOptions opt;
        opt.layout = LineLayout::transects;
        opt.lines = 12;
        opt.length_m = 50;
        const auto all = analyse_stand(v, stems, dem, opt);
        opt.effects = StemEffects::override_only;
        const auto pushed = analyse_stand(v, stems, dem, opt);
        opt.effects = StemEffects::avoidance_only;
        const auto avoided = analyse_stand(v, stems, dem, opt);
        CHECK(pushed.trees == all.trees); // the stand's counts are the whole stand's
        CHECK(pushed.stems.size() + avoided.stems.size() == all.stems.size());
        for (const Stem& s : pushed.stems) CHECK(s.diameter_m < dc);
        for (const Stem& s : avoided.stems) CHECK(s.diameter_m >= dc);
        REQUIRE(all.lines.size() == pushed.lines.size());
        REQUIRE(all.lines.size() == avoided.lines.size());
        for (std::size_t l = 0; l < all.lines.size(); ++l) {
            // A detour around a big stem can skirt small ones too, so a line through the small
            // stems alone may be slower than through the whole stand; adding the small stems to
            // the big ones never speeds a line up.
            CHECK(avoided.lines[l].result.overridden == 0);
            CHECK(all.lines[l].result.smg_m_per_s <= avoided.lines[l].result.smg_m_per_s + 1e-9);
        }
        // Pushing stems over slows the vehicle, if little; the avoided stems slow it most.
        const auto none = analyse_stand(v, {}, dem, opt);
        CHECK(pushed.smg_mean_m_per_s < none.smg_mean_m_per_s);
        CHECK(pushed.override_fraction > 0);
        CHECK(all.smg_mean_m_per_s < pushed.smg_mean_m_per_s);
        CHECK(all.smg_mean_m_per_s <= avoided.smg_mean_m_per_s);
    }
}

TEST_CASE("pits: an uprooted tree's pit lies windward of its plate, is cut into the ground, and "
          "slows a line across it",
          "[mobility][logs][pits]") {
    StandDeadWood d;
    // A root plate 3 m across and 0.5 m thick, standing on edge from (50, -3) toward +y.
    d.add(4, false, {50, -3}, {50, -2.5}, 0.25, 3.0, 3.0);
    // A stem, a stump, a top and a snapped snag leave no pit.
    d.add(0, false, {10, 5}, {20, 5}, 0.3, 0.3, 0.1);
    d.add(1, false, {12, 5}, {12, 5}, 0.3, 0.3, 0.3);
    d.add(2, false, {14, 5}, {18, 5}, 0.1, 0.1, 0.05);
    d.add(3, true, {16, 5}, {16, 5}, 0.3, 4.0, 4.0);
    REQUIRE(d.pits.size() == 1);
    const Pit& p = d.pits[0];
    CHECK(p.x_m == Approx(50));
    CHECK(p.y_m == Approx(-1)); // a thickness and a radius windward of the base
    CHECK(p.radius_m == Approx(1.5));
    CHECK(p.depth_m == Approx(0.25)); // half the thickness
    // Cut into the ground: every cell centre within the radius lowered by the depth, no other.
    const GridSpec g{200, 40, 0.5, 0.0, -10.0};
    const RasterD flat(g, 2.0);
    RasterD dem = flat;
    carve_pits(dem, d.pits);
    int inside = 0;
    for (int j = 0; j < g.ny; ++j)
        for (int i = 0; i < g.nx; ++i) {
            const bool in = std::hypot(g.x_of(i) - 50, g.y_of(j) + 1) <= 1.5;
            inside += in;
            CHECK(dem(i, j) == (in ? 1.75 : 2.0));
        }
    CHECK(inside == Approx(std::numbers::pi * 1.5 * 1.5 / 0.25).epsilon(0.15));
    // The layer's form with an origin: the same depths, moved.
    const RasterD moved = pit_depths(g, {{60, 4, 1.5, 0.25}}, 10, 5);
    for (int j = 0; j < g.ny; ++j)
        for (int i = 0; i < g.nx; ++i) CHECK(moved(i, j) == 2.0 - dem(i, j));
    // A line through the pit is slower than over the flat ground; one beside it is not.
    const Vehicle v = mrzr();
    auto line = [&](const RasterD& z, double y) {
        return drive_line(v, StemIndex({}, 2.0), LogIndex({}, 2.0), &z, {1, y}, {99, y});
    };
    const LineResult over = line(dem, -1), plain = line(flat, -1), beside = line(dem, 6);
    CHECK(plain.smg_m_per_s == Approx(steady_speed_m_per_s(v, 0)));
    CHECK((over.nogo || over.time_s > plain.time_s * 1.001));
    CHECK(beside.time_s == Approx(plain.time_s));
}
