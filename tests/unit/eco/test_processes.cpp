// Hand-checked cases for each plant process (issue 4 s8): shading (paper 002 Fig 2), root-water
// sharing, starvation, the dispersal kernel, allometry, stand metrics and species-file errors.
#include "ecoterra/eco/canopy.hpp"
#include "ecoterra/eco/dispersal.hpp"
#include "ecoterra/eco/growth.hpp"
#include "ecoterra/eco/processes.hpp"
#include "ecoterra/eco/roots.hpp"
#include "ecoterra/eco/stand_metrics.hpp"
#include "ecoterra/parallel.hpp"
#include "ecoterra/random.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <numbers>
#include <omp.h>
#include <vector>

using namespace ecoterra;
using namespace ecoterra::eco;

namespace {
GridSpec grid(int n) {
    GridSpec g;
    g.nx = g.ny = n;
    g.cell_size_m = 1.0;
    return g;
}
/// A crown made of explicit cells (one span per cell).
void add_cells(CrownSet& c, std::initializer_list<std::pair<int, int>> cells) {
    if (c.offset.empty()) c.offset.push_back(0);
    for (auto [x, y] : cells) c.spans.push_back({y, x, x});
    c.offset.push_back(static_cast<std::uint32_t>(c.spans.size()));
    c.cells.push_back(static_cast<std::int32_t>(cells.size()));
}
} // namespace

TEST_CASE("shading: the paper's Fig 2 (A has one of four cells under taller B)", "[eco][canopy]") {
    const auto g = grid(4);
    CrownSet c;
    c.clear();
    add_cells(c, {{0, 0}, {1, 0}, {0, 1}, {1, 1}}); // A, 2x2
    add_cells(c, {{1, 1}, {2, 1}, {1, 2}, {2, 2}}); // B, 2x2, shares (1,1)
    RasterD ground;
    const auto s =
        compute_shading(g, c, {5.0, 12.0}, {4.0, 4.0}, ShadingMode::blocking, 0.5, &ground);
    CHECK(s[0] == Approx(0.25));
    CHECK(s[1] == 0.0);
    CHECK(ground(1, 1) == 1.0);
    CHECK(ground(3, 3) == 0.0);
    // Equal heights do not shade each other.
    const auto eq =
        compute_shading(g, c, {7.0, 7.0}, {4.0, 4.0}, ShadingMode::blocking, 0.5, nullptr);
    CHECK(eq[0] == 0.0);
    CHECK(eq[1] == 0.0);
    // Beer-Lambert: the shared cell transmits exp(-k LAI) instead of nothing.
    const auto b =
        compute_shading(g, c, {5.0, 12.0}, {4.0, 4.0}, ShadingMode::beer_lambert, 0.5, nullptr);
    CHECK(b[0] == Approx(0.25 * (1 - std::exp(-0.5 * 4.0))).epsilon(1e-12));
}

TEST_CASE("shading, crown_profile: leaf area above mid-crown, each crown's spread over its depth",
          "[eco][canopy]") {
    const auto g = grid(4);
    CrownSet c;
    c.clear();
    add_cells(c, {{0, 0}, {1, 0}, {0, 1}, {1, 1}}); // A, 2x2
    add_cells(c, {{1, 1}, {2, 1}, {1, 2}, {2, 2}}); // B, 2x2, shares (1,1)
    const double k = 0.5;
    RasterD ground;
    // A 10 m tall with crown 6-10 m, mid-crown 8 m; B 12 m with crown 8-12 m holds all its LAI 4
    // above 8 m, and A's crown top (10 m) is above B's mid-crown (10 m) by nothing.
    const auto s = compute_shading(g, c, {10.0, 12.0}, {4.0, 4.0}, ShadingMode::crown_profile, k,
                                   &ground, {4.0, 4.0});
    CHECK(s[0] == Approx(0.25 * (1 - std::exp(-k * 4.0))).epsilon(1e-12));
    CHECK(s[1] == 0.0);
    CHECK(ground(1, 1) == Approx(1 - std::exp(-k * 8.0)));
    CHECK(ground(0, 0) == Approx(1 - std::exp(-k * 4.0)));
    CHECK(ground(3, 3) == 0.0);
    // B 11 m: only its leaves above A's mid-crown, 4 (11 - 8) / 4 = 3, shade A; A's leaves above
    // B's mid-crown (9 m), 4 (10 - 9) / 4 = 1, shade B.
    const auto t = compute_shading(g, c, {10.0, 11.0}, {4.0, 4.0}, ShadingMode::crown_profile, k,
                                   nullptr, {4.0, 4.0});
    CHECK(t[0] == Approx(0.25 * (1 - std::exp(-k * 3.0))).epsilon(1e-12));
    CHECK(t[1] == Approx(0.25 * (1 - std::exp(-k * 1.0))).epsilon(1e-12));
    // Equal codominants shade each other with their upper halves, alike.
    const auto eq = compute_shading(g, c, {10.0, 10.0}, {4.0, 4.0}, ShadingMode::crown_profile, k,
                                    nullptr, {4.0, 4.0});
    CHECK(eq[0] == Approx(0.25 * (1 - std::exp(-k * 2.0))).epsilon(1e-12));
    CHECK(eq[1] == eq[0]);
    // Without the depths it cannot run, and says so.
    CHECK_THROWS_WITH(
        compute_shading(g, c, {10.0, 12.0}, {4.0, 4.0}, ShadingMode::crown_profile, k, nullptr),
        Catch::Contains("crown depth per plant"));
}

