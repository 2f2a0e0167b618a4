// Vehicles and the override law: the published MAVS numbers (reference mobility.md s1.6), closed
// forms of the steady-state speed, and the vehicle files' strictness.
#include "support/temp_dir.hpp"

#include "ecoterra/error.hpp"
#include "ecoterra/mobility/override.hpp"
#include "ecoterra/mobility/smg.hpp"
#include "ecoterra/mobility/traverse.hpp"
#include "ecoterra/mobility/vehicle.hpp"
#include "ecoterra/random.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>
#include <numbers>

using namespace ecoterra;
using namespace ecoterra::mobility;
using nlohmann::json;

namespace {

Vehicle mrzr() {
    return load_vehicle(test::data_dir() / "vehicles/mrzr4.json");
}

/// The MRZR's speed above 14.1 m/s in closed form: the root of
/// 11520 (57.6 - v) / 43.5 - 18.7 v^2 - R = 0.
double mrzr_closed_form(double resistance_n) {
    const double a = 18.7, b = 11520.0 / 43.5, c = resistance_n - 11520.0 * 57.6 / 43.5;
    return (-b + std::sqrt(b * b - 4 * a * c)) / (2 * a);
}

} // namespace

TEST_CASE("the override force follows MAVS's cubic law at the published diameters",
          "[mobility][override]") {
    // Reference mobility.md s1.6 (MRZR, h = 23.02 cm: tyre radius + CG offset), rounded to 1 N.
    constexpr double h = 0.2302;
    const std::vector<std::pair<double, double>> table = {
        {0.01, 19},   {0.025, 226},  {0.05, 1204}, {0.075, 4063},
        {0.10, 9631}, {0.15, 32504}, {0.20, 77046}};
    for (const auto& [d, f] : table) {
        INFO("d = " << d << " m");
        CHECK(override_force_n(d, h) == Approx(f).margin(1.0));
    }
    CHECK(override_force_n(0.0, h) == 0.0);
    // Cubic above the small-stem bracket: doubling the diameter multiplies the force by 8.
    CHECK(override_force_n(0.2, h) / override_force_n(0.1, h) == Approx(8.0).epsilon(1e-6));
    // The critical diameter of the MRZR (GVW 12.55 kN): 5.07 cm, where F is about a tenth of GVW.
    const double dc = critical_diameter_m(12550, h);
    CHECK(dc == Approx(0.0507).margin(5e-5));
    CHECK(override_force_n(dc, h) == Approx(1255).margin(2));
    // The Husky's (GVW 490 N, h 19.4 cm): about 1.7 cm.
    CHECK(critical_diameter_m(490, 0.194) == Approx(0.017).margin(5e-4));
}

