// Mobility maps (docs/mobility.md s10): the ground, slope, vegetation and dead wood of each cell
// and heading against the physics they come from, and against drive_line along a row.
#include "support/temp_dir.hpp"

#include "ecoterra/hydro/soil_strength.hpp"
#include "ecoterra/mobility/ground.hpp"
#include "ecoterra/mobility/map.hpp"
#include "ecoterra/mobility/override.hpp"
#include "ecoterra/mobility/route.hpp"
#include "ecoterra/random.hpp"
#include "ecoterra/terrain/spectral.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <numbers>
#include <omp.h>

using namespace ecoterra;
using namespace ecoterra::mobility;

namespace {

Vehicle mrzr() {
    return load_vehicle(test::data_dir() / "vehicles/mrzr4.json");
}
Vehicle husky() {
    return load_vehicle(test::data_dir() / "vehicles/husky_a200.json");
}

RasterD flat(int n, double cell) {
    return RasterD(GridSpec{n, n, cell, 0.0, 0.0}, 0.0);
}

MobilityMap map_of(const Vehicle& v, const RasterD& dem, std::vector<StandStem> stems = {},
                   std::vector<Log> logs = {}, const GroundMaps& g = {}, MapOptions opt = {}) {
    return mobility_map(v, dem, stems, logs, g, opt);
}

int heading_index(const MobilityMap& m, double deg) {
    for (std::size_t h = 0; h < m.headings_deg.size(); ++h)
        if (std::abs(m.headings_deg[h] - deg) < 1e-9) return static_cast<int>(h);
    FAIL("no heading " << deg);
    return -1;
}

Limit limit_at(const MobilityMap& m, int h, int i, int j) {
    return static_cast<Limit>(m.limit[static_cast<std::size_t>(h)](i, j));
}

} // namespace

TEST_CASE("mobility map: open flat ground is GO at the vehicle's top speed everywhere",
          "[mobility][map]") {
    for (const Vehicle& v : {mrzr(), husky()}) {
        const MobilityMap m = map_of(v, flat(12, 1.0));
        CHECK(m.headings_deg.size() == 8);
        CHECK(m.go_share == 1);
        CHECK(m.top_speed_m_per_s == Approx(steady_speed_m_per_s(v, rolling_resistance_n(v, 0))));
        CHECK(m.mean_speed_m_per_s == Approx(m.top_speed_m_per_s));
        CHECK(m.limit_share[static_cast<int>(Limit::none)] == 1);
    }
}

TEST_CASE("mobility map: a slope steeper than the climb limit is NO-GO uphill and across, GO "
          "downhill",
          "[mobility][map]") {
    const Vehicle v = mrzr(); // climbs 30 deg, side slopes 25 deg
    RasterD dem = flat(20, 1.0);
    const double s = std::tan(35 * std::numbers::pi / 180);
    for (int j = 0; j < dem.ny(); ++j)
        for (int i = 0; i < dem.nx(); ++i) dem(i, j) = s * dem.grid().x_of(i); // rises east
    const MobilityMap m = map_of(v, dem);
    const int e = heading_index(m, 90), w = heading_index(m, 270), n = heading_index(m, 0);
    for (int j = 2; j < 18; ++j)
        for (int i = 2; i < 18; ++i) {
            CHECK(m.speed_m_per_s[e](i, j) == 0);
            CHECK(limit_at(m, e, i, j) == Limit::slope);
            CHECK(m.speed_m_per_s[n](i, j) == 0); // a side slope of 35 deg
            CHECK(m.speed_m_per_s[w](i, j) > 0);
        }
    // A moderate slope slows the climb (by more than 10 %: the slope limits it) and not the
    // descent.
    const double g = 0.25;
    for (int j = 0; j < dem.ny(); ++j)
        for (int i = 0; i < dem.nx(); ++i) dem(i, j) = g * dem.grid().x_of(i);
    const MobilityMap m2 = map_of(v, dem);
    const double up =
        steady_speed_m_per_s(v, rolling_resistance_n(v, g) + grade_resistance_n(v, g));
    CHECK(m2.speed_m_per_s[e](10, 10) == Approx(up));
    CHECK(limit_at(m2, e, 10, 10) == Limit::slope);
    CHECK(m2.speed_m_per_s[w](10, 10) == Approx(m2.top_speed_m_per_s));
}