TEST_CASE("shading, crown_profile: equals a direct sum over crowns on random stands, and "
          "Beer-Lambert when crowns have no depth",
          "[eco][canopy]") {
    const auto g = grid(40);
    Rng rng(2024, "crown_profile");
    for (int stand = 0; stand < 12; ++stand) {
        const int n = 5 + static_cast<int>(rng.uniform() * 60);
        CrownSet c;
        c.clear();
        std::vector<double> h(n), lai(n), depth(n), x(n), y(n), r(n);
        for (int p = 0; p < n; ++p) {
            x[p] = 40 * rng.uniform(), y[p] = 40 * rng.uniform(), r[p] = 0.5 + 6 * rng.uniform();
            // Quantised heights so that ties occur.
            h[p] = 2 + std::round(20 * rng.uniform()) * 0.5;
            lai[p] = 1 + 4 * rng.uniform();
            depth[p] = (0.1 + 0.8 * rng.uniform()) * h[p];
            c.add(g, x[p], y[p], r[p]);
        }
        const double k = 0.3 + rng.uniform();
        RasterD ground;
        const auto s = compute_shading(g, c, h, lai, ShadingMode::crown_profile, k, &ground, depth);
        // The crowns' visits by row band and the ground's cells split over threads (forced on
        // this small stand): the same bits on 1 to 3 threads.
        const int saved_threads = omp_get_max_threads();
        set_parallel_min_items(1);
        for (int threads : {1, 2, 3}) {
            CAPTURE(threads);
            omp_set_num_threads(threads);
            RasterD ground_t;
            const auto st =
                compute_shading(g, c, h, lai, ShadingMode::crown_profile, k, &ground_t, depth);
            CHECK(std::memcmp(st.data(), s.data(), s.size() * sizeof(double)) == 0);
            CHECK(std::memcmp(ground_t.data(), ground.data(),
                              static_cast<std::size_t>(g.size()) * sizeof(double)) == 0);
        }
        omp_set_num_threads(saved_threads);
        set_parallel_min_items(kMinParallelItems);
        // Direct: per plant, per cell, every other crown covering the cell.
        std::vector<std::vector<int>> owners(static_cast<std::size_t>(g.size()));
        for (int p = 0; p < n; ++p)
            for (auto q = c.offset[p]; q < c.offset[p + 1]; ++q)
                for (int i = c.spans[q].x0; i <= c.spans[q].x1; ++i)
                    owners[static_cast<std::size_t>(c.spans[q].row * g.nx + i)].push_back(p);
        for (int p = 0; p < n; ++p) {
            const double z = h[p] - 0.5 * depth[p];
            double light = 0;
            for (auto q = c.offset[p]; q < c.offset[p + 1]; ++q)
                for (int i = c.spans[q].x0; i <= c.spans[q].x1; ++i) {
                    double l = 0;
                    for (int o : owners[static_cast<std::size_t>(c.spans[q].row * g.nx + i)])
                        if (o != p && h[o] > z) l += lai[o] * std::min(1.0, (h[o] - z) / depth[o]);
                    light += std::exp(-k * l);
                }
            CHECK(s[p] == Approx(1 - light / c.cells[p]).margin(1e-12));
        }
        for (std::int64_t cell = 0; cell < g.size(); ++cell) {
            double l = 0;
            for (int o : owners[static_cast<std::size_t>(cell)]) l += lai[o];
            CHECK(ground.data()[cell] == Approx(1 - std::exp(-k * l)).margin(1e-12));
        }
        // Crowns of no depth hold their leaves at the top: Beer-Lambert through taller crowns.
        const auto flat = compute_shading(g, c, h, lai, ShadingMode::crown_profile, k, nullptr,
                                          std::vector<double>(n, 0.0));
        const auto bl = compute_shading(g, c, h, lai, ShadingMode::beer_lambert, k, nullptr);
        for (int p = 0; p < n; ++p) CHECK(flat[p] == Approx(bl[p]).margin(1e-12));
    }
}

TEST_CASE("crowns cover the cells whose centres lie within the radius, and the stem cell",
          "[eco][canopy]") {
    const auto g = grid(20);
    CrownSet c;
    c.clear();
    c.add(g, 10.0, 10.0, 3.0); // centred on a cell corner
    c.add(g, 5.5, 5.5, 0.1);   // a seedling: only its own cell
    c.add(g, 0.2, 19.8, 2.0);  // at a corner: clipped by the grid
    int brute = 0;
    for (int j = 0; j < 20; ++j)
        for (int i = 0; i < 20; ++i) brute += std::hypot(g.x_of(i) - 10.0, g.y_of(j) - 10.0) <= 3.0;
    CHECK(c.cells[0] == brute);
    CHECK(c.cells[1] == 1);
    CHECK(c.spans[c.offset[1]].row == 5);
    CHECK(c.spans[c.offset[1]].x0 == 5);
    int corner = 0;
    for (int j = 0; j < 20; ++j)
        for (int i = 0; i < 20; ++i) corner += std::hypot(g.x_of(i) - 0.2, g.y_of(j) - 19.8) <= 2.0;
    CHECK(c.cells[2] == corner);
}

