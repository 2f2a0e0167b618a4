// Groundwater against analytic solutions of the Boussinesq equation (the steady Dupuit mound, the
// linearised hillslope recession and recharge mound, a decaying mode), and the implicit solver
// against the CVODE reference on fractal and white-noise terrain.
#include "ecoterra/hydro/groundwater.hpp"
#include "ecoterra/terrain/spectral.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <random>
#include <utility>

using namespace ecoterra;
using namespace ecoterra::hydro;
using ecoterra::GridSpec;
using ecoterra::RasterD;
using GB = GroundwaterBoundary;

namespace {

const char* name(GroundwaterSolver s) {
    return s == GroundwaterSolver::cvode ? "cvode" : "implicit";
}
GroundwaterNumerics with(GroundwaterSolver s) {
    GroundwaterNumerics n;
    n.solver = s;
    return n;
}

double sum(const std::vector<double>& v) {
    double s = 0;
    for (double x : v) s += x;
    return s;
}

/// Linearised Boussinesq (thick aquifer, T = K H constant, D = T / S_y) on a strip; x is the
/// distance from a fixed head at 0.
/// Hillslope recession: no flow at x = L, initial rise H0 everywhere, drains to the stream at 0:
///   h = sum over odd m of 4 H0 / (m pi) sin(m pi x / (2 L)) exp(-m^2 pi^2 D t / (4 L^2)).
double recession(double x, double t, double L, double D, double H0) {
    double h = 0;
    for (int m = 1; m < 2001; m += 2)
        h += 4 * H0 / (m * std::numbers::pi) * std::sin(m * std::numbers::pi * x / (2 * L)) *
             std::exp(-m * m * std::numbers::pi * std::numbers::pi * D * t / (4 * L * L));
    return h;
}
/// Recharge mound: fixed heads at 0 and L, uniform recharge W (m/s) from t = 0 on a flat table:
///   h = W x (L - x) / (2 T) - sum over odd m of 4 W L^2 / (T m^3 pi^3) sin(m pi x / L)
///       exp(-m^2 pi^2 D t / L^2).
double mound(double x, double t, double L, double D, double T, double W) {
    double h = W * x * (L - x) / (2 * T);
    for (int m = 1; m < 2001; m += 2) {
        const double mp = m * std::numbers::pi;
        h -= 4 * W * L * L / (T * mp * mp * mp) * std::sin(mp * x / L) *
             std::exp(-mp * mp * D * t / (L * L));
    }
    return h;
}

/// The terrain and conductivity of the comparisons on fractal and white-noise terrain: fBm
/// (D 2.3, rms `fbm_rms_m`) or white noise (sd 0.3 m, from rng), and K = 5e-6 m/s e^(u - 0.5)
/// per cell (u uniform in [0, 1), from rng after the noise).
std::pair<RasterD, RasterF> test_aquifer(const GridSpec& g, int kind, double fbm_rms_m,
                                         std::uint64_t seed, std::mt19937_64& rng) {
    RasterD dem =
        kind == 0
            ? terrain::fbm_surface(g, terrain::FbmParams::from_dimension(2.3, fbm_rms_m), seed)
            : RasterD(g, 0.0);
    if (kind == 1) {
        std::normal_distribution<double> noise(0.0, 0.3);
        for (std::int64_t c = 0; c < dem.size(); ++c) dem.data()[c] = noise(rng);
    }
    RasterF ks(g, 5e-6f);
    std::uniform_real_distribution<double> u(0, 1);
    for (std::int64_t c = 0; c < ks.size(); ++c)
        ks.data()[c] = static_cast<float>(5e-6 * std::exp(u(rng) - 0.5));
    return {std::move(dem), std::move(ks)};
}

} // namespace

