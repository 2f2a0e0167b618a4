// Groundwater against the Dupuit mound and a decaying mode.
#include "ecoterra/hydro/groundwater.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>

using namespace ecoterra;
using namespace ecoterra::hydro;
using ecoterra::GridSpec;
using ecoterra::RasterD;
using GB = GroundwaterBoundary;

TEST_CASE("Steady Dupuit mound under uniform recharge between fixed heads",
          "[groundwater][verification]") {
    // h(x)^2 = h0^2 + (W / K) x (L - x), x from the west boundary cell centre, L = (nx - 1) dx.
    const int nx = 41, ny = 3;
    const double dx = 10, K = 1e-4, W = 1e-8, h0 = 10, sy = 0.2;
    const GridSpec g{nx, ny, dx, 0, 0};
    RasterD surface(g, 100.0), base(g, 0.0), head(g, h0);
    RasterF ks(g, static_cast<float>(K));
    Groundwater gw(surface, base, head, ks, sy,
                   {GB::fixed_head, GB::fixed_head, GB::no_flow, GB::no_flow});
    const double dt = 1e6; // s
    std::vector<double> recharge(static_cast<std::size_t>(g.size()), W * dx * dx * dt);
    double out = 0, added = 0;
    const double s0 = gw.storage_m3();
    for (int k = 0; k < 60; ++k) {
        const auto r = gw.step(dt, recharge);
        out += r.outflow_m3;
        for (double v : recharge) added += v; // recharge on fixed heads leaves at once
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
    CHECK(h(20, 1) == Approx(std::sqrt(h0 * h0 + W / K * 200 * 200)).epsilon(1e-6));
    // Conservation: what was added is stored or left through the fixed heads.
    CHECK(gw.storage_m3() - s0 + out == Approx(added).epsilon(1e-9));
    // At steady state the outflow equals the recharge.
    const auto last = gw.step(dt, recharge);
    double step_added = 0;
    for (double v : recharge) step_added += v;
    CHECK(last.outflow_m3 == Approx(step_added).epsilon(1e-5));
}

TEST_CASE("A sine mode of the water table decays at the discrete diffusion rate",
          "[groundwater][verification]") {
    // Thick aquifer (T ~ K H constant): linear diffusion with D = K H / S_y. The discrete mode
    // sin(pi x / L) decays as exp(-lambda t), lambda = (4 D / dx^2) sin^2(pi dx / (2 L)).
    const int nx = 41, ny = 3;
    const double dx = 10, K = 1e-4, H = 1000, a = 0.01, sy = 0.2;
    const GridSpec g{nx, ny, dx, 0, 0};
    const double L = (nx - 1) * dx;
    RasterD surface(g, 50.0), base(g, -H), head(g, 0.0);
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) head(i, j) = a * std::sin(std::numbers::pi * i * dx / L);
    RasterF ks(g, static_cast<float>(K));
    Groundwater gw(surface, base, head, ks, sy,
                   {GB::fixed_head, GB::fixed_head, GB::no_flow, GB::no_flow});
    const double D = K * H / sy;
    const double lambda =
        4 * D / (dx * dx) * std::pow(std::sin(std::numbers::pi * dx / (2 * L)), 2);
    const double t = 1.0 / lambda;
    const std::vector<double> none(static_cast<std::size_t>(g.size()), 0.0);
    for (int k = 0; k < 4; ++k) gw.step(t / 4, none);
    const RasterD h = gw.head();
    CHECK(h(20, 1) / a == Approx(std::exp(-1.0)).epsilon(1e-4));
    CHECK(h(10, 0) / (a * std::sin(std::numbers::pi * 0.25)) ==
          Approx(std::exp(-1.0)).epsilon(1e-4));
}

TEST_CASE("A water table pushed above the surface seeps out", "[groundwater]") {
    const GridSpec g{5, 5, 1.0, 0, 0};
    RasterD surface(g, 10.0);
    RasterF ks(g, 1e-5f);
    Groundwater gw(surface, ks, 0.2, 20.0, 0.5);
    std::vector<double> recharge(static_cast<std::size_t>(g.size()), 0.0);
    recharge[12] = 1.0; // 1 m3 into the centre cell: 5 m of rise at S_y 0.2
    const double s0 = gw.storage_m3();
    const auto r = gw.step(60.0, recharge);
    double seep = 0;
    for (double s : r.seepage_m3) seep += s;
    CHECK(seep > 0);
    CHECK(gw.head()(2, 2) <= 10.0);
    CHECK(gw.storage_m3() - s0 + r.outflow_m3 + seep == Approx(1.0).epsilon(1e-9));
}