TEST_CASE("crown_set and root_cells: built in blocks on 1-3 threads, the crowns and roots of "
          "one plant at a time",
          "[eco][canopy][roots]") {
    // Stands of 3 to 3.5 blocks of plants (kCrownBlock), so that the joins are crossed, on a
    // plant grid equal to the hydrology grid and on one 2 and 3 times finer.
    Rng rng(31, "crown_set");
    for (int stand = 0; stand < 4; ++stand) {
        const auto g = grid(120 + 30 * stand);
        const std::size_t n = 3 * kCrownBlock + static_cast<std::size_t>(rng.uniform() * 2000);
        std::vector<double> x(n), y(n), r(n);
        for (std::size_t p = 0; p < n; ++p) {
            x[p] = g.nx * rng.uniform(), y[p] = g.ny * rng.uniform();
            r[p] = stand % 2 ? 0.05 + 0.3 * rng.uniform() : 0.3 + 5 * rng.uniform();
        }
        CrownSet one_by_one;
        one_by_one.clear();
        for (std::size_t p = 0; p < n; ++p) one_by_one.add(g, x[p], y[p], r[p]);
        const int saved_threads = omp_get_max_threads();
        set_parallel_min_items(1);
        for (int threads : {1, 2, 3}) {
            CAPTURE(stand, threads);
            omp_set_num_threads(threads);
            const CrownSet c = crown_set(g, x, y, r);
            REQUIRE(c.offset == one_by_one.offset);
            REQUIRE(c.cells == one_by_one.cells);
            REQUIRE(c.spans.size() == one_by_one.spans.size());
            for (std::size_t s = 0; s < c.spans.size(); ++s) {
                REQUIRE(c.spans[s].row == one_by_one.spans[s].row);
                REQUIRE(c.spans[s].x0 == one_by_one.spans[s].x0);
                REQUIRE(c.spans[s].x1 == one_by_one.spans[s].x1);
            }
            for (int factor : {1, 2, 3}) {
                CellMap map;
                map.factor = factor;
                map.hydro_nx = g.nx / factor;
                const RootCells roots = root_cells(c, map);
                REQUIRE(roots.size() == n);
                std::int64_t additions = 0;
                for (std::size_t p = 0; p < n; p += 97) { // every 97th plant alone
                    CrownSet single;
                    single.clear();
                    single.add(g, x[p], y[p], r[p]);
                    const RootCells alone = root_cells(single, map);
                    const std::uint32_t e0 = roots.offset[p];
                    REQUIRE(roots.offset[p + 1] - e0 == alone.offset[1]);
                    for (std::uint32_t e = 0; e < alone.offset[1]; ++e) {
                        REQUIRE(roots.cell[e0 + e] == alone.cell[e]);
                        REQUIRE(roots.share[e0 + e] == alone.share[e]);
                        REQUIRE(roots.cells_of(e0 + e) == alone.cells_of(e));
                    }
                }
                for (std::uint32_t e = 0; e < roots.cell.size(); ++e)
                    additions += roots.cells_of(e);
                CHECK(roots.additions == additions);
            }
        }
        omp_set_num_threads(saved_threads);
        set_parallel_min_items(kMinParallelItems);
    }
}

TEST_CASE("root water: a cell shared by two root balls is split by their requests",
          "[eco][roots]") {
    // Plant 0 roots in cells 0 and 1, plant 1 in cell 1 only (a 2x1 hydrology grid).
    CrownSet c;
    c.clear();
    add_cells(c, {{0, 0}, {1, 0}});
    add_cells(c, {{1, 0}});
    CellMap map;
    map.hydro_nx = 2;
    const RootCells roots = root_cells(c, map);
    std::vector<double> request(2, 0.0);
    scatter_demand(roots, {2.0, 3.0}, request); // m3
    CHECK(request[0] == Approx(1.0));
    CHECK(request[1] == Approx(4.0)); // 1 from plant 0, 3 from plant 1
    // Cell 1 can supply only 2 m3 of its 4: both plants get half of what they asked there.
    std::vector<double> frac;
    gather_supply(roots, {1.0, 0.5}, frac);
    CHECK(frac[0] == Approx(0.75)); // (1 + 0.5) / 2 cells
    CHECK(frac[1] == Approx(0.5));
    // Water delivered = supply: 1 + 0.5 from plant 0's cells, 1.5 for plant 1 = 3 m3 = 1 + 2.
    CHECK(2.0 * frac[0] + 3.0 * frac[1] == Approx(1.0 + 2.0));
    // A plant grid twice as fine maps four plant cells onto one hydrology cell.
    CellMap fine;
    fine.factor = 2;
    fine.hydro_nx = 1;
    CHECK(fine.hydro(1, 1) == 0);
    CHECK(fine.hydro(3, 1) == 1);
    // The same two crowns on that grid: plant 0's two cells both lie in hydrology cell 0, and a
    // third plant spans both hydrology cells (3 of its 4 cells in the second).
    add_cells(c, {{1, 1}, {1, 2}, {0, 3}, {1, 3}});
    const RootCells fine_roots = root_cells(c, fine);
    REQUIRE(fine_roots.size() == 3);
    CHECK(fine_roots.offset == std::vector<std::uint32_t>{0, 1, 2, 4});
    CHECK(fine_roots.share[0] == 1.0);
    CHECK(fine_roots.share[2] == Approx(0.25));
    CHECK(fine_roots.cell[3] == 1);
    CHECK(fine_roots.share[3] == Approx(0.75));
    std::vector<double> fine_request(2, 0.0);
    scatter_demand(fine_roots, {2.0, 3.0, 4.0}, fine_request);
    CHECK(fine_request[0] == Approx(2.0 + 3.0 + 1.0));
    CHECK(fine_request[1] == Approx(3.0));
    gather_supply(fine_roots, {1.0, 0.5}, frac);
    CHECK(frac[2] == Approx(0.25 * 1.0 + 0.75 * 0.5));
}