TEST_CASE("Steady Dupuit mound under uniform recharge between fixed heads",
          "[groundwater][verification]") {
    const GroundwaterSolver solver =
        GENERATE(GroundwaterSolver::implicit, GroundwaterSolver::cvode);
    INFO(name(solver));
    // h(x)^2 = h0^2 + (W / K) x (L - x), x from the west boundary cell centre, L = (nx - 1) dx.
    const int nx = 41, ny = 3;
    const double dx = 10, K = 1e-4, W = 1e-8, h0 = 10, sy = 0.2;
    const GridSpec g{nx, ny, dx, 0, 0};
    RasterD surface(g, 100.0), base(g, 0.0), head(g, h0);
    RasterF ks(g, static_cast<float>(K));
    Groundwater gw(surface, base, head, ks, sy,
                   {GB::fixed_head, GB::fixed_head, GB::no_flow, GB::no_flow}, with(solver));
    const double dt = 1e6; // s
    std::vector<double> recharge(static_cast<std::size_t>(g.size()), W * dx * dx * dt);
    double out = 0, added = 0;
    const double s0 = gw.storage_m3();
    for (int k = 0; k < 120; ++k) {
        const auto r = gw.step(dt, recharge);
        out += r.outflow_m3;
        added += sum(recharge); // recharge on fixed heads leaves at once
        for (double s : r.seepage_m3) CHECK(s == 0.0);
    }
    const RasterD h = gw.head();
    const double L = (nx - 1) * dx;
    double worst = 0;
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            const double x = i * dx;
            const double exact = std::sqrt(h0 * h0 + W / K * x * (L - x));
            worst = std::max(worst, std::abs(h(i, j) - exact) / exact);
        }
    CHECK(worst < 1e-6);
    // Conservation: what was added is stored or left through the fixed heads.
    CHECK(gw.storage_m3() - s0 + out == Approx(added).epsilon(1e-12));
    // At steady state the outflow equals the recharge.
    const auto last = gw.step(dt, recharge);
    CHECK(last.outflow_m3 == Approx(sum(recharge)).epsilon(1e-5));
}

TEST_CASE("A sine mode of the water table decays at the discrete diffusion rate",
          "[groundwater][verification]") {
    // Thick aquifer (T ~ K H constant): linear diffusion with D = K H / S_y. The discrete mode
    // sin(pi x / L) decays as exp(-lambda t), lambda = (4 D / dx^2) sin^2(pi dx / (2 L)), in
    // continuous time (CVODE, to its tolerance); a TR-BDF2 step of dt (the implicit solver at one
    // step per call) multiplies it by R(z) = (a (1 + g z / 2) / (1 - g z / 2) - b) / (1 - c z),
    // z = -lambda dt, g = 2 - sqrt 2, a = 1 / (g (2 - g)), b = a - 1, c = (1 - g) / (2 - g).
    const int nx = 41, ny = 3;
    const double dx = 10, K = 1e-4, H = 1000, a = 0.01, sy = 0.2;
    const GridSpec g{nx, ny, dx, 0, 0};
    const double L = (nx - 1) * dx;
    RasterD surface(g, 50.0), base(g, -H), head(g, 0.0);
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) head(i, j) = a * std::sin(std::numbers::pi * i * dx / L);
    RasterF ks(g, static_cast<float>(K));
    const double D = K * H / sy;
    const double lambda =
        4 * D / (dx * dx) * std::pow(std::sin(std::numbers::pi * dx / (2 * L)), 2);
    const double t = 1.0 / lambda;
    const std::vector<double> none(static_cast<std::size_t>(g.size()), 0.0);
    for (const int steps : {4, 64}) {
        for (const auto solver : {GroundwaterSolver::implicit, GroundwaterSolver::cvode}) {
            // CVODE restarts at every call; at 64 calls its error (~2e-3) is its tolerance's.
            if (solver == GroundwaterSolver::cvode && steps > 4) continue;
            INFO(name(solver) << ", " << steps << " steps");
            GroundwaterNumerics numerics = with(solver);
            numerics.substeps = 1;
            // The mode is 1 cm high: its solves must hold the heads to well below the default
            // tolerance (1e-5 m), or the comparison is of the tolerance, not of the time steps.
            numerics.head_tolerance_m = 1e-7;
            Groundwater gw(surface, base, head, ks, sy,
                           {GB::fixed_head, GB::fixed_head, GB::no_flow, GB::no_flow}, numerics);
            for (int k = 0; k < steps; ++k) gw.step(t / steps, none);
            const RasterD h = gw.head();
            const double z = -lambda * t / steps, gm = 2 - std::sqrt(2.0);
            const double ga = 1 / (gm * (2 - gm)), gb = ga - 1, gc = (1 - gm) / (2 - gm);
            const double r = (ga * (1 + gm * z / 2) / (1 - gm * z / 2) - gb) / (1 - gc * z);
            const double expected =
                solver == GroundwaterSolver::cvode ? std::exp(-1.0) : std::pow(r, steps);
            // CVODE holds the heads to ~1e-7 m of 1e-2, the implicit solver to ~1e-7 m here.
            const double eps = solver == GroundwaterSolver::cvode ? 1e-4 : 5e-4;
            CHECK(h(20, 1) / a == Approx(expected).epsilon(eps));
            CHECK(h(10, 0) / (a * std::sin(std::numbers::pi * 0.25)) ==
                  Approx(expected).epsilon(eps));
        }
    }
}

