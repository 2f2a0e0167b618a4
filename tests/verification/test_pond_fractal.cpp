// Ponding and the daily catchment updates against the brute-force reference on fractal DEMs (fBm
// and the multifractal), padded with a ring at the lowest elevation and unpadded. Fractal DEMs
// have large basins that drain to the edge and have room: a depression that spills into one of
// them must fill it before any water leaves the domain (the defect of issue 10, which white-noise
// DEMs rarely showed).
#include "ecoterra/hydro/catchments.hpp"
#include "ecoterra/hydro/pond.hpp"
#include "ecoterra/random.hpp"
#include "ecoterra/terrain/spectral.hpp"
#include "ecoterra/terrain/weierstrass.hpp"
#include "support/brute_force_pond.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

using namespace ecoterra;
using namespace ecoterra::hydro;
using ecoterra::GridSpec;
using ecoterra::RasterD;

namespace {

/// A one-cell ring at the DEM's lowest elevation around it (as Fill-Spill-Merge's ocean).
RasterD padded(const RasterD& z) {
    const auto& g = z.grid();
    const double low = *std::min_element(z.data(), z.data() + z.size());
    RasterD p(GridSpec{g.nx + 2, g.ny + 2, g.cell_size_m, g.origin_x_m - g.cell_size_m,
                       g.origin_y_m - g.cell_size_m},
              low);
    for (int j = 0; j < g.ny; ++j)
        for (int i = 0; i < g.nx; ++i) p(i + 1, j + 1) = z(i, j);
    return p;
}

RasterD fractal_dem(std::uint64_t seed) {
    Rng rng(seed, "test.pond_fractal");
    const int n = 24 + static_cast<int>(rng.below(37)); // 24 to 60 cells a side
    if (seed % 3 == 0) {
        const GridSpec g{n, n, 0.05, 0, 0};
        auto p = terrain::majhor2023_params(2.3 + 0.15 * static_cast<double>(rng.below(3)));
        p.relief_m = rng.uniform(0.5, 3.0);
        return terrain::multifractal_generate(g, p, seed).z;
    }
    const GridSpec g{n, n, 0.5 + rng.uniform(), 0, 0};
    const auto p = terrain::FbmParams::from_dimension(rng.uniform(2.1, 2.5), rng.uniform(0.3, 2.0));
    return terrain::fbm_surface(g, p, seed);
}

double max_depth_difference(const RasterD& d, const std::vector<double>& ref) {
    double worst = 0;
    for (std::int64_t k = 0; k < d.size(); ++k)
        worst = std::max(worst, std::abs(d.data()[k] - ref[static_cast<std::size_t>(k)]));
    return worst;
}

} // namespace

TEST_CASE("A full depression's overflow fills the edge-draining depression beside it",
          "[catchments][depressions]") {
    // The smallest case of issue 10: edge cells at 0, pit A (12.97) beside pit B (9.5) over a
    // 13.0 pass; B drains to the edge over 12.0. A holds 0.03 m3 and receives 0.05 m3, so 0.02
    // spills into B, which also receives its own 0.10 m3 and has room for 2.5 m3: B holds 0.12.
    RasterD z(GridSpec{7, 5, 1.0, 0, 0}, 0.0);
    const double interior[3][5] = {
        {20, 20, 20, 20, 20}, {20, 12.97, 13, 9.5, 12}, {20, 20, 20, 20, 20}};
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 5; ++i) z(i + 1, j + 1) = interior[j][i];
    const Catchments c = pond(z, 0.05, Routing::d8);
    const std::int64_t a = cell_index(z.grid(), 2, 2), b = cell_index(z.grid(), 4, 2);
    const auto ids = c.id_map();
    REQUIRE(ids.data()[a] != 0);
    REQUIRE(ids.data()[b] != 0);
    double va = 0, vb = 0;
    for (const auto& k : c.catchments()) {
        if (k.id == ids.data()[a]) va = k.volume_m3;
        if (k.id == ids.data()[b]) vb = k.volume_m3;
    }
    CHECK(va == Approx(0.03).margin(1e-12));
    CHECK(vb == Approx(0.12).margin(1e-12));
    CHECK(c.lost_m3() == Approx(35 * 0.05 - 0.15).margin(1e-12));
    // The hierarchy names B as A's overflow leaf although A has no parent.
    const auto& dh = c.hierarchy();
    const std::int32_t la = dh.leaf_of(a), lb = dh.leaf_of(b);
    CHECK(dh.overflow_leaf(la) == lb);
    CHECK(dh.overflow_leaf(lb) == -1);
    const auto ref = test::brute_force_pond(z, 0.05);
    CHECK(max_depth_difference(c.depth_map(), ref.depth_m) < 1e-12);
}

