// The depression hierarchy's invariants, and the catchments it carries checked with Boost.Graph:
// after filling and draining, each catchment is one connected water body and no two touch.
#include "ecoterra/hydro/catchments.hpp"
#include "ecoterra/hydro/depressions.hpp"
#include "ecoterra/hydro/hydrology.hpp"
#include "ecoterra/random.hpp"
#include "ecoterra/terrain/weierstrass.hpp"

#include <boost/graph/adjacency_list.hpp>
#include <boost/graph/connected_components.hpp>
#include <catch2/catch.hpp>
#include <omp.h>

#include <cmath>
#include <map>
#include <queue>
#include <set>

using namespace ecoterra;
using namespace ecoterra::hydro;
using ecoterra::GridSpec;
using ecoterra::RasterD;

namespace {

RasterD random_dem(std::uint64_t seed) {
    Rng rng(seed, "test.depressions");
    const int nx = 10 + static_cast<int>(rng.below(20)), ny = 10 + static_cast<int>(rng.below(20));
    RasterD z(GridSpec{nx, ny, 0.5 + rng.uniform(), 0, 0});
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i)
            z(i, j) = rng.uniform(0.0, 1.0) + 0.3 * std::sin(0.5 * i) * std::cos(0.4 * j);
    return z;
}

bool is_ancestor_or_self(const DepressionHierarchy& dh, std::int32_t a, std::int32_t n) {
    for (; n >= 0; n = dh.parent(n))
        if (n == a) return true;
    return false;
}

} // namespace

TEST_CASE("Depression hierarchy: outlets rise, capacities add, bands hold every floodable cell",
          "[catchments][depressions]") {
    for (std::uint64_t seed = 1; seed <= 30; ++seed) {
        const RasterD z = random_dem(seed);
        const FlowDirections fd(z);
        const DepressionHierarchy dh(fd);
        CAPTURE(seed);
        REQUIRE(dh.leaf_count() > 0);
        for (std::int32_t n = 0; n < dh.node_count(); ++n) {
            const std::int32_t p = dh.parent(n);
            if (p >= 0) {
                CHECK(dh.outlet_z(p) >= dh.outlet_z(n));
                CHECK(dh.capacity(p) >= dh.base_capacity(p) - 1e-12);
                CHECK((dh.child(p, 0) == n || dh.child(p, 1) == n));
                // The overflow leaf lies on the sibling's side.
                CHECK(is_ancestor_or_self(dh, dh.sibling(n), dh.overflow_leaf(n)));
            } else if (dh.overflow_leaf(n) >= 0) {
                // A top-level depression spills into another tree that drains to the edge over a
                // pass no higher than its own.
                std::int32_t t = dh.overflow_leaf(n);
                CHECK(dh.is_leaf(t));
                CHECK_FALSE(is_ancestor_or_self(dh, n, t));
                while (dh.parent(t) >= 0) t = dh.parent(t);
                CHECK(dh.outlet_z(t) <= dh.outlet_z(n));
            }
        }
        // Capacity by brute force: the water above every cell of the subtree below the outlet.
        for (std::int32_t n = 0; n < dh.node_count(); ++n) {
            double cap = 0;
            for (std::int64_t c = 0; c < z.size(); ++c) {
                const std::int32_t l = dh.leaf_of(c);
                if (l >= 0 && is_ancestor_or_self(dh, n, l) && z.data()[c] < dh.outlet_z(n))
                    cap += dh.outlet_z(n) - z.data()[c];
            }
            CHECK(dh.capacity(n) == Approx(cap).epsilon(1e-12).margin(1e-12));
        }
        for (std::int64_t c = 0; c < z.size(); ++c) {
            const std::int32_t n = dh.node_of(c), l = dh.leaf_of(c);
            if (fd.is_outlet(c)) CHECK(l == -1);
            if (n < 0) continue;
            CHECK(is_ancestor_or_self(dh, n, l));
            CHECK(z.data()[c] < dh.outlet_z(n));
            if (!dh.is_leaf(n)) CHECK(z.data()[c] >= dh.base_z(n));
        }
    }
}