TEST_CASE("Hillslope recession follows the linearised Boussinesq solution",
          "[groundwater][verification]") {
    // A 1 km hillslope in 100 cells: a stream (fixed head) at x = 0, the divide (no flow) at the
    // far face; the water table starts 1 m above the stream everywhere and drains. Thick aquifer
    // (1 m of 200), so the linearised equation holds to ~0.5 %.
    const GroundwaterSolver solver =
        GENERATE(GroundwaterSolver::implicit, GroundwaterSolver::cvode);
    INFO(name(solver));
    const int n = 100;
    const double dx = 10, K = 2e-5, Hb = 200, H0 = 1, sy = 0.1;
    const GridSpec g{n + 1, 1, dx, 0, 0};
    const double L = (n + 0.5) * dx, T = K * Hb, D = T / sy;
    RasterD surface(g, 50.0), base(g, -Hb), head(g, H0);
    head(0, 0) = 0;
    RasterF ks(g, static_cast<float>(K));
    Groundwater gw(surface, base, head, ks, sy,
                   {GB::fixed_head, GB::no_flow, GB::no_flow, GB::no_flow}, with(solver));
    const std::vector<double> none(static_cast<std::size_t>(g.size()), 0.0);
    const double s0 = gw.storage_m3();
    double out = 0;
    const double day = 86400, t_end = 0.3 * L * L / D; // well into the first mode's decay
    const int days = static_cast<int>(std::ceil(t_end / day));
    for (int d = 0; d < days; ++d) out += gw.step(day, none).outflow_m3;
    const RasterD h = gw.head();
    const double t = days * day;
    double worst = 0;
    for (int i = 1; i <= n; ++i)
        worst = std::max(worst, std::abs(h(i, 0) - recession(i * dx, t, L, D, H0)));
    INFO(days << " days, divide at " << h(n, 0) << " m against " << recession(n * dx, t, L, D, H0));
    CHECK(worst < 0.01 * H0);
    CHECK(h(n, 0) == Approx(recession(n * dx, t, L, D, H0)).epsilon(0.01));
    CHECK(s0 - gw.storage_m3() == Approx(out).epsilon(1e-12));
}

TEST_CASE("A recharge mound rises as the linearised Boussinesq solution",
          "[groundwater][verification]") {
    const GroundwaterSolver solver =
        GENERATE(GroundwaterSolver::implicit, GroundwaterSolver::cvode);
    INFO(name(solver));
    // 1 km between two streams (fixed heads), 2 mm/day of recharge from t = 0.
    const int n = 101;
    const double dx = 10, K = 2e-5, Hb = 200, sy = 0.1, W = 0.002 / 86400;
    const GridSpec g{n, 1, dx, 0, 0};
    const double L = (n - 1) * dx, T = K * Hb, D = T / sy;
    RasterD surface(g, 50.0), base(g, -Hb), head(g, 0.0);
    RasterF ks(g, static_cast<float>(K));
    Groundwater gw(surface, base, head, ks, sy,
                   {GB::fixed_head, GB::fixed_head, GB::no_flow, GB::no_flow}, with(solver));
    const double day = 86400;
    const std::vector<double> recharge(static_cast<std::size_t>(g.size()), W * dx * dx * day);
    const double s0 = gw.storage_m3();
    double out = 0, added = 0;
    for (const double fraction : {0.05, 0.2, 1.0}) { // of L^2 / D
        const int days = static_cast<int>(std::ceil(fraction * L * L / D / day));
        for (int d = 0; d < days; ++d) {
            out += gw.step(day, recharge).outflow_m3;
            added += sum(recharge);
        }
    }
    const double t = day * (std::ceil(0.05 * L * L / D / day) + std::ceil(0.2 * L * L / D / day) +
                            std::ceil(L * L / D / day));
    const RasterD h = gw.head();
    const double peak = mound(L / 2, t, L, D, T, W);
    double worst = 0;
    for (int i = 0; i < n; ++i)
        worst = std::max(worst, std::abs(h(i, 0) - mound(i * dx, t, L, D, T, W)));
    INFO("peak " << h(n / 2, 0) << " m against " << peak);
    CHECK(worst < 0.01 * peak);
    CHECK(gw.storage_m3() - s0 + out == Approx(added).epsilon(1e-12));
}