TEST_CASE("the steady-state speed is the root of thrust minus drag and resistance",
          "[mobility][speed]") {
    Vehicle v = mrzr();
    CHECK(v.weight_n() == Approx(12550).margin(5));
    // An empty flat stand: the top speed (22.3 m/s, the curve's own equilibrium 22.34 m/s).
    CHECK(steady_speed_m_per_s(v, 0) == Approx(22.3));
    v.top_speed_m_per_s = 100; // uncapped: the closed form
    CHECK(steady_speed_m_per_s(v, 0) == Approx(mrzr_closed_form(0)).epsilon(1e-9));
    // One stem per cell (reference s1.6): 21.2 m/s at 5 cm, 18.4 at 7.5 cm.
    CHECK(steady_speed_m_per_s(v, override_force_n(0.05, 0.23)) == Approx(21.2).margin(0.05));
    CHECK(steady_speed_m_per_s(v, override_force_n(0.075, 0.23)) == Approx(18.4).margin(0.05));
    // A grade lowers the speed as the tractive curve says.
    for (const double grade : {0.02, 0.05, 0.1, 0.2}) {
        const double r = grade_resistance_n(v, grade);
        CHECK(r == Approx(v.weight_n() * grade / std::sqrt(1 + grade * grade)));
        const double s = steady_speed_m_per_s(v, r);
        if (s > 14.1) CHECK(s == Approx(mrzr_closed_form(r)).epsilon(1e-9));
        CHECK(s < steady_speed_m_per_s(v, 0));
    }
    // Below 14.1 m/s the thrust is flat: 11520 - 18.7 v^2 = R.
    const double r = 11520 - 18.7 * 10 * 10;
    CHECK(steady_speed_m_per_s(v, r) == Approx(10.0).epsilon(1e-9));
    // More resistance never gives more speed; beyond the thrust at standstill it is NOGO.
    double last = 1e9;
    for (double res = 0; res < 13000; res += 250) {
        const double s = steady_speed_m_per_s(v, res);
        CHECK(s <= last);
        last = s;
    }
    CHECK(steady_speed_m_per_s(v, 11520) == 0.0);
    CHECK(steady_speed_m_per_s(v, 2e4) == 0.0);
    // The traction limit caps the thrust.
    v.traction_coefficient = 0.5;
    CHECK(v.tractive_force_at(0) == Approx(0.5 * v.weight_n()));
    CHECK(steady_speed_m_per_s(v, 0.6 * v.weight_n()) == 0.0);
}

TEST_CASE("stem diameter at the push height tapers linearly from breast height",
          "[mobility][override]") {
    CHECK(diameter_at_height_m(0.3, 20, 1.3) == Approx(0.3));
    CHECK(diameter_at_height_m(0.3, 20, 0.23) == Approx(0.3 * 19.77 / 18.7));
    CHECK(diameter_at_height_m(0.3, 20, 20) == 0.0);
    CHECK(diameter_at_height_m(0.0, 1.0, 0.2) == 0.0); // below breast height
}

TEST_CASE("vehicle files: the shipped ones load, round-trip, and bad values are named",
          "[mobility][vehicle][errors]") {
    for (const char* f : {"mrzr4.json", "husky_a200.json"}) {
        const Vehicle v = load_vehicle(test::data_dir() / "vehicles" / f);
        const json j = to_json(v);
        CHECK(to_json(parse_vehicle(j, f)) == j);
        for (const auto& p : vehicle_catalog().params())
            CHECK((j.contains(p.key) || p.optional)); // an unset optional key is left out
    }
    const Vehicle h = load_vehicle(test::data_dir() / "vehicles/husky_a200.json");
    CHECK(h.top_speed_m_per_s == 1.0);
    CHECK(steady_speed_m_per_s(h, 0) == Approx(1.0));
    const json good = to_json(h);
    auto fails = [&](json j, const std::string& contains) {
        INFO(j.dump());
        CHECK_THROWS_WITH(parse_vehicle(j, "car.json"),
                          Catch::Contains("car.json") && Catch::Contains(contains));
    };
    json j = good;
    j["width_m"] = 0;
    fails(j, "width_m");
    j = good;
    j["mass_kg"] = -5;
    fails(j, "-5");
    j = good;
    j["widht_m"] = 1;
    fails(j, "did you mean");
    j = good;
    j.erase("tractive_force_n");
    fails(j, "tractive_force_n");
    j = good;
    j["tractive_force_n"] = {{0, 300}, {2, 200}, {1, 100}};
    fails(j, "function of speed");
    j = good;
    j["tractive_force_n"] = {{0, 300}, {1, -1}};
    fails(j, "row 1");
    j = good;
    j["tractive_force_n"] = {{0.5, 300}, {1, 100}};
    fails(j, "speed 0");
    j = good;
    j["track_m"] = 2;
    fails(j, "track_m");
    j = good;
    j.erase("mass_kg");
    fails(j, "mass_kg");
    CHECK_THROWS_AS(load_vehicle("/nonexistent/car.json"), InputError);
}