TEST_CASE("Top-level overflow chains end at the domain edge, over passes that never rise",
          "[catchments][depressions]") {
    for (std::uint64_t seed = 1; seed <= 30; ++seed) {
        const RasterD z = seed % 2 ? padded(fractal_dem(seed)) : fractal_dem(seed);
        const FlowDirections fd(z);
        const DepressionHierarchy dh(fd);
        CAPTURE(seed);
        auto top = [&](std::int32_t n) {
            while (dh.parent(n) >= 0) n = dh.parent(n);
            return n;
        };
        for (std::int32_t n = 0; n < dh.node_count(); ++n) {
            if (dh.parent(n) >= 0) continue;
            // Follow the spill from tree to tree: every step goes over a pass no higher than the
            // last, into another tree, and the chain reaches the edge within node_count steps.
            std::int32_t x = n;
            int steps = 0;
            while (dh.overflow_leaf(x) >= 0 && steps <= dh.node_count()) {
                const std::int32_t next = top(dh.overflow_leaf(x));
                CHECK(next != x);
                CHECK(dh.outlet_z(next) <= dh.outlet_z(x));
                x = next;
                ++steps;
            }
            CHECK(dh.overflow_leaf(x) == -1);
        }
    }
}

TEST_CASE("Ponding equals the brute-force reference on fractal DEMs, padded and unpadded",
          "[catchments][verification][slow]") {
    int compared = 0, filled_downstream = 0;
    for (std::uint64_t seed = 1; seed <= 24; ++seed) {
        for (const bool pad : {false, true}) {
            const RasterD z = pad ? padded(fractal_dem(seed)) : fractal_dem(seed);
            Rng rng(seed, "test.pond_fractal.depth");
            const double depth = rng.uniform(0.005, 0.2);
            const double area = z.cell_size() * z.cell_size();
            CAPTURE(seed, pad, z.grid().nx, depth);
            const auto ref = test::brute_force_pond(z, depth);
            const Catchments c = pond(z, depth, Routing::d8);
            CHECK(max_depth_difference(c.depth_map(), ref.depth_m) < 1e-9);
            CHECK(c.total_volume_m3() == Approx(ref.stored_m3).epsilon(1e-12).margin(1e-9));
            CHECK(c.lost_m3() == Approx(ref.lost_m3).epsilon(1e-12).margin(1e-9));
            // The daily path: the same water in uneven portions, each followed by an equilibrium
            // (the catchments carry over from one to the next), reaches the same state.
            Catchments daily(z);
            double left = 1.0;
            for (int part = 0; part < 4; ++part) {
                const double share = part == 3 ? left : left * rng.uniform(0.1, 0.6);
                left -= share;
                std::vector<double> v(static_cast<std::size_t>(z.size()), share * depth * area);
                daily.add_routed(route_to_pits(daily.flow(), v, Routing::d8));
                daily.equilibrate();
            }
            CHECK(max_depth_difference(daily.depth_map(), ref.depth_m) < 1e-9);
            CHECK(daily.total_volume_m3() == Approx(ref.stored_m3).epsilon(1e-11).margin(1e-9));
            // The lowest-neighbour rule (Fill-Spill-Merge's) against the reference on that rule.
            const auto ref_low = test::brute_force_pond(z, depth, D8Rule::lowest);
            const Catchments low = pond(z, depth, Routing::d8_lowest);
            CHECK(max_depth_difference(low.depth_map(), ref_low.depth_m) < 1e-9);
            CHECK(low.lost_m3() == Approx(ref_low.lost_m3).epsilon(1e-12).margin(1e-9));
            ++compared;
            // Count the DEMs where a top-level depression poured into another before the edge.
            for (const auto& k : c.catchments())
                if (c.hierarchy().parent(k.node) < 0 && c.hierarchy().overflow_leaf(k.node) >= 0 &&
                    k.volume_m3 >= c.hierarchy().capacity(k.node) * area * (1 - 1e-12))
                    ++filled_downstream;
        }
    }
    CHECK(compared == 48);
    CHECK(filled_downstream > 10); // the case the fix is about is well represented
}