TEST_CASE("The implicit solver follows the CVODE reference on fractal and white-noise terrain",
          "[groundwater][verification][slow]") {
    // A year of daily recharge (rain days drawn from a seeded generator, more in the hollows) on
    // 1 m cells with heterogeneous conductivity: the implicit solver's water table converges to the
    // reference's at (at least) second order in its step, is within 1 cm at the default steps,
    // seepage included, and both solvers close their budgets.
    const int terrain_kind = GENERATE(0, 1);
    const std::uint64_t seed = GENERATE(1, 2);
    const GridSpec g{32, 32, 1.0, 0, 0};
    std::mt19937_64 rng(seed);
    const auto [dem, ks] = test_aquifer(g, terrain_kind, 0.5, seed, rng);
    INFO((terrain_kind == 0 ? "fBm" : "white noise") << " terrain, seed " << seed);
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<Groundwater> runs;
    runs.emplace_back(dem, ks, 0.2, 10.0, 1.0, with(GroundwaterSolver::cvode));
    const std::vector<int> substeps = {1, 2, 4, 8};
    for (int n : substeps)
        runs.emplace_back(dem, ks, 0.2, 10.0, 1.0,
                          GroundwaterNumerics{GroundwaterSolver::implicit, n});
    std::vector<double> storage0, left(runs.size(), 0.0);
    for (const auto& r : runs) storage0.push_back(r.storage_m3());
    double added = 0;
    std::vector<double> recharge(static_cast<std::size_t>(g.size()));
    for (int d = 0; d < 365; ++d) {
        const bool rain = u(rng) < 0.3;
        const double mm = rain ? 2 + 20 * u(rng) : 0.0;
        for (std::int64_t c = 0; c < dem.size(); ++c)
            recharge[c] = mm * 1e-3 * (dem.data()[c] < 0 ? 1.5 : 0.5);
        added += sum(recharge);
        for (std::size_t k = 0; k < runs.size(); ++k) {
            const auto r = runs[k].step(86400, recharge);
            left[k] += r.outflow_m3 + sum(r.seepage_m3);
        }
    }
    const RasterD ref = runs[0].head();
    std::vector<double> worst;
    for (std::size_t k = 1; k < runs.size(); ++k) {
        const RasterD h = runs[k].head();
        double w = 0;
        for (std::int64_t c = 0; c < h.size(); ++c)
            w = std::max(w, std::abs(h.data()[c] - ref.data()[c]));
        worst.push_back(w);
    }
    REQUIRE(worst.size() == substeps.size());
    INFO("largest water-table differences at 1, 2, 4, 8 steps a day: "
         << worst[0] << ", " << worst[1] << ", " << worst[2] << ", " << worst[3] << " m");
    // Each halving of the step cuts the difference by more than 2 (second order would be 4),
    // until it nears the reference's own error (~2e-4 m after a year at CVODE's tolerances).
    for (std::size_t k = 1; k < substeps.size(); ++k)
        if (worst[k - 1] > 2e-3) CHECK(worst[k] / worst[k - 1] < 0.45);
    CHECK(worst[3] < 1e-3);
    // The default is 2 steps a day (worst[1]).
    REQUIRE(GroundwaterNumerics{}.substeps == 2);
    CHECK(worst[1] < 0.01);
    for (std::size_t k = 0; k < runs.size(); ++k)
        CHECK(runs[k].storage_m3() - storage0[k] + left[k] ==
              Approx(added).epsilon(k == 0 ? 1e-9 : 1e-12));
}

TEST_CASE("A water table pushed above the surface seeps out", "[groundwater]") {
    const GroundwaterSolver solver =
        GENERATE(GroundwaterSolver::implicit, GroundwaterSolver::cvode);
    INFO(name(solver));
    const GridSpec g{5, 5, 1.0, 0, 0};
    RasterD surface(g, 10.0);
    RasterF ks(g, 1e-5f);
    Groundwater gw(surface, ks, 0.2, 20.0, 0.5, with(solver));
    std::vector<double> recharge(static_cast<std::size_t>(g.size()), 0.0);
    recharge[12] = 1.0; // 1 m3 into the centre cell: 5 m of rise at S_y 0.2
    const double s0 = gw.storage_m3();
    const auto r = gw.step(60.0, recharge);
    const double seep = sum(r.seepage_m3);
    CHECK(seep > 0);
    CHECK(gw.head()(2, 2) <= 10.0);
    CHECK(gw.storage_m3() - s0 + r.outflow_m3 + seep == Approx(1.0).epsilon(1e-12));
}