TEST_CASE("carbon: a plant in deep shade drains its reserve and starves on the day predicted",
          "[eco][growth]") {
    Species s;
    s.shade = {0.0, 0.2};
    Plant p;
    p.dbh_m = 0.05;
    allometry::apply(s, p);
    p.wood_kg = allometry::stem_mass_kg(s, p.dbh_m);
    p.reserve_kg = 0.5;
    const double g = shade_factor(s.shade, 1.0); // fully shaded: exp(-12.5)
    CHECK(g == Approx(std::exp(-12.5)));
    const double tmean = 20.0; // respiration at its reference rate
    const double daily_resp =
        s.respiration_kg_per_m2_leaf_per_m_per_yr / 365.0 * p.leaf_area_m2 * p.height_m;
    const double daily_prod = s.max_production_kg_per_m2_leaf_per_day * p.leaf_area_m2 * g;
    const int expected = static_cast<int>(std::ceil(0.5 / (daily_resp - daily_prod)));
    int day = 0;
    double wood0 = p.wood_kg;
    for (;;) {
        ++day;
        const auto c = carbon_day(s, p, g, 1.0, tmean);
        if (c.starved) break;
        REQUIRE(day < 100000);
    }
    CHECK(day == expected);
    CHECK(p.wood_kg == wood0); // no wood was built from a deficit
    // The same plant in full light fills its reserve first, then builds wood.
    Plant q;
    q.dbh_m = 0.05;
    allometry::apply(s, q);
    q.wood_kg = allometry::stem_mass_kg(s, q.dbh_m);
    const auto c = carbon_day(s, q, 1.0, 1.0, tmean);
    CHECK(c.to_reserve_kg > 0);
    CHECK(c.production_kg - c.maintenance_kg ==
          Approx(c.to_reserve_kg + c.to_wood_kg + c.growth_respiration_kg));
}

TEST_CASE("carbon: a full reserve carries a plant through a drought that kills a low one",
          "[eco][growth]") {
    Species s;
    auto make = [&](double fill) {
        Plant p;
        p.dbh_m = 0.1;
        allometry::apply(s, p);
        p.wood_kg = allometry::stem_mass_kg(s, p.dbh_m);
        p.reserve_kg = fill * s.reserve_capacity_kg_per_m2_leaf * p.leaf_area_m2;
        return p;
    };
    Plant full = make(1.0), low = make(0.1);
    const double g = water_factor(s.water, 0.0); // no water: exp(-0.5/0.09)
    bool full_died = false, low_died = false;
    for (int d = 0; d < 120; ++d) {
        full_died = full_died || carbon_day(s, full, g, 1.0, 25.0).starved;
        low_died = low_died || carbon_day(s, low, g, 1.0, 25.0).starved;
    }
    CHECK(low_died);
    CHECK_FALSE(full_died);
}

TEST_CASE("suppression: a slow grower's running efficiency sets its death probability",
          "[eco][growth]") {
    Species s;
    s.suppression_growth_efficiency_kg_per_m2_leaf_per_yr = 0.2;
    s.suppression_mortality_per_yr = 0.3;
    Plant p;
    p.dbh_m = 0.1;
    allometry::apply(s, p);
    p.wood_kg = allometry::stem_mass_kg(s, p.dbh_m);
    p.reserve_kg = 1.0;
    p.mass_at_year_start_kg = p.wood_kg + p.reserve_kg;
    REQUIRE(std::isnan(p.growth_efficiency));
    // Year 1: it gains 0.05 kg per m2 of leaf; the first year sets the mean.
    p.wood_kg += 0.05 * p.leaf_area_m2;
    CHECK(update_growth_efficiency(p) == Approx(0.05));
    CHECK(p.growth_efficiency == Approx(0.05));
    CHECK(suppression_mortality(s, p.growth_efficiency) == Approx(0.3 * (1 - 0.05 / 0.2)));
    // Year 2: it loses 0.1 kg per m2 from its reserve; the mean moves a third of the way.
    p.reserve_kg -= 0.1 * p.leaf_area_m2;
    CHECK(update_growth_efficiency(p) == Approx(-0.1));
    CHECK(p.growth_efficiency == Approx(0.05 + (-0.1 - 0.05) / 3).margin(1e-12));
    CHECK(suppression_mortality(s, p.growth_efficiency) == Approx(0.3).margin(1e-12));
    CHECK(suppression_mortality(s, -0.5) == 0.3); // capped at mu_max
    // A vigorous plant and a species without the rule never die of it.
    CHECK(suppression_mortality(s, 0.25) == 0.0);
    // Under light_and_turnover a suppressed plant starves instead (growth.hpp).
    CHECK(suppression_mortality(s, -1.0, GrowthModel::light_and_turnover) == 0.0);
    s.suppression_growth_efficiency_kg_per_m2_leaf_per_yr = 0.0;
    CHECK(suppression_mortality(s, -1.0) == 0.0);
}

TEST_CASE("crown leaves: a shaded crown holds fewer under light_and_turnover, none change under "
          "paper 002's model",
          "[eco][growth][canopy]") {
    Species s;
    s.shaded_crown_leaf_fraction = 0.25;
    const auto lt = GrowthModel::light_and_turnover;
    CHECK(crown_leaf_factor(s, lt, 0.0) == 1.0);
    CHECK(crown_leaf_factor(s, lt, 1.0) == 0.25);
    CHECK(crown_leaf_factor(s, lt, 0.6) == Approx(0.25 + 0.75 * 0.4));
    CHECK(crown_leaf_factor(s, GrowthModel::paper002, 1.0) == 1.0);
    s.shaded_crown_leaf_fraction = 1.0;
    CHECK(crown_leaf_factor(s, lt, 1.0) == 1.0);
    // In the engine's kernels: a small tree under a large one, both with the trait.
    s.shaded_crown_leaf_fraction = 0.25;
    const std::vector<Species> species{s};
    Population pop;
    for (const auto& [x, d] : {std::pair{10.0, 0.5}, std::pair{10.5, 0.05}}) {
        Plant p;
        p.x_m = x, p.y_m = 10.0, p.dbh_m = d;
        allometry::apply(s, p);
        p.wood_kg = allometry::stem_mass_kg(s, d);
        pop.push(p);
    }
    Canopy canopy;
    canopy.plant_grid = grid(20);
    canopy.map = CellMap{1, 20};
    for (int pass = 0; pass < 2; ++pass) {
        refresh_structure(pop, species, lt);
        canopy.refresh(pop, species, ShadingMode::crown_profile, 0.5, lt);
    }
    const double shade = pop.shade_fraction[1];
    REQUIRE(shade > 0.5);
    CHECK(pop.shade_fraction[0] == 0.0);
    refresh_structure(pop, species, lt);
    CHECK(pop.leaf_area_m2[1] ==
          Approx(allometry::size(s, pop.dbh_m[1]).leaf_area_m2 * (0.25 + 0.75 * (1 - shade))));
    CHECK(pop.leaf_area_m2[0] == Approx(allometry::size(s, pop.dbh_m[0]).leaf_area_m2));
    // Under paper 002's model the same stand keeps its allometric leaves.
    refresh_structure(pop, species, GrowthModel::paper002);
    CHECK(pop.leaf_area_m2[1] == allometry::size(s, pop.dbh_m[1]).leaf_area_m2);
}

