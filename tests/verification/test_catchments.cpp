// Catchments against analytic cases and against the brute-force reference on random DEMs.
#include "support/brute_force_pond.hpp"

#include "ecoterra/hydro/catchments.hpp"
#include "ecoterra/random.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <set>

using namespace ecoterra;
using namespace ecoterra::hydro;
using ecoterra::GridSpec;
using ecoterra::RasterD;

namespace {

RasterD box_dem() {
    // A 10 x 8 plateau at 10 m with a 4 x 3 basin at 9 m and a 1-cell notch at 9.5 m.
    RasterD z(GridSpec{10, 8, 1.0, 0, 0}, 10.0);
    for (int j = 2; j < 5; ++j)
        for (int i = 3; i < 7; ++i) z(i, j) = 9.0;
    z(4, 3) = 8.9; // the pit
    return z;
}

} // namespace

TEST_CASE("A basin fills to the level its volume gives", "[catchments]") {
    const RasterD z = box_dem();
    Catchments c(z);
    const std::int64_t pit = cell_index(z.grid(), 4, 3);
    REQUIRE(c.flow().is_pit(pit));
    c.add_to_pit(pit, 1.2); // 12 cells: 0.1 above the pit, then 11 + 1 cells at 9.0 ... 9.x
    c.equilibrate();
    REQUIRE(c.catchments().size() == 1);
    // V = sum (h - z): (h - 8.9) + 11 (h - 9) = 1.2  =>  h = (1.2 + 8.9 + 99) / 12
    CHECK(c.catchments()[0].level_m == Approx((1.2 + 8.9 + 99.0) / 12.0).epsilon(1e-12));
    const RasterD d = c.depth_map();
    CHECK(d(4, 3) == Approx(c.catchments()[0].level_m - 8.9));
    CHECK(d(0, 0) == 0.0);
    CHECK(c.id_map()(5, 4) == c.catchments()[0].id);
    // Shrinking: take water out, the level falls and the body shrinks to the pit.
    c.remove_water(c.catchments()[0].id, 1.15);
    c.equilibrate();
    CHECK(c.catchments()[0].level_m == Approx(8.95).epsilon(1e-12));
    CHECK(c.id_map()(5, 4) == 0);
}

TEST_CASE("A full basin spills over the lowest rim cell and loses water off the edge",
          "[catchments]") {
    RasterD z = box_dem();
    for (int j = 0; j < 3; ++j) z(6, j) = 9.5; // a channel at 9.5 m from the basin to the edge
    z(6, 0) = 9.5;
    Catchments c(z);
    c.add_to_pit(cell_index(z.grid(), 4, 3), 100.0);
    c.equilibrate();
    REQUIRE(c.catchments().size() == 1);
    CHECK(c.catchments()[0].level_m == Approx(9.5));
    CHECK_FALSE(c.catchments()[0].dynamic);
    // Conservation: stored + lost = added.
    CHECK(c.total_volume_m3() + c.lost_m3() == Approx(100.0).epsilon(1e-12));
}