TEST_CASE("mobility map: soil wetter than the vehicle's VCI1 is NO-GO, cells return as they "
          "dry in the order of their moisture, and clay bogs down where sand does not",
          "[mobility][map][soil]") {
    // Wet loam (Sullivan & Anderson) stays above 250 kPa up to saturation, far firmer than the
    // MRZR's VCI1 of 98 kPa: a heavy truck shows the wet-season NO-GO. 30 t on three axles of
    // two 1 m tyres 0.3 m wide: mobility index ~650, VCI1 ~510 kPa.
    Vehicle v = mrzr();
    v.mass_kg = 30000;
    v.axles = 3;
    v.wheel_radius_m = 0.5;
    v.tyre_width_m = 0.3;
    v.tractive_force_n = {{0, 1.5e5}, {10, 1.5e5}, {25, 0}};
    REQUIRE(cone_index_needs(v).vci1_kpa() > 450);
    const VehicleGround vg(v);
    const RasterD dem = flat(30, 1.0);
    RasterD rci(dem.grid(), 0.0);
    RasterD theta(dem.grid(), 0.0);
    Rng rng(11, "test");
    using hydro::Texture;
    // Loam at random soil water between dry and saturated.
    for (int j = 0; j < dem.ny(); ++j)
        for (int i = 0; i < dem.nx(); ++i) {
            theta(i, j) = rng.uniform(0.10, 0.47);
            rci(i, j) = hydro::rating_cone_index_kpa(Texture::loam, theta(i, j));
        }
    GroundMaps g;
    g.rci_kpa = &rci;
    const MobilityMap m = map_of(v, dem, {}, {}, g);
    // The NO-GO cells are exactly the wettest: a threshold of moisture splits them.
    double wettest_go = 0, driest_nogo = 1;
    int nogo = 0;
    for (int j = 0; j < dem.ny(); ++j)
        for (int i = 0; i < dem.nx(); ++i) {
            const bool go = m.go_fraction(i, j) > 0;
            if (go)
                wettest_go = std::max(wettest_go, theta(i, j));
            else
                driest_nogo = std::min(driest_nogo, theta(i, j)), ++nogo;
            CHECK((m.go_fraction(i, j) == 0 || m.go_fraction(i, j) == 1)); // flat: all or none
            if (!go) CHECK(m.limiting(i, j) == static_cast<std::uint8_t>(Limit::soil));
            if (rci(i, j) < vg.vci1_kpa()) CHECK_FALSE(go); // FM 5-430's one-pass rule
        }
    CHECK(nogo > 0);
    CHECK(nogo < dem.nx() * dem.ny());
    CHECK(wettest_go < driest_nogo);
    // Among GO cells, speed never rises with moisture (softer loam, more motion resistance).
    std::vector<std::pair<double, double>> by_theta;
    for (int j = 0; j < dem.ny(); ++j)
        for (int i = 0; i < dem.nx(); ++i)
            if (m.go_fraction(i, j) > 0)
                by_theta.emplace_back(theta(i, j), m.speed_mean_m_per_s(i, j));
    std::sort(by_theta.begin(), by_theta.end());
    for (std::size_t k = 1; k < by_theta.size(); ++k)
        CHECK(by_theta[k].second <= by_theta[k - 1].second);
    // The MRZR bogs down nowhere in the same soil.
    CHECK(map_of(mrzr(), dem, {}, {}, g).go_share == 1);
    // Dry (every cell at 0.10): GO everywhere.
    for (int j = 0; j < dem.ny(); ++j)
        for (int i = 0; i < dem.nx(); ++i)
            rci(i, j) = hydro::rating_cone_index_kpa(Texture::loam, 0.10);
    CHECK(map_of(v, dem, {}, {}, g).go_share == 1);
    // The same rain on clay and on sand: clay bogs down at some soil water, sand never does
    // (Sullivan & Anderson's sand firms as it wets).
    auto first_nogo = [&](Texture t) {
        for (double th = 0.05; th <= 0.5; th += 0.01)
            if (!vg.effect({hydro::rating_cone_index_kpa(t, th), 0, false}).go()) return th;
        return 1.0;
    };
    CHECK(first_nogo(Texture::clay) < 0.5);
    CHECK(first_nogo(Texture::sand) == 1.0);
}