namespace {

LineResult drive(const std::vector<Stem>& stems, const RasterD* dem = nullptr, Point a = {0, 0},
                 Point b = {100, 0}) {
    return drive_line(mrzr(), StemIndex(stems, 2.0), dem, a, b);
}

/// Stems of one diameter at uniform random positions over [x0, x1] x [y0, y1].
std::vector<Stem> random_stand(std::uint64_t seed, std::size_t n, double d, double x0, double y0,
                               double x1, double y1) {
    Rng rng(seed, "test.stand");
    std::vector<Stem> s;
    for (std::size_t k = 0; k < n; ++k) s.push_back({rng.uniform(x0, x1), rng.uniform(y0, y1), d});
    return s;
}

} // namespace

TEST_CASE("speed made good: an empty flat stand gives the top speed, a slope what the curve says",
          "[mobility][smg]") {
    const Vehicle v = mrzr();
    const auto empty = drive({});
    CHECK_FALSE(empty.nogo);
    CHECK(empty.path_m == Approx(100));
    CHECK(empty.smg_m_per_s == Approx(steady_speed_m_per_s(v, 0)));
    // A tilted plane z = 0.1 x: uphill at the speed of grade 0.1, downhill faster (capped).
    RasterD plane(GridSpec{300, 100, 1.0, -50.0, -50.0});
    for (int j = 0; j < plane.ny(); ++j)
        for (int i = 0; i < plane.nx(); ++i) plane(i, j) = 0.1 * plane.grid().x_of(i);
    const double up =
        steady_speed_m_per_s(v, rolling_resistance_n(v, 0.1) + grade_resistance_n(v, 0.1));
    CHECK(drive({}, &plane).smg_m_per_s == Approx(up).epsilon(1e-9));
    CHECK(drive({}, &plane, {100, 0}, {0, 0}).smg_m_per_s >= up);
    CHECK_THROWS_WITH(drive({}, &plane, {0, 0}, {400, 0}), Catch::Contains("leaves the terrain"));
    // Across a slope: below the side-slope limit the line runs level at the flat speed; above it,
    // NOGO (the MRZR's limit is 25 degrees; tan 25 deg = 0.466).
    for (const double tilt : {0.1, 0.3, 0.45, 0.48, 0.7}) {
        RasterD across(GridSpec{300, 100, 1.0, -50.0, -50.0});
        for (int j = 0; j < across.ny(); ++j)
            for (int i = 0; i < across.nx(); ++i) across(i, j) = tilt * across.grid().y_of(j);
        const auto r = drive({}, &across);
        CAPTURE(tilt);
        CHECK(r.nogo == (std::atan(tilt) > v.max_side_slope_deg * std::numbers::pi / 180));
        if (r.nogo)
            CHECK_THAT(r.nogo_reason, Catch::Contains("side-slope limit"));
        else
            CHECK(r.smg_m_per_s == Approx(empty.smg_m_per_s).epsilon(1e-9));
    }
}

TEST_CASE("speed made good: one thick stem costs the detour around it, a wall is NOGO",
          "[mobility][smg]") {
    const Vehicle v = mrzr();
    // A 30 cm stem on the line's middle: the shortest path hugs a disk of radius R = d/2 + W/2.
    const auto one = drive({{50, 0, 0.3}});
    REQUIRE_FALSE(one.nogo);
    const double R = 0.15 + 0.5 * v.width_m, D = 50;
    const double alpha = std::acos(R / D);
    const double expect = 2 * std::sqrt(D * D - R * R) + R * (std::numbers::pi - 2 * alpha);
    CHECK(one.path_m == Approx(expect).epsilon(2e-3));
    CHECK(one.avoided == 1);
    CHECK(one.overridden == 0);
    CHECK(one.smg_m_per_s == Approx(100 / (one.path_m / v.top_speed_m_per_s)).epsilon(1e-9));
    // A row of 20 cm stems every 0.5 m across the whole planning area: no way through.
    std::vector<Stem> wall;
    for (double y = -40; y <= 40; y += 0.5) wall.push_back({50, y, 0.2});
    const auto blocked = drive(wall);
    CHECK(blocked.nogo);
    CHECK(blocked.smg_m_per_s == 0.0);
    // Thin stems across the line are pushed over, more slowly than the open stand.
    std::vector<Stem> thin;
    for (double y = -40; y <= 40; y += 0.5) thin.push_back({50, y, 0.03});
    const auto pushed = drive(thin);
    CHECK_FALSE(pushed.nogo);
    CHECK(pushed.overridden >= 3);
    CHECK(pushed.path_m == Approx(100));
    CHECK(pushed.smg_m_per_s < drive({}).smg_m_per_s);
    CHECK(pushed.override_m == Approx(v.width_m).margin(1e-9));
}