TEST_CASE("maintenance: paper 002's coefficient or, under light_and_turnover, the sapwood's",
          "[eco][growth]") {
    Species s;
    s.respiration_kg_per_m2_leaf_per_m_per_yr = 0.015;
    s.sapwood_respiration_kg_per_m2_leaf_per_m_per_yr = 0.006;
    CHECK(maintenance_coefficient(s, GrowthModel::paper002) == 0.015);
    CHECK(maintenance_coefficient(s, GrowthModel::light_and_turnover) == 0.006);
    Plant p;
    p.dbh_m = 0.2;
    allometry::apply(s, p);
    for (const double rm : {0.015, 0.006}) {
        CarbonPools pools{1.0, 1.0, 0.0};
        const auto c =
            carbon_day(s, p.leaf_area_m2, p.height_m, p.dbh_m, pools, 0.0, 1.0, 1.0, 1.0, 0.0, rm);
        CHECK(c.maintenance_kg == Approx(rm / kDaysPerYear * p.leaf_area_m2 * p.height_m));
    }
}

TEST_CASE("growth factors and allometry", "[eco][growth]") {
    Species s;
    CHECK(shade_factor({0.2, 0.5}, 0.1) == 1.0);
    CHECK(shade_factor({0.2, 0.5}, 0.7) == Approx(std::exp(-0.5)));
    CHECK(water_factor({1.0, 0.3}, 0.7) == Approx(std::exp(-0.5)));
    CHECK(ph_factor({6.5, 1.0}, 4.5) == Approx(std::exp(-2.0)));
    CHECK(texture_factor(hydro::Texture::silt_loam, 30, 20, 65, 15) == 1.0);
    CHECK(texture_factor(hydro::Texture::silt_loam, 30, 85, 10, 5) < 0.2);
    const auto c = texture_centroid(hydro::Texture::clay);
    CHECK(c[0] + c[1] + c[2] == Approx(100.0));
    CHECK(hydro::classify_texture(c[0], c[1], c[2]) == hydro::Texture::clay);
    CHECK(allometry::height_m(s, 0.0) == Approx(kBreastHeightM));
    CHECK(allometry::height_m(s, 10.0) == Approx(s.max_height_m).epsilon(1e-6));
    for (double d : {0.005, 0.1, 0.3, 0.8, 2.0}) {
        const double m = allometry::stem_mass_kg(s, d);
        CHECK(allometry::dbh_from_stem_mass(s, m, 0.05) == Approx(d).epsilon(1e-10));
    }
    // Crown radius at 30 cm within the published 2.2-2.8 m (reference forest.md s2).
    CHECK(allometry::crown_radius_m(s, 0.3) > 2.2);
    CHECK(allometry::crown_radius_m(s, 0.3) < 2.9);
}

TEST_CASE("dispersal: sampled distances follow the two-part exponential kernel",
          "[eco][dispersal]") {
    DispersalKernel k{10.0, 80.0, 0.2};
    Rng rng(7, "test");
    constexpr int kN = 200000;
    double mean = 0;
    int beyond50 = 0;
    for (int i = 0; i < kN; ++i) {
        const double d = sample_dispersal_distance(k, rng);
        mean += d;
        beyond50 += d > 50;
    }
    mean /= kN;
    CHECK(mean == Approx(0.8 * 10 + 0.2 * 80).epsilon(0.01));
    const double p50 = 0.8 * std::exp(-50.0 / 10) + 0.2 * std::exp(-50.0 / 80);
    CHECK(beyond50 / double(kN) == Approx(p50).epsilon(0.02));
    // Seeds scale with basal area and vigor, normalised at 30 cm.
    Species s;
    CHECK(seeds_per_year(s, 0.3, 1.0) == Approx(s.seeds_per_yr_at_30cm));
    CHECK(seeds_per_year(s, 0.6, 0.5) == Approx(2.0 * s.seeds_per_yr_at_30cm));
    // Poisson draws have the right mean on both branches.
    for (double lam : {3.0, 120.0}) {
        double sum = 0;
        for (int i = 0; i < 20000; ++i) sum += static_cast<double>(poisson(rng, lam));
        CHECK(sum / 20000 == Approx(lam).epsilon(0.02));
    }
}

TEST_CASE("stand metrics: basal area, Reineke SDI and an exact exponential", "[eco][stand]") {
    // 100 stems of 30 cm on 1 ha: BA = 100 pi 0.15^2 = 7.069 m2/ha.
    std::vector<double> d(100, 0.30);
    auto m = stand_metrics(d, 1e4);
    CHECK(m.basal_area_m2_per_ha == Approx(100 * std::numbers::pi * 0.0225));
    CHECK(m.basal_area_m2_per_ha * kFt2PerAcrePerM2PerHa == Approx(30.79).epsilon(1e-3));
    CHECK(m.sdi_per_ha == Approx(100 * std::pow(30.0 / 25.4, 1.605)));
    CHECK_FALSE(m.fit_valid);
    // Counts 64, 32, 16, 8, 4 per 5 cm class: q = 2 exactly, R2 = 1.
    std::vector<double> e;
    int n = 64;
    for (int cls = 0; cls < 5; ++cls, n /= 2)
        for (int k = 0; k < n; ++k) e.push_back((cls * 5 + 2.5) / 100.0);
    m = stand_metrics(e, 1e4);
    REQUIRE(m.fit_valid);
    CHECK(m.q_per_class == Approx(2.0));
    CHECK(m.rate_per_cm == Approx(std::log(2.0) / 5));
    CHECK(m.r2 == Approx(1.0));
    CHECK(m.histogram == std::vector<std::int64_t>{64, 32, 16, 8, 4});
}