TEST_CASE("mobility map: the light robot keeps going where the MRZR bogs down, as their "
          "needs say",
          "[mobility][map][soil]") {
    const RasterD dem = flat(6, 1.0);
    RasterD rci(dem.grid(), 50.0); // kPa: under the MRZR's VCI1 (98), over the Husky's ~19
    GroundMaps g;
    g.rci_kpa = &rci;
    CHECK(map_of(mrzr(), dem, {}, {}, g).go_share == 0);
    const MobilityMap h = map_of(husky(), dem, {}, {}, g);
    CHECK(h.go_share == 1);
    // (Its soil resistance, 1/Bn = 0.08 of its weight, leaves it its full 1 m/s: the motors'
    // 343 N are far more than the 54 N it needs on the flat.)
    CHECK(h.mean_speed_m_per_s <= h.top_speed_m_per_s);
    rci = RasterD(dem.grid(), 10.0); // below the Husky's net-traction limit
    const MobilityMap h2 = map_of(husky(), dem, {}, {}, g);
    CHECK(h2.go_share == 0);
    CHECK(h2.limit_share[static_cast<int>(Limit::soil)] == 1);
    // Brixius's net traction crosses zero near the MRZR's VCI1 (reference trafficability.md
    // s3f: ~106 kPa against 98).
    const double bn = brixius_mobility_number(mrzr(), 106);
    CHECK(bn == Approx(4.6).margin(0.1));
    CHECK(std::abs(brixius_max_net_traction(bn).first) < 0.01);
}

TEST_CASE("mobility map: standing water deeper than the fording depth is NO-GO",
          "[mobility][map][water]") {
    const Vehicle v = mrzr(); // no fording depth given: the ground clearance, 0.3 m
    CHECK(v.fording_depth() == v.ground_clearance_m);
    const RasterD dem = flat(10, 1.0);
    RasterD w(dem.grid(), 0.0);
    for (int j = 0; j < 10; ++j) w(4, j) = 0.35, w(7, j) = 0.2;
    GroundMaps g;
    g.water_depth_m = &w;
    const MobilityMap m = map_of(v, dem, {}, {}, g);
    for (int j = 0; j < 10; ++j) {
        CHECK(m.go_fraction(4, j) == 0);
        CHECK(m.limiting(4, j) == static_cast<std::uint8_t>(Limit::water));
        CHECK(m.go_fraction(7, j) == 1);
    }
}

TEST_CASE("mobility map: a thick tree closes the cells around it, thin stems slow the cells "
          "they stand in",
          "[mobility][map][vegetation]") {
    const Vehicle v = mrzr();
    const RasterD dem = flat(20, 1.0);
    // A 40 cm tree at the centre of cell (10, 10): every lane through the cell passes within
    // (d + w)/2 of it. A cell whose corner it stands on stays open in the headings whose lanes
    // may keep (d + w)/2 away within the cell.
    const MobilityMap m = map_of(v, dem, {{10.5, 10.5, 0.4, 20.0}});
    CHECK(m.go_fraction(10, 10) == 0);
    CHECK(m.limiting(10, 10) == static_cast<std::uint8_t>(Limit::vegetation));
    const MobilityMap corner = map_of(v, dem, {{10.0, 10.0, 0.4, 20.0}});
    CHECK(corner.go_fraction(9, 9) > 0);
    CHECK(corner.go_fraction(9, 9) < 1);
    CHECK(m.go_fraction(0, 0) == 1);
    CHECK(m.speed_mean_m_per_s(0, 0) == Approx(m.top_speed_m_per_s));
    // Shrubs of 5 cm at the ground (3.9 cm at the push height, under the critical 5.1 cm), a
    // row 0.25 m apart across x = 5.5: six in a lane, pushed over at ~3.3 kN, 14 % slower.
    std::vector<StandStem> thin;
    for (double y = 0.125; y < 20; y += 0.25)
        thin.push_back({5.5, y, 0.0, 1.0, StemKind::shrub, 0.05});
    const MobilityMap t = map_of(v, dem, thin);
    const int e = heading_index(t, 90);
    CHECK(t.speed_m_per_s[e](5, 10) > 0);
    CHECK(t.speed_m_per_s[e](5, 10) < t.top_speed_m_per_s);
    CHECK(limit_at(t, e, 5, 10) == Limit::vegetation);
    CHECK(t.speed_m_per_s[e](15, 10) == Approx(t.top_speed_m_per_s));
}