TEST_CASE("speed made good never rises as stems are added, and the cubic law ranks stands",
          "[mobility][smg][property]") {
    for (std::uint64_t seed = 1; seed <= 6; ++seed) {
        CAPTURE(seed);
        auto stems = random_stand(seed, 30, 0.12, 0, -20, 100, 20);
        double last = drive({}).smg_m_per_s;
        for (const std::size_t extra : {10u, 20u, 40u}) {
            auto more = random_stand(seed + 100 * extra, extra, 0.04, 0, -20, 100, 20);
            stems.insert(stems.end(), more.begin(), more.end());
            const double s = drive(stems).smg_m_per_s;
            CHECK(s <= last * (1 + 1e-9));
            last = s;
        }
    }
    // Equal basal area, stems all below the critical diameter: the force per basal area grows
    // with d (F ~ d^3, count ~ 1/d^2), so thicker stems slow the vehicle more.
    const double area = 100.0 * 40.0, ba = 11.48e-4 * area; // 11.48 m2/ha (50 ft2/acre)
    auto stand = [&](double d) {
        const auto n = static_cast<std::size_t>(ba / (std::numbers::pi * d * d / 4));
        return drive(random_stand(7, n, d, 0, -20, 100, 20)).smg_m_per_s;
    };
    CHECK(stand(0.045) < stand(0.02));
}

namespace {

/// A 20 x 20 m terrain of 5 cm cells from z(x, y).
template <class F>
RasterD surface(F z) {
    RasterD r(GridSpec{400, 400, 0.05, 0.0, 0.0});
    for (int j = 0; j < r.ny(); ++j)
        for (int i = 0; i < r.nx(); ++i) r(i, j) = z(r.grid().x_of(i), r.grid().y_of(j));
    return r;
}

Vehicle husky() {
    return load_vehicle(test::data_dir() / "vehicles/husky_a200.json");
}

} // namespace