TEST_CASE("Drained catchments are the connected components of the wet cells (Boost.Graph)",
          "[catchments][depressions][verification]") {
    int splits = 0;
    for (std::uint64_t seed = 1; seed <= 40; ++seed) {
        const RasterD z = random_dem(seed + 100);
        Rng rng(seed, "test.drain");
        Catchments c = pond(z, rng.uniform(0.05, 0.5), Routing::d8);
        const std::size_t before = c.catchments().size();
        // Take a random share of each catchment's water.
        std::vector<std::pair<std::int32_t, double>> take;
        for (const auto& k : c.catchments())
            take.emplace_back(k.id, rng.uniform(0.2, 0.95) * k.volume_m3);
        for (const auto& [id, v] : take) c.remove_water(id, v);
        c.equilibrate();
        splits += c.catchments().size() > before;
        CAPTURE(seed);
        // Wet cells and their 8-neighbour graph.
        const RasterD d = c.depth_map();
        const auto ids = c.id_map();
        std::vector<std::int64_t> wet;
        std::map<std::int64_t, std::size_t> vid;
        for (std::int64_t k = 0; k < z.size(); ++k)
            if (d.data()[k] > 0) {
                vid[k] = wet.size();
                wet.push_back(k);
            }
        boost::adjacency_list<boost::vecS, boost::vecS, boost::undirectedS> graph(wet.size());
        const auto& g = z.grid();
        for (std::size_t v = 0; v < wet.size(); ++v) {
            const int i = static_cast<int>(wet[v] % g.nx), j = static_cast<int>(wet[v] / g.nx);
            z.for_moore(i, j, [&](int a, int b) {
                const auto it = vid.find(cell_index(g, a, b));
                if (it != vid.end() && it->second > v) boost::add_edge(v, it->second, graph);
            });
        }
        std::vector<int> comp(wet.size());
        const int n_comp = wet.empty() ? 0 : boost::connected_components(graph, comp.data());
        // One id per component and one component per id.
        std::map<int, std::set<std::int32_t>> ids_of_comp;
        std::map<std::int32_t, std::set<int>> comps_of_id;
        for (std::size_t v = 0; v < wet.size(); ++v) {
            ids_of_comp[comp[v]].insert(ids.data()[wet[v]]);
            comps_of_id[ids.data()[wet[v]]].insert(comp[v]);
        }
        for (const auto& [cc, s] : ids_of_comp) CHECK(s.size() == 1);
        for (const auto& [id, s] : comps_of_id) {
            CHECK(id != 0);
            CHECK(s.size() == 1);
        }
        CHECK(static_cast<int>(comps_of_id.size()) == n_comp);
        // Each catchment's volume is the water above its own cells.
        for (const auto& k : c.catchments()) {
            double v = 0;
            c.for_each_wet_cell(
                k, [&](std::int64_t cell) { v += std::max(0.0, k.level_m - z.data()[cell]); });
            CHECK(v * c.cell_area_m2() == Approx(k.volume_m3).epsilon(1e-9).margin(1e-12));
        }
    }
    CHECK(splits > 3);
}

TEST_CASE("The daily update gives the same bits on one and two threads",
          "[hydrology][determinism]") {
    // 384^2 cells: enough blocks for the parallel loops to run on both threads.
    const GridSpec g{384, 384, 1.0, 0, 0};
    terrain::MultifractalParams p = terrain::majhor2023_params(2.45);
    p.relief_m = 6.0;
    const RasterD dem = terrain::multifractal_generate(g, p, 11).z;
    const SoilMap soil = uniform_soil(g, SoilComposition{30, 50, 20, 6.0, {}});
    auto run = [&](int threads) {
        omp_set_num_threads(threads);
        HydrologyModel m(dem, soil, RasterD(g, 0.4), HydrologyOptions{},
                         climate_preset("humid_subtropical"));
        WeatherGenerator wg(climate_preset("humid_subtropical"), 9);
        std::vector<DailyFluxes> out;
        for (int d = 0; d < 40; ++d) out.push_back(m.step(wg.next()));
        return std::make_pair(out, m.soil_moisture());
    };
    const auto a = run(1), b = run(2);
    omp_set_num_threads(2);
    double rain = 0;
    for (std::size_t d = 0; d < a.first.size(); ++d) {
        CHECK(a.first[d].evaporation == b.first[d].evaporation);
        CHECK(a.first[d].infiltration == b.first[d].infiltration);
        CHECK(a.first[d].d_surface == b.first[d].d_surface);
        rain += a.first[d].rain;
    }
    REQUIRE(rain > 0);
    std::int64_t differ = 0;
    for (std::int64_t k = 0; k < dem.size(); ++k)
        differ += a.second.data()[k] != b.second.data()[k];
    CHECK(differ == 0);
}

namespace {

/// Priority-flood depression filling (Barnes, Lehman & Mulla 2014) from the domain edge: every
/// interior cell raised to the lowest level at which water on it can leave.
RasterD priority_flood_fill(const RasterD& z) {
    RasterD w = z;
    const auto& g = z.grid();
    using Entry = std::pair<double, std::int64_t>;
    std::priority_queue<Entry, std::vector<Entry>, std::greater<>> open;
    std::vector<char> closed(static_cast<std::size_t>(z.size()), 0);
    for (int j = 0; j < g.ny; ++j)
        for (int i = 0; i < g.nx; ++i)
            if (i == 0 || j == 0 || i == g.nx - 1 || j == g.ny - 1) {
                open.emplace(z(i, j), cell_index(g, i, j));
                closed[cell_index(g, i, j)] = 1;
            }
    while (!open.empty()) {
        // (Not a structured binding: clang 14 cannot capture one in the lambda below.)
        const double h = open.top().first;
        const auto c = open.top().second;
        open.pop();
        z.for_moore(static_cast<int>(c % g.nx), static_cast<int>(c / g.nx), [&](int a, int b) {
            const std::int64_t n = cell_index(g, a, b);
            if (closed[n]) return;
            closed[n] = 1;
            w.data()[n] = std::max(z.data()[n], h);
            open.emplace(w.data()[n], n);
        });
    }
    return w;
}

RasterD integer_dem(std::uint64_t seed) {
    RasterD z = random_dem(seed);
    for (std::int64_t k = 0; k < z.size(); ++k) z.data()[k] = std::floor(10.0 * z.data()[k]);
    return z;
}

} // namespace