TEST_CASE("mobility map: a log too high to climb is an obstacle, a low one slows the crossing",
          "[mobility][map][deadwood]") {
    const Vehicle v = mrzr(); // step limit min(0.3, 0.33) = 0.3 m
    const RasterD dem = flat(20, 1.0);
    const Log high{{0, 10.5}, {20, 10.5}, 0.5, 0.5, 0.5}; // along x: blocks north-south
    const MobilityMap m = map_of(v, dem, {}, {high});
    const int n = heading_index(m, 0);
    CHECK(m.speed_m_per_s[n](5, 10) == 0);
    CHECK(limit_at(m, n, 5, 10) == Limit::obstacle);
    const Log low{{0, 10.5}, {20, 10.5}, 0.15, 0.15, 0.15};
    const MobilityMap l = map_of(v, dem, {}, {low});
    CHECK(l.speed_m_per_s[n](5, 10) > 0);
    CHECK(l.speed_m_per_s[n](5, 10) < l.top_speed_m_per_s);
    CHECK(l.speed_m_per_s[n](5, 10) >= step_crossing_speed_m_per_s(v, 0.15) - 1e-12);
    CHECK(limit_at(l, n, 5, 10) == Limit::obstacle);
    CHECK(l.speed_m_per_s[n](5, 2) == Approx(l.top_speed_m_per_s));
}

TEST_CASE("mobility map: along a row it agrees with drive_line, on fractal terrain with stems "
          "and soft soil",
          "[mobility][map]") {
    Vehicle v = mrzr();
    // Acceleration and braking as fast as the file allows: the map holds steady speeds.
    v.max_acceleration_m_per_s2 = v.max_deceleration_m_per_s2 = 20;
    for (const std::uint64_t seed : {1u, 2u, 3u}) {
        CAPTURE(seed);
        const RasterD dem = terrain::fbm_surface(
            GridSpec{64, 64, 1.0, 0.0, 0.0}, terrain::FbmParams::from_dimension(2.3, 0.3), seed);
        Rng rng(seed, "stems");
        std::vector<StandStem> stems;
        for (int k = 0; k < 60; ++k) // shrubs of 1-3 cm: overridden, never avoided
            stems.push_back({rng.uniform(0, 64), rng.uniform(0, 64), 0.0, 2.0, StemKind::shrub,
                             rng.uniform(0.01, 0.03)});
        RasterD rci(dem.grid(), 2000.0);
        for (int j = 0; j < 64; ++j)
            for (int i = 25; i < 35; ++i) rci(i, j) = 250; // soft: Bn ~ 10
        GroundMaps g;
        g.rci_kpa = &rci;
        const MobilityMap m = map_of(v, dem, stems, {}, g);
        const int e = heading_index(m, 90);
        std::vector<Stem> at_push;
        for (const auto& s : stems)
            at_push.push_back(
                {s.x_m, s.y_m,
                 diameter_at_height_from_base_m(s.base_diameter_m, s.height_m, v.push_height_m)});
        const StemIndex index(at_push, 1.0);
        SmgOptions opt;
        opt.ground = g;
        for (const int row : {10, 32, 50}) {
            CAPTURE(row);
            const double y = dem.grid().y_of(row);
            const LineResult line = drive_line(v, index, &dem, {4.0, y}, {60.0, y}, opt);
            INFO(line.nogo_reason);
            REQUIRE_FALSE(line.nogo);
            // The map's cells driven as drive_line drives its own: each boundary at the slower
            // of its two cells' steady speeds, speeding up and braking in between.
            std::vector<double> len(56, 1.0), cap(57, std::numeric_limits<double>::infinity());
            for (int i = 4; i < 60; ++i) {
                const double sp = m.speed_m_per_s[e](i, row);
                cap[static_cast<std::size_t>(i - 4)] =
                    std::min(cap[static_cast<std::size_t>(i - 4)], sp);
                cap[static_cast<std::size_t>(i - 3)] = sp;
            }
            const double t =
                profile_time_s(len, cap, v.max_acceleration_m_per_s2, v.max_deceleration_m_per_s2);
            CHECK(t == Approx(line.time_s).epsilon(0.03)); // measured within 1.6 %
        }
    }
}