TEST_CASE("traversal: planes, a corrugation and a bar against their closed forms",
          "[mobility][traverse]") {
    const Vehicle v = husky();
    const MissionLine east{1, 2, 10, 18, 10};
    // Flat: success in length / speed, no motion of the chassis.
    const auto flat = traverse(v, surface([](double, double) { return 0.0; }), east);
    REQUIRE(flat.success);
    CHECK(flat.time_s == Approx(16.0));
    CHECK(flat.rms_vertical_acceleration_m_per_s2 == Approx(0).margin(1e-9));
    CHECK(flat.rms_pitch_rate_deg_per_s == Approx(0).margin(1e-9));
    // A climb of 20 % along the path: pitch atan(0.2), no rates (a plane), success.
    const auto ramp = traverse(v, surface([](double x, double) { return 0.2 * x; }), east);
    REQUIRE(ramp.success);
    CHECK(ramp.max_abs_pitch_deg == Approx(std::atan(0.2) * 180 / std::numbers::pi));
    CHECK(ramp.rms_pitch_rate_deg_per_s == Approx(0).margin(1e-6));
    CHECK(ramp.rms_vertical_acceleration_m_per_s2 == Approx(0).margin(1e-6));
    // Steeper than the Husky's 45 degree climb: fails at the first pose; across it, the 30
    // degree side-slope limit fails first.
    const auto steep = traverse(v, surface([](double x, double) { return 1.1 * x; }), east);
    CHECK_FALSE(steep.success);
    CHECK(steep.failure == "climb limit");
    CHECK(steep.failed_at_m == 0.0);
    const auto side = traverse(v, surface([](double, double y) { return 0.7 * y; }), east);
    CHECK(side.failure == "side-slope limit");
    // A corrugation z = A sin(k x): the chassis (mean of the wheels at x +- L/2) moves as
    // A cos(k L/2) sin(k x), so its RMS vertical acceleration is A cos(k L / 2) (k v)^2 / sqrt 2.
    const double A = 0.01, lambda = 2.0, k = 2 * std::numbers::pi / lambda;
    const auto wave =
        traverse(v, surface([&](double x, double) { return A * std::sin(k * x); }), east);
    REQUIRE(wave.success);
    const double expect = A * std::abs(std::cos(k * v.wheelbase_m / 2)) * k * k / std::sqrt(2.0);
    CHECK(wave.rms_vertical_acceleration_m_per_s2 == Approx(expect).epsilon(0.02));
    CHECK(wave.rms_roll_rate_deg_per_s == Approx(0).margin(1e-9));
    // A bar 20 cm high and 15 cm wide across the path: its vertical face meets the chassis's
    // front edge (13 cm up, 0.495 m ahead of the centre) before the wheels reach it.
    const auto bar = traverse(
        v, surface([](double x, double) { return std::abs(x - 10) < 0.075 ? 0.2 : 0.0; }), east);
    CHECK(bar.failure == "bumper");
    CHECK(bar.failed_at_m == Approx(10 - 0.075 - 0.495 - 2).margin(0.06));
    // A smooth ridge 20 cm high and 0.6 m wide (faces up to 1.05, which the front edge slides up
    // and the wheels climb): it passes between the axles and lifts the belly.
    const auto ridge =
        traverse(v, surface([](double x, double) {
                     const double u = std::numbers::pi * (x - 10) / 0.6;
                     return std::abs(x - 10) < 0.3 ? 0.2 * std::cos(u) * std::cos(u) : 0.0;
                 }),
                 east);
    CHECK(ridge.failure == "high-centred");
    CHECK(ridge.failed_at_m == Approx(8).margin(0.3));
    // Off the terrain.
    CHECK_THROWS_WITH(traverse(v, surface([](double, double) { return 0.0; }), {2, 2, 10, 30, 10}),
                      Catch::Contains("leaves the terrain"));
}

TEST_CASE("traversal: a step stalls the vehicle when pushing a wheel up its edge takes more "
          "traction than the ground gives",
          "[mobility][traverse]") {
    Vehicle v = husky(); // wheel radius 0.165 m, traction 0.7, rolling 0.03
    const MissionLine east{1, 2, 10, 18, 10};
    auto step = [](double h) {
        return surface([h](double x, double) { return x >= 10 ? h : 0.0; });
    };
    // A wheel pushed against a step of height h rises at tan(phi), cos(phi) = (r - h)/r: both
    // front wheels at once lift the mean of the four at tan(phi)/2. An 8 cm step: tan(phi) =
    // 1.66, 0.83 + 0.03 of the weight needed against 0.7 given: stuck where the front wheels
    // meet it. A 4 cm step: 0.43 + 0.03: it climbs.
    const auto high = traverse(v, step(0.08), east);
    CHECK(high.failure == "stuck");
    CHECK(high.failed_at_m == Approx(10 - 0.256 - 2).margin(0.2));
    CHECK(traverse(v, step(0.04), east).success);
    // With grip enough (1.2 > 0.86) the 8 cm step is climbed.
    v.traction_coefficient = 1.2;
    v.tractive_force_n = {{0, 1.2 * v.weight_n()}, {1, 1.2 * v.weight_n()}};
    CHECK(traverse(v, step(0.08), east).success);
    // The ground: a band softer than the Husky's net traction (Brixius: ~19 kPa) stalls it, and
    // water deeper than its fording depth (its clearance, 0.13 m) stops it.
    const RasterD flat = surface([](double, double) { return 0.0; });
    RasterD rci(flat.grid(), 500.0), water(flat.grid(), 0.0);
    for (int j = 0; j < rci.ny(); ++j)
        for (int i = 240; i < 260; ++i) rci(i, j) = 10;
    TraverseOptions opt;
    opt.ground.rci_kpa = &rci;
    const auto soft = traverse(husky(), flat, east, opt);
    CHECK(soft.failure == "stuck (soil)");
    CHECK(soft.failed_at_m == Approx(12 - 2).margin(0.06));
    opt.ground.rci_kpa = nullptr;
    for (int j = 0; j < rci.ny(); ++j)
        for (int i = 100; i < 110; ++i) water(i, j) = 0.2;
    opt.ground.water_depth_m = &water;
    CHECK(traverse(husky(), flat, east, opt).failure == "water");
}