TEST_CASE("stand metrics by species partition the stand: stems and basal area add up",
          "[eco][stand]") {
    std::vector<double> d;
    std::vector<int> sp;
    for (int k = 0; k < 300; ++k) {
        d.push_back(k % 7 == 0 ? 0.0 : 0.02 + 0.001 * k); // some below breast height
        sp.push_back(k % 3);
    }
    const auto all = stand_metrics(d, 2.5e4);
    const auto per = stand_metrics_by_species(d, sp, 4, 2.5e4);
    REQUIRE(per.size() == 4);
    CHECK(per[3].stems == 0);
    CHECK(per[0].stems + per[1].stems + per[2].stems == all.stems);
    CHECK(per[0].basal_area_m2_per_ha + per[1].basal_area_m2_per_ha + per[2].basal_area_m2_per_ha ==
          Approx(all.basal_area_m2_per_ha).epsilon(1e-12));
    CHECK_THROWS_WITH(stand_metrics_by_species(d, sp, 2, 2.5e4),
                      Catch::Contains("species index 2"));
    sp.pop_back();
    CHECK_THROWS_AS(stand_metrics_by_species(d, sp, 3, 2.5e4), InputError);
}

TEST_CASE("species files: MAVS entries load with reported defaults, bad values are named",
          "[eco][species]") {
    using nlohmann::json;
    const json mavs = {{"Texture Inputs", "x.json"},
                       {"Species",
                        {{{"Mesh File", "a.obj"},
                          {"Species Name", "Oak"},
                          {"Num New Per Area", 0.001},
                          {"Growth Rate", 0.1},
                          {"Max Height", 20.0},
                          {"Min Height", 10.0},
                          {"Mesh Height", 1.0},
                          {"Height To Diameter Ratio", 0.05},
                          {"Max Age", 50},
                          {"Rotate Mesh", false}}}}};
    const auto def = parse_ecosystem(mavs, "mavs.json");
    REQUIRE(def.species.size() == 1);
    CHECK(def.species[0].max_height_m == 20.0);
    CHECK(def.species[0].maturity_age_yr == 10.0); // 0.2 x Max Age
    bool noted = false;
    for (const auto& n : def.notes)
        noted = noted ||
                n.find("every physiology key takes its default for a tree") != std::string::npos;
    CHECK(noted);
    CHECK(def.species[0].max_stem_diameter_m == Approx(1.0)); // Max Height / 20
    auto bad = [&](const std::string& key, const json& value, const std::string& expect) {
        json j = mavs;
        if (key.rfind("physiology.", 0) == 0) {
            json& p = j["Species"][0]["physiology"];
            const std::string sub = key.substr(11);
            const auto dot = sub.find('.');
            if (dot == std::string::npos)
                p[sub] = value;
            else
                p[sub.substr(0, dot)][sub.substr(dot + 1)] = value;
        } else {
            j["Species"][0][key] = value;
        }
        try {
            parse_ecosystem(j, "eco.json");
            FAIL("no error for " << key);
        } catch (const InputError& e) {
            const std::string msg = e.what();
            CHECK_THAT(msg, Catch::Contains("eco.json") && Catch::Contains("'Oak'") &&
                                Catch::Contains(expect));
        }
    };
    bad("Max Height", -3.0, "Max Height");
    bad("physiology.shade.tolerance", 0.0, "physiology.shade.tolerance");
    bad("physiology.texture", "peat", "physiology.texture must be sand, loamy_sand");
    bad("physiology.leaf_area_per_crown_areaa", 3.0, "did you mean");
    json missing = mavs;
    missing["Species"][0].erase("Max Age");
    CHECK_THROWS_WITH(parse_ecosystem(missing, "eco.json"),
                      Catch::Contains("missing key 'Max Age'"));
    // A MAVS file may leave out the name (MAVS never reads it); ecoterra needs it.
    json nameless = mavs;
    nameless["Species"][0].erase("Species Name");
    CHECK_THROWS_WITH(parse_ecosystem(nameless, "eco.json"),
                      Catch::Contains("eco.json") && Catch::Contains("#0") &&
                          Catch::Contains("missing key 'Species Name'") &&
                          Catch::Contains("a.obj"));
    nameless["Species"][0]["Species Name"] = " ";
    CHECK_THROWS_WITH(parse_ecosystem(nameless, "eco.json"),
                      Catch::Contains("'Species Name' is empty"));
}

TEST_CASE("light response: a normalised rectangular hyperbola that favours tolerant species in "
          "shade",
          "[eco][growth]") {
    for (const double k : {0.05, 0.1, 0.3, 1.0, 3.0}) {
        CHECK(light_factor(k, 0.0) == 0.0);
        CHECK(light_factor(k, 1.0) == Approx(1.0));
        CHECK(light_factor(k, 1.5) == Approx(1.0)); // light is clamped to full sun
        if (k <= 1) CHECK(light_factor(k, k) == Approx(0.5 * (1.0 + k))); // half of 1 + K
        double last = 0;
        for (int i = 1; i <= 100; ++i) {
            const double f = light_factor(k, i / 100.0);
            CHECK(f > last);                                 // rises with light
            CHECK(f >= i / 100.0);                           // above the linear response
            CHECK(f <= (1.0 + k) / k * (i / 100.0) + 1e-12); // below its slope at 0
            last = f;
        }
    }
    // At 5 % of full sun a tolerant species (K 0.1) keeps several times an intolerant one's
    // (K 1) share of its production.
    CHECK(light_factor(0.1, 0.05) / light_factor(1.0, 0.05) > 3.5);
}