TEST_CASE("mobility map: coarse cells, any thread count, and bad options", "[mobility][map]") {
    const Vehicle v = mrzr();
    RasterD dem = flat(40, 0.5);
    Rng rng(5, "test");
    for (int j = 0; j < dem.ny(); ++j)
        for (int i = 0; i < dem.nx(); ++i) dem(i, j) = 0.05 * std::sin(0.3 * i) * std::cos(0.2 * j);
    std::vector<StandStem> stems;
    for (int k = 0; k < 30; ++k) stems.push_back({rng.uniform(0, 20), rng.uniform(0, 20), 0.08, 9});
    RasterD rci(dem.grid(), 0.0);
    for (int j = 0; j < dem.ny(); ++j)
        for (int i = 0; i < dem.nx(); ++i) rci(i, j) = rng.uniform(60, 400);
    GroundMaps g;
    g.rci_kpa = &rci;
    const int threads = omp_get_max_threads();
    omp_set_num_threads(1);
    const MobilityMap one = map_of(v, dem, stems, {}, g);
    omp_set_num_threads(std::max(2, threads));
    const MobilityMap two = map_of(v, dem, stems, {}, g);
    omp_set_num_threads(threads);
    for (std::size_t h = 0; h < one.speed_m_per_s.size(); ++h) {
        CHECK((one.speed_m_per_s[h].array() == two.speed_m_per_s[h].array()).all());
        CHECK((one.limit[h].array() == two.limit[h].array()).all());
    }
    // A 2 m cell holds 4 x 4 terrain cells: the median of their ground.
    MapOptions opt;
    opt.cell_m = 2;
    opt.headings = 16;
    const MobilityMap c = map_of(v, dem, stems, {}, g, opt);
    CHECK(c.grid.nx == 10);
    CHECK(c.headings_deg.size() == 16);
    std::vector<double> block;
    for (int jj = 4; jj < 8; ++jj)
        for (int ii = 8; ii < 12; ++ii) block.push_back(rci(ii, jj));
    std::sort(block.begin(), block.end());
    CHECK(c.rci_kpa(2, 1) == Approx(0.5 * (block[7] + block[8])));
    opt.cell_m = 0.25;
    CHECK_THROWS_WITH(map_of(v, dem, {}, {}, {}, opt), Catch::Contains("finer than the terrain"));
    opt.cell_m = 0.75;
    CHECK_THROWS_WITH(map_of(v, dem, {}, {}, {}, opt), Catch::Contains("not a whole multiple"));
    opt.cell_m = 0;
    opt.headings = 0;
    CHECK_THROWS_WITH(map_of(v, dem, {}, {}, {}, opt), Catch::Contains("headings = 0"));
}

TEST_CASE("steady speed: the closed form agrees with a fine search over many vehicles and loads",
          "[mobility][map]") {
    // An independent reference: march up from standstill in steps of 1e-4 m/s to the first speed
    // the net force does not exceed 0, then bisect.
    Rng rng(17, "test");
    for (int trial = 0; trial < 300; ++trial) {
        Vehicle v = mrzr();
        v.tractive_force_n.clear();
        double s = 0, f = rng.uniform(2000, 15000);
        const int rows = 2 + static_cast<int>(rng.uniform(0, 4));
        for (int r = 0; r < rows; ++r) {
            v.tractive_force_n.emplace_back(s, f);
            s += rng.uniform(1, 12);
            f = std::max(0.0, f + rng.uniform(-6000, 2000));
        }
        v.drag_n_per_m2_s2 = trial % 3 == 0 ? 0.0 : rng.uniform(0, 30);
        v.top_speed_m_per_s = rng.uniform(5, 30);
        const double mu = rng.uniform(0.2, 1.2);
        const double resistance = rng.uniform(-2000, 12000);
        CAPTURE(trial, resistance, mu);
        auto net = [&](double x) {
            return v.tractive_force_at(x, mu) - v.drag_n_per_m2_s2 * x * x - resistance;
        };
        double ref = 0;
        if (net(0) > 0) {
            double x = 0;
            const double step = 1e-4;
            while (x < v.top_speed_m_per_s && net(std::min(x + step, v.top_speed_m_per_s)) > 0)
                x += step;
            if (x >= v.top_speed_m_per_s) {
                ref = v.top_speed_m_per_s;
            } else {
                double lo = x, hi = std::min(x + step, v.top_speed_m_per_s);
                for (int it = 0; it < 60; ++it)
                    (net(0.5 * (lo + hi)) > 0 ? lo : hi) = 0.5 * (lo + hi);
                ref = lo;
            }
        }
        CHECK(steady_speed_m_per_s(v, resistance, mu) == Approx(ref).margin(1e-7));
    }
}

