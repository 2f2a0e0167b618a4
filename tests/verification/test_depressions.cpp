// The depression hierarchy's invariants, and the catchments it carries checked with Boost.Graph:
// after filling and draining, each catchment is one connected water body and no two touch.
#include "ecoterra/hydro/catchments.hpp"
#include "ecoterra/hydro/hydrology.hpp"
#include "ecoterra/random.hpp"
#include "ecoterra/terrain/weierstrass.hpp"

#include <boost/graph/adjacency_list.hpp>
#include <boost/graph/connected_components.hpp>
#include <catch2/catch.hpp>
#include <omp.h>

#include <cmath>
#include <map>
#include <set>

using namespace ecoterra;
using namespace ecoterra::hydro;
using terrain::GridSpec;
using terrain::RasterD;

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
            } else {
                CHECK(dh.overflow_leaf(n) == -1);
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
            c.for_each_wet_cell(k, [&](std::int64_t cell) {
                v += std::max(0.0, k.level_m - z.data()[cell]);
            });
            CHECK(v * c.cell_area_m2() == Approx(k.volume_m3).epsilon(1e-9).margin(1e-12));
        }
    }
    CHECK(splits > 3);
}

TEST_CASE("The daily update gives the same bits on one and two threads", "[hydrology][determinism]") {
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