TEST_CASE("tissue turnover: leaf mass from longevity (Reich et al. 1997) and its daily cost",
          "[eco][growth]") {
    // SLA = exp(6.15) (12 L)^-0.46 cm2/g: 469 cm2/g at one month, so LMA = 0.0213 kg/m2.
    CHECK(leaf_mass_per_area_from_longevity(1.0 / 12) == Approx(10.0 / std::exp(6.15)));
    // Longer-lived leaves are heavier: x 2^0.46 per doubling of longevity.
    for (const double l : {0.25, 0.5, 1.0, 2.0, 4.0})
        CHECK(leaf_mass_per_area_from_longevity(2 * l) / leaf_mass_per_area_from_longevity(l) ==
              Approx(std::pow(2.0, 0.46)));
    Species s;
    s.leaf_mass_per_area_kg_per_m2 = 0.08;
    s.leaf_lifespan_yr = 2.0;
    s.fine_root_to_leaf_mass = 1.0;
    s.fine_root_turnover_per_yr = 0.7;
    // 10 m2 of leaf: 0.8 kg of leaves (0.4 kg a year) and 0.8 kg of fine roots (0.56 kg a year),
    // built at 1 / (1 - 0.25) kg of carbohydrate per kg.
    CHECK(tissue_cost_kg_per_day(s, 10.0) * 365.0 == Approx((0.4 + 0.56) / 0.75));
    // The cost is paid first: a plant in the dark loses production - maintenance - cost a day,
    // and the cost goes to growth respiration and litter, closing the day's carbon.
    Plant p;
    p.dbh_m = 0.05;
    allometry::apply(s, p);
    p.wood_kg = allometry::stem_mass_kg(s, p.dbh_m);
    p.reserve_kg = 1.0;
    CarbonPools pools{p.reserve_kg, p.wood_kg, 0.0};
    const double cost = tissue_cost_kg_per_day(s, p.leaf_area_m2);
    const auto c = carbon_day(s, p.leaf_area_m2, p.height_m, p.dbh_m, pools, 0.0, 1.0, 1.0, 1.0,
                              cost, s.respiration_kg_per_m2_leaf_per_m_per_yr);
    CHECK(c.growth_respiration_kg == Approx(0.25 * cost));
    CHECK(c.litter_kg == Approx(0.75 * cost));
    CHECK(1.0 - pools.reserve_kg == Approx(c.maintenance_kg + cost));
    CHECK(pools.wood_kg == p.wood_kg);
}

TEST_CASE("tissue turnover: the light compensation point is where production meets the costs, "
          "lower for shade-tolerant species",
          "[eco][growth]") {
    // Net carbon of a day at light I: p_max LA f_L(I) - R - Q. Its root, found by bisection on
    // carbon_day, equals the analytic one of I (1 + K) / (I + K) = (R + Q) / (p_max LA).
    auto compensation = [](double k) {
        Species s;
        s.light_half_saturation = k;
        s.leaf_mass_per_area_kg_per_m2 = 0.05;
        Plant p;
        p.dbh_m = 0.03;
        allometry::apply(s, p);
        const double cost = tissue_cost_kg_per_day(s, p.leaf_area_m2);
        auto net = [&](double light) {
            CarbonPools pools{1.0, 1.0, 0.0};
            const auto c =
                carbon_day(s, p.leaf_area_m2, p.height_m, p.dbh_m, pools, light_factor(k, light),
                           1.0, 1.0, 1.0, cost, s.respiration_kg_per_m2_leaf_per_m_per_yr);
            return c.production_kg - c.maintenance_kg - cost;
        };
        double lo = 0, hi = 1;
        for (int i = 0; i < 60; ++i) (net(0.5 * (lo + hi)) > 0 ? hi : lo) = 0.5 * (lo + hi);
        const double need = (s.respiration_kg_per_m2_leaf_per_m_per_yr / 365.0 * p.height_m +
                             cost / p.leaf_area_m2) /
                            s.max_production_kg_per_m2_leaf_per_day;
        CHECK(lo == Approx(need * k / (1.0 + k - need)).epsilon(1e-9));
        return lo;
    };
    const double tolerant = compensation(0.1), intolerant = compensation(1.0);
    CHECK(tolerant > 0.0);
    CHECK(tolerant < intolerant);
}

TEST_CASE("gap_light is the window mean of the ground light, clipped at the edges",
          "[eco][processes][establishment]") {
    // Against a brute-force window mean over random ground shade, many sizes and half-widths.
    Rng rng(17);
    for (int trial = 0; trial < 40; ++trial) {
        GridSpec g;
        g.nx = 1 + static_cast<int>(rng.uniform() * 23);
        g.ny = 1 + static_cast<int>(rng.uniform() * 23);
        g.cell_size_m = trial % 2 ? 1.0 : 0.5;
        RasterD shade(g, 0.0);
        for (std::int64_t c = 0; c < shade.size(); ++c)
            shade.data()[c] = rng.uniform() < 0.3 ? 0.0 : rng.uniform();
        const double half_m = rng.uniform() * 6;
        const RasterD light = gap_light(shade, half_m);
        const int r = static_cast<int>(std::floor(half_m / g.cell_size_m));
        for (int j = 0; j < g.ny; ++j)
            for (int i = 0; i < g.nx; ++i) {
                double sum = 0;
                int n = 0;
                for (int jj = std::max(0, j - r); jj <= std::min(g.ny - 1, j + r); ++jj)
                    for (int ii = std::max(0, i - r); ii <= std::min(g.nx - 1, i + r); ++ii)
                        sum += 1.0 - shade(ii, jj), ++n;
                CHECK(light(i, j) == Approx(sum / n).margin(1e-12));
            }
    }
    // A one-cell gap in a closed canopy is open at half-width 0 and dark in a 5 x 5 window; the
    // centre of a clearing wider than the window is in full light.
    RasterD closed(grid(21), 1.0);
    closed(10, 10) = 0.0;
    CHECK(gap_light(closed, 0.0)(10, 10) == 1.0);
    CHECK(gap_light(closed, 2.0)(10, 10) == Approx(1.0 / 25));
    for (int j = 4; j <= 16; ++j)
        for (int i = 4; i <= 16; ++i) closed(i, j) = 0.0;
    CHECK(gap_light(closed, 6.0)(10, 10) == 1.0);
    CHECK(gap_light(closed, 6.0)(4, 4) < 0.6);
}