TEST_CASE("route: the fastest path over a map agrees with a brute-force relaxation, and finds "
          "the gap in a wall",
          "[mobility][map][route]") {
    const std::vector<double> headings{0, 45, 90, 135, 180, 225, 270, 315};
    const int di[8] = {0, 1, 1, 1, 0, -1, -1, -1}, dj[8] = {1, 1, 0, -1, -1, -1, 0, 1};
    Rng rng(23, "test");
    for (int trial = 0; trial < 20; ++trial) {
        CAPTURE(trial);
        const GridSpec g{12, 9, 2.0, 100.0, 50.0};
        std::vector<RasterD> speed;
        for (int h = 0; h < 8; ++h) {
            RasterD r(g, 0.0);
            for (int j = 0; j < g.ny; ++j)
                for (int i = 0; i < g.nx; ++i)
                    r(i, j) = rng.uniform() < 0.15 ? 0.0 : rng.uniform(0.5, 10);
            speed.push_back(r);
        }
        speed[0](0, 0) = speed[2](0, 0) = 5; // the start can leave
        // Brute force: relax every edge until nothing changes (Bellman-Ford).
        std::vector<double> t(static_cast<std::size_t>(g.size()), 1e300);
        t[0] = 0;
        for (bool changed = true; changed;) {
            changed = false;
            for (int j = 0; j < g.ny; ++j)
                for (int i = 0; i < g.nx; ++i)
                    for (int m = 0; m < 8; ++m) {
                        const int ii = i + di[m], jj = j + dj[m];
                        if (!g.contains(ii, jj)) continue;
                        const double va = speed[m](i, j), vb = speed[m](ii, jj);
                        if (!(va > 0 && vb > 0)) continue;
                        const double step = (m % 2 ? std::sqrt(2.0) : 1.0) * g.cell_size_m;
                        const double tt = t[static_cast<std::size_t>(j * g.nx + i)] +
                                          0.5 * step / va + 0.5 * step / vb;
                        if (tt < t[static_cast<std::size_t>(jj * g.nx + ii)] - 1e-12) {
                            t[static_cast<std::size_t>(jj * g.nx + ii)] = tt;
                            changed = true;
                        }
                    }
        }
        const Route r = fastest_route(speed, headings, {101, 51}, {122.5, 64.5});
        const double ref = t[static_cast<std::size_t>(7 * g.nx + 11)];
        CHECK(r.found == (ref < 1e299));
        if (r.found) {
            CHECK(r.time_s == Approx(ref).epsilon(1e-12));
            CHECK(r.path.front().x_m == Approx(101));
            CHECK(r.path.back().y_m == Approx(65));
        }
    }
    // A NO-GO wall across a uniform map at x = 20 m with one gap: the route goes through the gap.
    const GridSpec g{40, 40, 1.0, 0.0, 0.0};
    std::vector<RasterD> speed(8, RasterD(g, 4.0));
    for (auto& r : speed)
        for (int j = 0; j < 40; ++j)
            if (j != 33) r(20, j) = 0;
    const Route r = fastest_route(speed, headings, {5.5, 5.5}, {35.5, 5.5});
    REQUIRE(r.found);
    bool through_gap = false;
    for (const auto& p : r.path) through_gap = through_gap || (p.x_m == 20.5 && p.y_m == 33.5);
    CHECK(through_gap);
    CHECK(r.time_s > 30 / 4.0);
    // Headings that miss a neighbour direction, points off the map.
    CHECK_THROWS_WITH(fastest_route({speed[0]}, {0}, {1, 1}, {2, 2}),
                      Catch::Contains("no speed layer for heading 45"));
    CHECK_THROWS_WITH(fastest_route(speed, headings, {-1, 1}, {2, 2}),
                      Catch::Contains("--from (-1, 1) is off the map"));
}