TEST_CASE("Fill-Spill-Merge's own test DEM: depression volumes and the water reaching each pit",
          "[catchments][depressions][verification]") {
    // The 10 x 10 DEM of the "MoveWaterIntoPits 1" case in Barnes, Callaghan & Wickert's
    // Fill-Spill-Merge unit tests (edges -9, the ocean). With 1 m of water on every cell, FSM
    // reports 64 m3 reaching the ocean, 30 and 6 m3 reaching its two depressions, depression
    // volumes of 73 and 2 m3, and 111 m3 for the meta-depression holding both.
    const double t[10][10] = {
        {-9, -9, -9, -9, -9, -9, -9, -9, -9, -9}, {-9, 9, 9, 9, 9, 9, 9, 9, 9, -9},
        {-9, 9, 8, 8, 8, 8, 7, 6, 9, -9},         {-9, 9, 8, 7, 8, 7, 6, 5, 9, -9},
        {-9, 9, 8, 7, 8, 6, 5, 4, 9, -9},         {-9, 9, 8, 8, 8, 5, 4, 3, 9, -9},
        {-9, 9, 7, 6, 5, 4, 3, 2, 9, -9},         {-9, 9, 7, 6, 5, 4, 3, 1, 9, -9},
        {-9, 9, 9, 9, 9, 9, 9, 9, 9, -9},         {-9, -9, -9, -9, -9, -9, -9, -9, -9, -9}};
    RasterD z(GridSpec{10, 10, 1.0, 0, 0});
    for (int j = 0; j < 10; ++j)
        for (int i = 0; i < 10; ++i) z(i, j) = t[j][i];
    const FlowDirections fd(z);
    const DepressionHierarchy dh(fd);
    REQUIRE(dh.leaf_count() == 2);
    REQUIRE(dh.node_count() == 3);
    const std::int32_t big = dh.leaf_of(cell_index(z.grid(), 7, 7)),
                       small = dh.leaf_of(cell_index(z.grid(), 3, 4));
    REQUIRE(big != small);
    CHECK(dh.capacity(big) == Approx(73.0));
    CHECK(dh.capacity(small) == Approx(2.0));
    CHECK(dh.parent(big) == 2);
    CHECK(dh.parent(small) == 2);
    CHECK(dh.capacity(2) == Approx(111.0));
    CHECK(dh.parent(2) == -1);
    std::vector<double> one(static_cast<std::size_t>(z.size()), 1.0);
    const RoutedWater r = route_to_pits(fd, one, Routing::d8);
    CHECK(r.lost_m3 == Approx(64.0));
    double at_big = 0, at_small = 0;
    for (std::int64_t c = 0; c < z.size(); ++c) {
        if (r.at_pit_m3[c] <= 0) continue;
        (dh.leaf_of(c) == big ? at_big : at_small) += r.at_pit_m3[c];
    }
    CHECK(at_big == Approx(30.0));
    CHECK(at_small == Approx(6.0));
}

TEST_CASE("Heavy flooding fills every depression to the priority-flood surface",
          "[catchments][depressions][verification]") {
    // Fill-Spill-Merge's own check: with far more water than the depressions hold, the water
    // surface is the depression-filled DEM.
    for (std::uint64_t seed = 1; seed <= 40; ++seed) {
        const RasterD z = seed % 2 ? random_dem(seed + 300) : integer_dem(seed + 300);
        const Catchments c = pond(z, 50.0, Routing::d8);
        const RasterD filled = priority_flood_fill(z), d = c.depth_map();
        double worst = 0;
        for (std::int64_t k = 0; k < z.size(); ++k)
            worst = std::max(worst, std::abs(z.data()[k] + d.data()[k] - filled.data()[k]));
        CAPTURE(seed);
        CHECK(worst < 1e-9);
    }
}

TEST_CASE("Ponding the ponded water again changes nothing, flats included",
          "[catchments][depressions][verification]") {
    // Fill-Spill-Merge's repeated-run check, on integer-valued DEMs full of flats.
    for (std::uint64_t seed = 1; seed <= 40; ++seed) {
        const RasterD z = integer_dem(seed + 500);
        const Catchments first = pond(z, 0.4, Routing::d8);
        const RasterD d1 = first.depth_map();
        Catchments again(z);
        for (std::int64_t k = 0; k < z.size(); ++k)
            again.add_water(k, d1.data()[k] * again.cell_area_m2());
        again.equilibrate();
        const RasterD d2 = again.depth_map();
        double worst = 0;
        for (std::int64_t k = 0; k < z.size(); ++k)
            worst = std::max(worst, std::abs(d1.data()[k] - d2.data()[k]));
        CAPTURE(seed);
        CHECK(worst < 1e-9);
        CHECK(again.total_volume_m3() == Approx(first.total_volume_m3()).epsilon(1e-12));
    }
}