TEST_CASE("The owner map holds the hierarchy's owner of every cell through fills, spills, merges, "
          "splits, new water and a checkpoint",
          "[catchments][depressions]") {
    // owner() reads a map that each equilibrium keeps; owner_by_hierarchy() is its definition.
    // Fractal and white-noise DEMs, some on discrete steps (flats, cells at a full lake's level),
    // padded and unpadded, water added and taken in uneven portions.
    int checked = 0, owned = 0, split_or_shrunk = 0;
    for (std::uint64_t seed = 1; seed <= 24; ++seed) {
        Rng rng(seed, "test.owner_map");
        RasterD z = fractal_dem(seed);
        if (seed % 4 == 1) // white noise on ten levels: flats, and lakes full to a flat pass
            for (std::int64_t k = 0; k < z.size(); ++k)
                z.data()[k] = std::floor(rng.uniform(0.0, 10.0)) / 10.0;
        if (seed % 4 == 3) // the fractal on 2 cm steps
            for (std::int64_t k = 0; k < z.size(); ++k)
                z.data()[k] = std::round(z.data()[k] / 0.02) * 0.02;
        if (seed % 2 == 0) z = padded(z);
        CAPTURE(seed, z.grid().nx);
        Catchments c(z);
        const double area = z.cell_size() * z.cell_size();
        auto check_all = [&](const Catchments& x) {
            std::int64_t wrong = 0;
            for (std::int64_t k = 0; k < z.size(); ++k) {
                wrong += x.owner(k) != x.owner_by_hierarchy(k);
                owned += x.owner(k) != 0;
            }
            CHECK(wrong == 0);
            ++checked;
        };
        check_all(c);
        for (int part = 0; part < 6; ++part) {
            if (part % 3 == 2) {
                // Take water from every catchment: lakes shrink and split.
                const auto list = c.catchments();
                for (const auto& k : list)
                    split_or_shrunk +=
                        c.remove_water(k.id, k.volume_m3 * rng.uniform(0.3, 0.9)) > 0;
            } else {
                const double depth = rng.uniform(0.002, 0.08);
                std::vector<double> v(static_cast<std::size_t>(z.size()), depth * area);
                c.add_routed(route_to_pits(c.flow(), v, Routing::d8));
            }
            c.equilibrate();
            check_all(c);
            // New water between equilibria (onto lakes and dry cells) changes no answer.
            for (int drop = 0; drop < 20; ++drop)
                c.add_water(
                    static_cast<std::int64_t>(rng.below(static_cast<std::uint64_t>(z.size()))),
                    rng.uniform(0.0, 0.05) * area);
            check_all(c);
        }
        c.equilibrate();
        ArchiveWriter a;
        c.save_state(a);
        const std::vector<std::uint8_t> bytes = a.bytes();
        Catchments r(z);
        ArchiveReader in(bytes.data(), bytes.size(), "test");
        r.load_state(in);
        check_all(r);
        std::int64_t differ = 0;
        for (std::int64_t k = 0; k < z.size(); ++k) differ += r.owner(k) != c.owner(k);
        CHECK(differ == 0);
    }
    CHECK(checked == 24 * 14);
    CHECK(owned > 0);
    CHECK(split_or_shrunk > 24);
}