TEST_CASE("traversal: missions files are read by their header, bad values are named",
          "[mobility][traverse][errors]") {
    test::TempDir dir;
    std::ofstream(dir / "m.csv") << "id,start_x_m,start_y_m,goal_x_m,goal_y_m,heading_deg\n"
                                    "7,1,2,3,4,45\n";
    const auto m = read_missions_csv(dir / "m.csv");
    REQUIRE(m.size() == 1);
    CHECK(m[0].id == 7);
    CHECK(m[0].goal_y_m == 4);
    std::ofstream(dir / "bad.csv") << "id,start_x_m,start_y_m,goal_x_m,goal_y_m\n1,1,2,x,4\n";
    CHECK_THROWS_WITH(read_missions_csv(dir / "bad.csv"),
                      Catch::Contains("bad.csv line 2") && Catch::Contains("goal_x_m"));
    std::ofstream(dir / "short.csv") << "id,start_x_m\n";
    CHECK_THROWS_WITH(read_missions_csv(dir / "short.csv"), Catch::Contains("start_y_m"));
}

TEST_CASE("speed made good: turns slow the vehicle as its lateral acceleration allows",
          "[mobility][smg]") {
    // The speed profile in closed form: two 50 m cells at 20 m/s around a 10 m/s boundary,
    // 1 m/s2 either way: the vehicle brakes from sqrt(200) m/s and speeds up to it again.
    CHECK(profile_time_s({100}, {20, 20}, 1, 1) == Approx(5.0));
    const double u = std::sqrt(200.0);
    CHECK(profile_time_s({50, 50}, {20, 10, 20}, 1, 1) == Approx(2 * 100 / (u + 10)));
    CHECK_THROWS_AS(profile_time_s({50, 50}, {20, 20}, 1, 1), Error);
    // Through a field of obstacles, SMG grows with the lateral acceleration allowed in turns
    // and never exceeds the length-only figure.
    const auto stems = random_stand(11, 150, 0.15, 5, -6, 95, 6);
    Vehicle v = mrzr();
    double last = 0, first = 0;
    for (const double a_lat : {0.5, 2.0, 8.0, 20.0}) {
        v.max_lateral_acceleration_m_per_s2 = a_lat;
        const auto r = drive_line(v, StemIndex(stems, 2.0), nullptr, {0, 0}, {100, 0});
        REQUIRE_FALSE(r.nogo);
        CHECK(r.smg_m_per_s >= last);
        CHECK(r.smg_m_per_s <= 100 / (r.path_m / v.top_speed_m_per_s) * (1 + 1e-12));
        last = r.smg_m_per_s;
        if (first == 0) first = last;
    }
    CHECK(first < 0.9 * last); // the turns matter in this field
}