namespace {
GroundwaterNumerics coarse(int factor, GroundwaterSolver s = GroundwaterSolver::implicit) {
    GroundwaterNumerics n = with(s);
    n.aquifer_cell_factor = factor;
    return n;
}
} // namespace

TEST_CASE("A recharge mound on an aquifer of coarser cells rises as the linearised Boussinesq "
          "solution",
          "[groundwater][verification]") {
    const GroundwaterSolver solver =
        GENERATE(GroundwaterSolver::implicit, GroundwaterSolver::cvode);
    INFO(name(solver));
    // The strip of the test above as 100 x 4 terrain cells of 10 m under 25 x 1 aquifer cells of
    // 40 m: the fixed heads are the outer aquifer cells, whose centres are 960 m apart, and each
    // terrain cell's head is interpolated between the aquifer cells' centres.
    const int f = 4, nx = 100;
    const double dx = 10, K = 2e-5, Hb = 200, sy = 0.1, W = 0.002 / 86400;
    const GridSpec g{nx, f, dx, 0, 0};
    const double x0 = f * dx / 2, L = (nx / f - 1) * f * dx, T = K * Hb, D = T / sy;
    RasterD surface(g, 50.0), base(g, -Hb), head(g, 0.0);
    RasterF ks(g, static_cast<float>(K));
    Groundwater gw(surface, base, head, ks, sy,
                   {GB::fixed_head, GB::fixed_head, GB::no_flow, GB::no_flow}, coarse(f, solver));
    const double day = 86400;
    const std::vector<double> recharge(static_cast<std::size_t>(g.size()), W * dx * dx * day);
    const double s0 = gw.storage_m3();
    double out = 0, added = 0;
    const int days = static_cast<int>(std::ceil(0.3 * L * L / D / day));
    for (int d = 0; d < days; ++d) {
        out += gw.step(day, recharge).outflow_m3;
        added += sum(recharge);
    }
    const RasterD h = gw.head();
    const double t = days * day, peak = mound(L / 2, t, L, D, T, W);
    double worst = 0;
    for (int j = 0; j < g.ny; ++j)
        for (int i = 0; i < nx; ++i) {
            const double x = (i + 0.5) * dx - x0; // from the west fixed head's centre
            if (x < 0 || x > L) continue;         // outside the two fixed heads' centres
            worst = std::max(worst, std::abs(h(i, j) - mound(x, t, L, D, T, W)));
        }
    INFO("peak " << h(nx / 2, 0) << " m against " << peak << "; worst difference " << worst);
    CHECK(worst < 0.01 * peak);
    // The recharge onto the fixed-head aquifer cells leaves at once, counted in the outflow.
    CHECK(gw.storage_m3() - s0 + out == Approx(added).epsilon(1e-12));
}