TEST_CASE("Two basins: the first spills into the second, then they merge", "[catchments]") {
    // Two pits separated by a saddle at 5 m inside a rim at 20 m.
    RasterD z(GridSpec{12, 7, 1.0, 0, 0}, 20.0);
    for (int j = 1; j < 6; ++j)
        for (int i = 1; i < 11; ++i) z(i, j) = 6.0;
    for (int j = 1; j < 6; ++j) z(6, j) = 7.0; // a ridge ...
    z(6, 3) = 6.5;                             // ... with a saddle
    z(3, 3) = 1.0;                             // pit A (west)
    z(9, 3) = 2.0;                             // pit B (east)
    const std::int64_t a = cell_index(z.grid(), 3, 3), b = cell_index(z.grid(), 9, 3);
    Catchments c(z);
    // A little water in A only: it stays there.
    c.add_to_pit(a, 2.0);
    c.equilibrate();
    REQUIRE(c.catchments().size() == 1);
    CHECK(c.catchments()[0].level_m == Approx(3.0));
    // A's basin holds 5 m3 below the plateau and 17.5 m3 up to the saddle (6.5 m); B's holds 14.
    // With 25 m3 in A, A fills to the saddle and spills 7.5 m3 into B, which stays below it.
    c.add_to_pit(a, 23.0);
    c.equilibrate();
    REQUIRE(c.catchments().size() == 2);
    const auto ids = c.id_map();
    CHECK(ids(3, 3) != ids(9, 3));
    auto holds = [&c](const Catchment& k, std::int64_t pit) {
        const auto seeds = c.seeds(k);
        return std::find(seeds.begin(), seeds.end(), pit) != seeds.end();
    };
    REQUIRE(holds(c.catchments()[0], a) != holds(c.catchments()[1], a));
    const auto& ka = holds(c.catchments()[0], a) ? c.catchments()[0] : c.catchments()[1];
    const auto& kb = holds(c.catchments()[0], a) ? c.catchments()[1] : c.catchments()[0];
    CHECK(ka.level_m == Approx(6.5));
    CHECK(ka.volume_m3 == Approx(17.5));
    CHECK(kb.volume_m3 == Approx(7.5));
    CHECK(kb.level_m == Approx(6.0 + 3.5 / 20.0));
    // Much more: both basins fill to the saddle and merge into one lake over the saddle.
    c.add_to_pit(b, 200.0);
    c.equilibrate();
    REQUIRE(c.catchments().size() == 1);
    CHECK(holds(c.catchments()[0], a));
    CHECK(holds(c.catchments()[0], b));
    CHECK(c.catchments()[0].level_m > 6.5);
    CHECK(c.total_volume_m3() + c.lost_m3() == Approx(225.0).epsilon(1e-12));
    // Drain it to 6 m3, below the plateau: only the two pit holes hold water, at one level h with
    // (h - 1) + (h - 2) = 6, h = 4.5. It splits (breadth-first search) into two bodies.
    c.remove_water(c.catchments()[0].id, c.total_volume_m3() - 6.0);
    c.equilibrate();
    REQUIRE(c.catchments().size() == 2);
    CHECK(c.catchments()[0].level_m == Approx(4.5));
    CHECK(c.catchments()[1].level_m == Approx(4.5));
    CHECK(c.catchments()[0].volume_m3 + c.catchments()[1].volume_m3 == Approx(6.0));
    const auto split_ids = c.id_map();
    CHECK(split_ids(3, 3) != split_ids(9, 3));
    CHECK(split_ids(3, 3) != 0);
    CHECK(split_ids(9, 3) != 0);
}

TEST_CASE("Ponding equals the brute-force reference on random DEMs", "[catchments][verification]") {
    int compared = 0, with_spills = 0;
    for (std::uint64_t seed = 1; seed <= 60; ++seed) {
        Rng rng(seed, "test.pond");
        const int nx = 8 + static_cast<int>(rng.below(10)),
                  ny = 8 + static_cast<int>(rng.below(10));
        RasterD z(GridSpec{nx, ny, 1.0 + rng.uniform(), 0, 0});
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i)
                z(i, j) = rng.uniform(0.0, 1.0) + 0.05 * std::sin(0.7 * i) * std::cos(0.9 * j);
        const double depth = rng.uniform(0.01, 0.6);
        const Catchments c = pond(z, depth, Routing::d8);
        const auto ref = test::brute_force_pond(z, depth);
        // The same water added in two halves (the second update starts from the first's
        // regions) reaches the same equilibrium.
        Catchments two(z);
        std::vector<double> half(static_cast<std::size_t>(z.size()),
                                 0.5 * depth * z.cell_size() * z.cell_size());
        two.add_routed(route_to_pits(two.flow(), half, Routing::d8));
        two.equilibrate();
        two.add_routed(route_to_pits(two.flow(), half, Routing::d8));
        two.equilibrate();
        const RasterD d2 = two.depth_map();
        const RasterD d = c.depth_map();
        CAPTURE(seed, nx, ny, depth);
        double worst = 0;
        for (std::int64_t k = 0; k < z.size(); ++k)
            worst = std::max(worst, std::abs(d.data()[k] - ref.depth_m[k]));
        CHECK(worst < 1e-7);
        double worst2 = 0;
        for (std::int64_t k = 0; k < z.size(); ++k)
            worst2 = std::max(worst2, std::abs(d2.data()[k] - ref.depth_m[k]));
        CHECK(worst2 < 1e-7);
        // Stored volume equals the integral of the depth map.
        double integral = 0;
        for (std::int64_t k = 0; k < z.size(); ++k)
            integral += d.data()[k] * z.cell_size() * z.cell_size();
        CHECK(integral == Approx(c.total_volume_m3()).epsilon(1e-9).margin(1e-12));
        CHECK(c.lost_m3() == Approx(ref.lost_m3).epsilon(1e-9).margin(1e-9));
        CHECK(c.total_volume_m3() == Approx(ref.stored_m3).epsilon(1e-9).margin(1e-9));
        const double input = depth * z.cell_size() * z.cell_size() * static_cast<double>(z.size());
        CHECK(c.total_volume_m3() + c.lost_m3() == Approx(input).epsilon(1e-12));
        ++compared;
        // Count DEMs where some lake spilled into another (a lake with more than one seed, or a
        // lake that received water by spilling).
        for (const auto& k : c.catchments()) with_spills += c.seeds(k).size() > 1;
    }
    CHECK(compared == 60);
    CHECK(with_spills > 10);
}