TEST_CASE("top_height_m is the mean height of the 100 tallest trees a hectare",
          "[eco][processes][establishment]") {
    Species tree, shrub;
    tree.life_form = LifeForm::tree;
    shrub.life_form = LifeForm::shrub;
    const std::vector<Species> species{tree, shrub};
    Population pop;
    CHECK(top_height_m(pop, species, 1.0) == 0.0);
    for (int k = 1; k <= 150; ++k) {
        Plant p;
        p.height_m = k;
        pop.push(p);
    }
    Plant tall_shrub;
    tall_shrub.species = 1;
    tall_shrub.height_m = 500;
    pop.push(tall_shrub);                                    // shrubs do not count
    CHECK(top_height_m(pop, species, 1.0) == Approx(100.5)); // mean of 51..150
    CHECK(top_height_m(pop, species, 0.5) == Approx(125.5)); // the 50 tallest
    CHECK(top_height_m(pop, species, 1e-4) == 150.0);        // at least one tree
    CHECK(top_height_m(pop, species, 10.0) == Approx(75.5)); // all 150
    pop.alive[149] = 0;                                      // the dead do not count
    CHECK(top_height_m(pop, species, 1e-4) == 149.0);
}

TEST_CASE("senescence: the size-related mortality rises as a power of the stem diameter",
          "[eco][growth]") {
    Species s;
    s.background_mortality_per_yr = 0.004;
    // Off by default: every size dies at the background rate.
    for (double d : {0.0, 0.01, 0.5, 3.0}) CHECK(background_mortality(s, d) == 0.004);
    s.senescence_mortality_per_yr = 0.02;
    s.senescence_diameter_m = 0.5;
    for (double k : {1.0, 2.0, 3.0, 4.5}) {
        CAPTURE(k);
        s.senescence_exponent = k;
        CHECK(background_mortality(s, 0.0) == 0.004);
        CHECK(background_mortality(s, 0.5) == Approx(0.024));
        CHECK(background_mortality(s, 1.0) == Approx(0.004 + 0.02 * std::pow(2.0, k)));
        CHECK(background_mortality(s, 0.25) == Approx(0.004 + 0.02 * std::pow(0.5, k)));
        // Monotone in the diameter, and a probability.
        double last = 0;
        for (double d = 0; d < 20; d += 0.05) {
            const double m = background_mortality(s, d);
            CHECK(m >= last);
            CHECK(m <= 1.0);
            last = m;
        }
        CHECK(background_mortality(s, 100.0) == 1.0);
    }
}

TEST_CASE("sort_by_stem_cell: rows kept whole, ordered by the stem's cell row by row, stable "
          "within a cell",
          "[eco][population]") {
    Rng rng(77, "sort_by_stem_cell");
    for (int stand = 0; stand < 10; ++stand) {
        GridSpec g = grid(8 + static_cast<int>(rng.uniform() * 40));
        g.origin_x_m = -100 + 200 * rng.uniform();
        g.cell_size_m = 0.5 + rng.uniform();
        const int n = static_cast<int>(rng.uniform() * 400);
        Population pop;
        for (int k = 0; k < n; ++k) {
            Plant p;
            p.id = 1000 + k;
            // Clustered stems (many share a cell) and a few outside the grid (clamped).
            const double span = (k % 3 == 0 ? 0.2 : 1.1) * g.width_m();
            p.x_m = g.origin_x_m + span * rng.uniform();
            p.y_m = g.origin_y_m + span * rng.uniform();
            p.dbh_m = rng.uniform();
            p.species = static_cast<std::uint16_t>(k % 5);
            p.alive = 1;
            pop.push(p);
        }
        const Population before = pop;
        sort_by_stem_cell(pop, g);
        REQUIRE(pop.size() == before.size());
        auto key = [&](const Population& q, std::size_t k) {
            const auto [i, j] = g.clamped_cell(q.x_m[k], q.y_m[k]);
            return static_cast<std::int64_t>(j) * g.nx + i;
        };
        std::vector<char> seen(before.size(), 0);
        for (std::size_t k = 0; k < pop.size(); ++k) {
            // Each row is one of the originals, whole, and none twice.
            const auto orig = static_cast<std::size_t>(pop.id[k] - 1000);
            REQUIRE(orig < before.size());
            CHECK(seen[orig] == 0);
            seen[orig] = 1;
            const Plant a = pop.plant(k), b = before.plant(orig);
            CHECK(std::memcmp(&a, &b, sizeof(Plant)) == 0);
            if (k == 0) continue;
            CHECK(key(pop, k - 1) <= key(pop, k));
            if (key(pop, k - 1) == key(pop, k)) CHECK(pop.id[k - 1] < pop.id[k]); // stable
        }
        // Sorting a sorted population changes nothing.
        const Population once = pop;
        sort_by_stem_cell(pop, g);
        CHECK(pop.bitwise_equal(once));
    }
}