TEST_CASE("An aquifer of coarser cells follows the terrain-cell solution on fractal and "
          "white-noise terrain",
          "[groundwater][verification][slow]") {
    // A year of daily recharge as in the test against CVODE above (rain days from a seeded
    // generator, three times as much in the hollows, heterogeneous conductivity) on 64 x 64
    // terrain cells of 1 m under aquifer cells of 1, 2 and 4 m: a shallow table (1 m down, 10 m
    // of aquifer: much of the fractal terrain seeps) and a deeper one (3 m down, 20 m, half the
    // recharge). Every run closes its budget (seepage included) to rounding. The coarser
    // aquifers' water tables, interpolated to the terrain cells, stay close to the 1 m solution
    // inside the domain (the outer 8 m are left out: there the fixed heads are 1 m cells on one
    // side and a band of aquifer cells on the other), closer with 2 m cells than with 4 m on
    // fractal terrain (on white noise the two are alike: no 2 m cell resolves it either), and
    // the water that seeps and leaves stays within a few percent of the recharge.
    const int terrain_kind = GENERATE(0, 1);
    const bool shallow = GENERATE(true, false);
    const std::uint64_t seed = GENERATE(1, 2);
    const GridSpec g{64, 64, 1.0, 0, 0};
    std::mt19937_64 rng(seed);
    const auto [dem, ks] = test_aquifer(g, terrain_kind, 1.0, seed, rng);
    INFO((terrain_kind == 0 ? "fBm" : "white noise")
         << " terrain, seed " << seed << ", " << (shallow ? "shallow" : "deeper") << " table");
    std::uniform_real_distribution<double> u(0, 1);
    const double thickness = shallow ? 10 : 20, depth = shallow ? 1 : 3, scale = shallow ? 1 : 0.5;
    std::vector<Groundwater> runs;
    for (int f : {1, 2, 4}) runs.emplace_back(dem, ks, 0.2, thickness, depth, coarse(f));
    runs.emplace_back(dem, ks, 0.2, thickness, depth, coarse(4, GroundwaterSolver::cvode));
    std::vector<double> storage0, left(runs.size(), 0.0);
    for (const auto& r : runs) storage0.push_back(r.storage_m3());
    double added = 0;
    std::vector<double> recharge(static_cast<std::size_t>(g.size()));
    for (int d = 0; d < 365; ++d) {
        const double mm = u(rng) < 0.3 ? 2 + 20 * u(rng) : 0.0;
        for (std::int64_t c = 0; c < dem.size(); ++c)
            recharge[c] = scale * mm * 1e-3 * (dem.data()[c] < 0 ? 1.5 : 0.5);
        added += sum(recharge);
        for (std::size_t k = 0; k < runs.size(); ++k) {
            const auto r = runs[k].step(86400, recharge);
            left[k] += r.outflow_m3 + sum(r.seepage_m3);
        }
    }
    const RasterD ref = runs[0].head();
    std::vector<double> rms;
    std::vector<int> at_surface(runs.size(), 0); // terrain cells whose table meets the surface
    for (std::size_t k = 0; k < runs.size(); ++k) {
        CAPTURE(k);
        CHECK(runs[k].storage_m3() - storage0[k] + left[k] ==
              Approx(added).epsilon(k == 3 ? 1e-9 : 1e-12));
        const RasterD h = runs[k].head();
        double ss = 0;
        int n = 0;
        for (int j = 8; j < g.ny - 8; ++j)
            for (int i = 8; i < g.nx - 8; ++i, ++n) ss += std::pow(h(i, j) - ref(i, j), 2);
        double above = 0; // the water table stands at most at the surface
        for (std::int64_t c = 0; c < h.size(); ++c)
            above = std::max(above, h.data()[c] - dem.data()[c]);
        CHECK(above == 0);
        for (std::int64_t c = 0; c < h.size(); ++c) at_surface[k] += h.data()[c] == dem.data()[c];
        rms.push_back(std::sqrt(ss / n));
    }
    INFO("water table rms off the 1 m solution inside the domain, aquifer cells of 2 m, 4 m and "
         "4 m with cvode: "
         << rms[1] << ", " << rms[2] << ", " << rms[3] << " m; seepage + outflow " << left[1]
         << ", " << left[2] << ", " << left[3] << " m3 against " << left[0]
         << " m3 of 1 m cells, of " << added << " m3 of recharge; the table at the surface on "
         << at_surface[2] << " terrain cells with 4 m aquifer cells, " << at_surface[0]
         << " with 1 m");
    CHECK(rms[1] < 0.06);
    CHECK(rms[2] < 0.12);
    CHECK(rms[1] < rms[2] + 0.005); // smaller cells, closer (white noise: the same to ~3 mm)
    CHECK(std::abs(rms[3] - rms[2]) < 0.01); // the two solvers of the same 4 m aquifer agree
    for (std::size_t k = 1; k < runs.size(); ++k) CHECK(std::abs(left[k] - left[0]) < 0.05 * added);
    // Where much of the terrain seeps, the wet ground (the table at the surface) covers about as
    // many terrain cells (a seeping terrain cell is one whose table meets the surface).
    if (at_surface[0] >= 50) {
        CHECK(at_surface[2] > 0.8 * at_surface[0]);
        CHECK(at_surface[2] < 1.2 * at_surface[0]);
    }
}

TEST_CASE("An aquifer cell factor that does not divide the terrain is refused", "[groundwater]") {
    const GridSpec g{10, 12, 1.0, 0, 0};
    RasterD surface(g, 10.0);
    RasterF ks(g, 1e-5f);
    CHECK_THROWS_WITH(
        Groundwater(surface, ks, 0.2, 20.0, 0.5, coarse(4)),
        Catch::Contains("aquifer cell factor 4 does not divide the terrain's 10 x 12"));
    CHECK_NOTHROW(Groundwater(surface, ks, 0.2, 20.0, 0.5, coarse(2)));
}
