// Contract tests of the plant process kernels (processes.hpp): each process driven alone on a small
// population, checked for what it must conserve or keep (water, carbon, counts, the random streams,
// the geometry of the canopy), over several seeds.
#include "ecoterra/eco/ecosystem.hpp"
#include "ecoterra/eco/growth.hpp"
#include "ecoterra/eco/population.hpp"
#include "ecoterra/eco/processes.hpp"
#include "ecoterra/eco/scene_config.hpp"
#include "ecoterra/hydro/catchments.hpp"
#include "ecoterra/parallel.hpp"
#include "support/scenes.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <numeric>
#include <omp.h>
#include <set>

using namespace ecoterra;
using namespace ecoterra::eco;

namespace {
constexpr int kHydroCells = 8; ///< hydrology grid side
constexpr int kFactor = 2;     ///< plant cells per hydrology cell along a side
constexpr double kHydroCellM = 2.0;

GridSpec hydro_grid() {
    GridSpec g;
    g.nx = g.ny = kHydroCells;
    g.cell_size_m = kHydroCellM;
    return g;
}

/// Two tree species and an object, with the defaults of species.hpp.
std::vector<Species> test_species() {
    std::vector<Species> sp(3);
    sp[0].name = "broad";
    sp[1].name = "narrow";
    sp[1].max_crown_radius_m = 2.0;
    sp[1].shade = {0.1, 0.3};
    sp[2].name = "rock";
    sp[2].life_form = LifeForm::object;
    sp[2].max_height_m = 0.5;
    return sp;
}

/// The world a population lives in for the tests: a flat terrain, a uniform soil at a given
/// water content, a canopy on a grid `kFactor` times finer.
struct World {
    std::vector<Species> species = test_species();
    RasterD dem{hydro_grid(), 0.0};
    hydro::SoilMap soil = hydro::uniform_soil(hydro_grid(), {40, 40, 20, 6.5, std::nullopt});
    RasterD theta{hydro_grid(), 0.3};
    hydro::Catchments lakes{dem};
    Canopy canopy;
    GroundLayer ground;
    std::int64_t next_id = 1;
    World() {
        canopy.map.factor = kFactor;
        canopy.map.hydro_nx = kHydroCells;
        canopy.plant_grid = hydro_grid();
        canopy.plant_grid.nx = canopy.plant_grid.ny = kHydroCells * kFactor;
        canopy.plant_grid.cell_size_m = kHydroCellM / kFactor;
        canopy.ground_shade = RasterD(canopy.plant_grid, 0.0);
    }
    Nursery nursery(Competition c = Competition::coupled) {
        return {species, dem, soil, c, next_id};
    }
    SoilWater water() const { return {theta, soil}; }
    Seedbed seedbed() const { return {canopy, ground, species, 0.5, water(), lakes}; }
    /// `n` random plants of the two tree species (and every fifth an object).
    Population population(std::uint64_t seed, int n) {
        Rng rng(seed, "test.population");
        Population pop;
        const auto& g = canopy.plant_grid;
        for (int k = 0; k < n; ++k) {
            const auto sp = static_cast<std::uint16_t>(k % 5 == 4 ? 2 : rng.below(2));
            const double x = rng.uniform() * g.width_m(), y = rng.uniform() * g.height_m();
            pop.push(nursery().make(sp, x, y, rng.uniform(0.01, 0.3)));
            pop.age_yr.back() = std::floor(rng.uniform(0, 60));
        }
        canopy.refresh(pop, species, ShadingMode::blocking, 0.5);
        return pop;
    }
};

double carbon(const Population& pop) {
    double c = 0;
    for (std::size_t k = 0; k < pop.size(); ++k) c += pop.wood_kg[k] + pop.reserve_kg[k];
    return c;
}
} // namespace

TEST_CASE("population: rows, compaction and its checkpoint section round-trip",
          "[eco][processes][population]") {
    World w;
    Population pop = w.population(1, 40);
    REQUIRE(pop.size() == 40);
    for (std::size_t k = 0; k < pop.size(); ++k) {
        const Plant p = pop.plant(k);
        CHECK(p.id == pop.id[k]);
        CHECK(p.wood_kg == pop.wood_kg[k]);
    }
    ArchiveWriter a;
    pop.save(a);
    ArchiveReader r(a.bytes().data(), a.bytes().size(), "test");
    Population back;
    back.load(r);
    CHECK(r.at_end());
    CHECK(back.bitwise_equal(pop));
    std::vector<char> keep(pop.size());
    for (std::size_t k = 0; k < keep.size(); ++k) keep[k] = k % 3 != 0;
    back.keep_if(keep);
    CHECK(back.size() == 26);
    for (std::size_t k = 0, j = 0; k < pop.size(); ++k)
        if (keep[k]) CHECK(back.id[j++] == pop.id[k]);
    // A section whose columns differ in length is refused.
    Population broken = pop;
    broken.wood_kg.pop_back();
    ArchiveWriter b;
    broken.save(b);
    ArchiveReader rb(b.bytes().data(), b.bytes().size(), "test");
    CHECK_THROWS_WITH(back.load(rb), Catch::Contains("differ in length"));
}

TEST_CASE("water demand and supply: the cells ask what the plants demand, the plants get what "
          "the cells supply",
          "[eco][processes][water]") {
    for (std::uint64_t seed : {1, 2, 3, 4, 5}) {
        CAPTURE(seed);
        World w;
        Population pop = w.population(seed, 60);
        pop.alive[3] = 0; // a starved plant asks for nothing
        const DayClimate day = day_climate(w.species, 180, 22.0);
        std::vector<double> demand, request(static_cast<std::size_t>(w.dem.size()), 0.0);
        plant_water_demand(pop, w.species, day.phen, 0.004, GrowthModel::paper002, demand);
        CHECK(demand[3] == 0.0);
        // light_and_turnover: each plant asks in proportion to the light on its crown.
        std::vector<double> by_light;
        plant_water_demand(pop, w.species, day.phen, 0.004, GrowthModel::light_and_turnover,
                           by_light);
        for (std::size_t k = 0; k < pop.size(); ++k)
            CHECK(by_light[k] == Approx(demand[k] * (1.0 - pop.shade_fraction[k])));
        scatter_demand(w.canopy.roots, demand, request);
        // Two quantities in one pass: each the same bits as its own scatter (leaves of some
        // plants zero, demand of others zero).
        std::vector<double> leaves(pop.size()), demand_some = demand;
        for (std::size_t k = 0; k < pop.size(); ++k) {
            leaves[k] = k % 5 == 1 ? 0.0 : pop.leaf_area_m2[k];
            if (k % 7 == 2) demand_some[k] = 0.0;
        }
        std::vector<double> one_a(request.size(), 0.0), one_b(request.size(), 0.0),
            pair_a(request.size(), 0.0), pair_b(request.size(), 0.0);
        scatter_demand(w.canopy.roots, demand_some, one_a);
        scatter_demand(w.canopy.roots, leaves, one_b);
        scatter_pair(w.canopy.roots, demand_some, leaves, pair_a, pair_b);
        CHECK(std::memcmp(one_a.data(), pair_a.data(), one_a.size() * sizeof(double)) == 0);
        CHECK(std::memcmp(one_b.data(), pair_b.data(), one_b.size() * sizeof(double)) == 0);
        CHECK(std::accumulate(pair_b.begin(), pair_b.end(), 0.0) > 0);
        // And on large stands, the two scatters side by side on two threads (here forced on
        // this small one), on 1 to 3 threads: the same bits again.
        const int saved_threads = omp_get_max_threads();
        set_parallel_min_items(1);
        for (int threads : {1, 2, 3}) {
            CAPTURE(threads);
            omp_set_num_threads(threads);
            std::vector<double> par_a(request.size(), 0.0), par_b(request.size(), 0.0);
            scatter_pair(w.canopy.roots, demand_some, leaves, par_a, par_b);
            CHECK(std::memcmp(one_a.data(), par_a.data(), one_a.size() * sizeof(double)) == 0);
            CHECK(std::memcmp(one_b.data(), par_b.data(), one_b.size() * sizeof(double)) == 0);
        }
        omp_set_num_threads(saved_threads);
        set_parallel_min_items(kMinParallelItems);
        const double asked = std::accumulate(demand.begin(), demand.end(), 0.0);
        CHECK(std::accumulate(request.begin(), request.end(), 0.0) == Approx(asked).epsilon(1e-12));
        // A supply of a seeded share of each cell's request.
        Rng rng(seed, "test.supply");
        RasterD req_mm(w.dem.grid(), 0.0), sup_mm(w.dem.grid(), 0.0);
        double supplied_m3 = 0;
        for (std::int64_t c = 0; c < req_mm.size(); ++c) {
            req_mm.data()[c] = request[static_cast<std::size_t>(c)];
            sup_mm.data()[c] = req_mm.data()[c] * rng.uniform();
            supplied_m3 += sup_mm.data()[c];
        }
        std::vector<double> ratio, fraction;
        supply_fractions(w.canopy.roots, req_mm, sup_mm, ratio, fraction);
        double received = 0;
        for (std::size_t k = 0; k < pop.size(); ++k) {
            CHECK(fraction[k] >= 0.0);
            CHECK(fraction[k] <= 1.0);
            received += demand[k] * fraction[k];
        }
        CHECK(received == Approx(supplied_m3).epsilon(1e-10));
        // A full supply meets every demand.
        supply_fractions(w.canopy.roots, req_mm, req_mm, ratio, fraction);
        for (const double f : fraction) CHECK(f == 1.0);
    }
}

TEST_CASE("carbon balance: each plant's pools change by its production less respiration and "
          "turnover, and the sums are the plants'",
          "[eco][processes][carbon]") {
    for (std::uint64_t seed : {1, 2, 3}) {
        CAPTURE(seed);
        World w;
        Population pop = w.population(seed, 50);
        pop.reserve_kg[0] = 1e-9; // starves in the dark
        pop.shade_fraction[0] = 1.0;
        const Population before = pop;
        const std::vector<double> demand(pop.size(), 0.01);
        std::vector<double> fraction(pop.size());
        Rng rng(seed, "test.fraction");
        for (double& f : fraction) f = rng.uniform();
        PlantSums sums;
        carbon_balance(pop, w.species, day_climate(w.species, 200, 10.0), fraction, demand,
                       GrowthModel::paper002, sums);
        CHECK(carbon(pop) - carbon(before) ==
              Approx(sums.production - sums.maintenance - sums.growth_resp - sums.turnover)
                  .margin(1e-12));
        double starved = 0;
        for (std::size_t k = 0; k < pop.size(); ++k) {
            if (w.species[pop.species[k]].life_form == LifeForm::object) {
                CHECK(pop.wood_kg[k] == before.wood_kg[k]);
                CHECK(pop.reserve_kg[k] == before.reserve_kg[k]);
            }
            starved += pop.alive[k] ? 0 : 1;
        }
        CHECK(pop.alive[0] == 0);
        CHECK(sums.deaths_starvation == starved);
        CHECK(sums.demand_m3 == Approx(0.01 * static_cast<double>(pop.size())));
        CHECK(sums.supplied_m3 ==
              Approx(0.01 * std::accumulate(fraction.begin(), fraction.end(), 0.0)));
    }
}

TEST_CASE("canopy: structure follows the wood, shade stays in [0, 1], roots share out whole",
          "[eco][processes][canopy]") {
    World w;
    Population pop = w.population(7, 80);
    for (std::size_t k = 0; k < pop.size(); ++k) pop.wood_kg[k] *= 1.5;
    const Population before = pop;
    refresh_structure(pop, w.species);
    for (std::size_t k = 0; k < pop.size(); ++k) {
        const Species& s = w.species[pop.species[k]];
        if (s.life_form == LifeForm::object) {
            CHECK(pop.dbh_m[k] == before.dbh_m[k]);
            continue;
        }
        CHECK(allometry::stem_mass_kg(s, pop.dbh_m[k]) == Approx(pop.wood_kg[k]).epsilon(1e-9));
        CHECK(pop.dbh_m[k] > before.dbh_m[k]);
    }
    w.canopy.refresh(pop, w.species, ShadingMode::beer_lambert, 0.5);
    for (const double s : pop.shade_fraction) {
        CHECK(s >= 0.0);
        CHECK(s <= 1.0);
    }
    // The cell shade is the mean of the ground shade over each cell's plant cells.
    double ground = 0, cells = 0;
    for (std::int64_t c = 0; c < w.canopy.ground_shade.size(); ++c)
        ground += w.canopy.ground_shade.data()[c];
    for (const double v : w.canopy.cell_shade) cells += v;
    CHECK(cells * kFactor * kFactor == Approx(ground));
    for (std::size_t p = 0; p < w.canopy.roots.size(); ++p) {
        double share = 0;
        for (auto e = w.canopy.roots.offset[p]; e < w.canopy.roots.offset[p + 1]; ++e)
            share += w.canopy.roots.share[e] * w.canopy.roots.cells_of(e);
        CHECK(share == Approx(1.0));
    }
    // Vegetation density is the crown cover without a ground layer, in [0, 1].
    const RasterD density = w.canopy.vegetation_density(w.ground, w.dem.grid());
    for (std::int64_t c = 0; c < density.size(); ++c) {
        CHECK(density.data()[c] == Approx(w.canopy.cell_shade[static_cast<std::size_t>(c)]));
    }
}

TEST_CASE("mortality: one draw per plant, deaths counted by one cause each",
          "[eco][processes][demography]") {
    for (std::uint64_t seed : {1, 2, 3, 4}) {
        CAPTURE(seed);
        World w;
        for (auto& s : w.species) s.background_mortality_per_yr = 0.2, s.max_age_yr = 50;
        Population pop = w.population(seed, 100);
        pop.alive[5] = 0; // starved earlier this year: not counted again, but drawn for
        const Population before = pop;
        Rng rng(seed, "test.mortality"), twin(seed, "test.mortality");
        PlantSums sums;
        const auto dead = ageing_and_mortality(pop, w.species, rng, sums);
        for (std::size_t k = 0; k < pop.size(); ++k) twin.uniform();
        CHECK(rng.state() == twin.state());
        auto count = [&](DeathCause c) {
            return static_cast<double>(std::count(dead.begin(), dead.end(), static_cast<char>(c)));
        };
        const double flagged =
            static_cast<double>(dead.size() - static_cast<std::size_t>(count(DeathCause::none)));
        CHECK(flagged == sums.deaths_age + sums.deaths_background + sums.deaths_suppression);
        CHECK(count(DeathCause::age) == sums.deaths_age);
        CHECK(count(DeathCause::background) == sums.deaths_background);
        CHECK(count(DeathCause::suppression) == sums.deaths_suppression);
        CHECK(dead[5] == 0);
        CHECK(pop.age_yr[5] == before.age_yr[5]);
        for (std::size_t k = 0; k < pop.size(); ++k) {
            if (k != 5) CHECK(pop.age_yr[k] == before.age_yr[k] + 1);
            if (pop.age_yr[k] >= 50 && pop.alive[k])
                CHECK(dead[k] == static_cast<char>(DeathCause::age));
        }
        // Removing the dead moves exactly their carbon into the dead carbon.
        for (std::size_t k = 0; k < pop.size(); ++k)
            if (dead[k]) pop.alive[k] = 0;
        const double c0 = carbon(pop);
        remove_dead(pop, sums);
        CHECK(c0 - carbon(pop) == Approx(sums.dead_carbon));
        CHECK(pop.size() == 100 - static_cast<std::size_t>(flagged) - 1);
    }
}

TEST_CASE("mortality: large trees die at the background rate plus the size-related arm",
          "[eco][processes][demography]") {
    // 3000 trees of 10 cm and 3000 of 60 cm; the death fraction of each size class against
    // its probability, within 4.5 binomial standard deviations, over several seeds.
    World w;
    for (auto& s : w.species) {
        s.background_mortality_per_yr = 0.01, s.max_age_yr = 1000;
        s.suppression_mortality_per_yr = 0;
        s.senescence_mortality_per_yr = 0.1, s.senescence_diameter_m = 0.5;
        s.senescence_exponent = 2.0;
    }
    for (std::uint64_t seed : {1, 2, 3}) {
        CAPTURE(seed);
        Population pop;
        const int n = 3000;
        for (int k = 0; k < 2 * n; ++k) pop.push(w.nursery().make(0, 5.0, 5.0, k < n ? 0.1 : 0.6));
        Rng rng(seed, "test.senescence");
        PlantSums sums;
        const auto dead = ageing_and_mortality(pop, w.species, rng, sums);
        const double expected[2] = {background_mortality(w.species[0], 0.1),
                                    background_mortality(w.species[0], 0.6)};
        CHECK(expected[0] == Approx(0.01 + 0.1 * 0.04));
        CHECK(expected[1] == Approx(0.01 + 0.1 * 1.44));
        for (int cls = 0; cls < 2; ++cls) {
            const auto first = dead.begin() + cls * n;
            const auto died =
                std::count(first, first + n, static_cast<char>(DeathCause::background));
            const double p = expected[cls], sd = std::sqrt(n * p * (1 - p));
            CHECK(std::abs(static_cast<double>(died) - n * p) < 4.5 * sd);
        }
        CHECK(sums.deaths_background ==
              static_cast<double>(
                  std::count(dead.begin(), dead.end(), static_cast<char>(DeathCause::background))));
    }
}

TEST_CASE("seeding: every seed lands or is lost, recruits stand on the grid with fresh ids",
          "[eco][processes][demography]") {
    for (std::uint64_t seed : {1, 2, 3}) {
        CAPTURE(seed);
        World w;
        for (auto& s : w.species) {
            s.maturity_age_yr = 0;
            s.germination_probability = 1.0;
            s.germination_min_light = 0.0;
            s.germination_min_soil_water = -1.0;
            s.new_per_area_per_yr = 0.05;
            s.seeds_per_yr_at_30cm = 20;
        }
        Population pop = w.population(seed, 30);
        for (std::size_t k = 0; k < pop.size(); ++k) pop.growth_sum[k] = pop.growth_days[k] = 100;
        const std::vector<char> dead(pop.size(), 0);
        Rng rng(seed, "test.seeding");
        PlantSums sums;
        const std::int64_t id0 = w.next_id;
        auto recruits = seed_dispersal(pop, dead, w.species, w.canopy.plant_grid, w.seedbed(),
                                       w.nursery(), rng, sums);
        const auto from_seed = static_cast<double>(recruits.size());
        CHECK(sums.seeds > 0);
        CHECK(from_seed + sums.seeds_lost <= sums.seeds);
        background_arrivals(w.species, w.canopy.plant_grid, w.seedbed(), w.nursery(), rng,
                            recruits);
        std::set<std::int64_t> ids;
        const auto& g = w.canopy.plant_grid;
        for (const Plant& r : recruits) {
            CHECK(r.x_m >= 0);
            CHECK(r.x_m < g.width_m());
            CHECK(r.y_m >= 0);
            CHECK(r.y_m < g.height_m());
            CHECK(r.id >= id0);
            ids.insert(r.id);
        }
        CHECK(ids.size() == recruits.size());
        CHECK(w.next_id == id0 + static_cast<std::int64_t>(recruits.size()));
    }
}

TEST_CASE("light-only: thinning leaves no two circles overlapping and counts what it removes",
          "[eco][processes][light_only]") {
    for (const LightOnlyRadius rule : {LightOnlyRadius::mavs, LightOnlyRadius::crown}) {
        World w;
        Population pop = w.population(11, 120);
        PlantSums sums;
        std::vector<char> dead = light_only_growth(pop, w.species, sums);
        overlap_thinning(pop, dead, w.species, w.canopy.plant_grid, rule, sums);
        auto radius = [&](std::size_t k) {
            return rule == LightOnlyRadius::crown
                       ? pop.crown_radius_m[k]
                       : 0.5 * w.species[pop.species[k]].height_to_diameter_ratio * pop.height_m[k];
        };
        for (std::size_t i = 0; i < pop.size(); ++i)
            for (std::size_t k = i + 1; k < pop.size(); ++k)
                if (!dead[i] && !dead[k])
                    CHECK(std::hypot(pop.x_m[i] - pop.x_m[k], pop.y_m[i] - pop.y_m[k]) >=
                          radius(i) + radius(k));
        CHECK(static_cast<double>(
                  std::count(dead.begin(), dead.end(), static_cast<char>(DeathCause::overlap))) ==
              sums.deaths_overlap);
        CHECK(static_cast<double>(
                  std::count(dead.begin(), dead.end(), static_cast<char>(DeathCause::age))) ==
              sums.deaths_age);
        // An initial stem's age on the growth curve is the first whole year that reaches its
        // diameter.
        const Species& s = w.species[0];
        const double d = light_only_dbh_m(s, 12.5);
        CHECK(light_only_age_yr(s, d) == 13);
        CHECK(light_only_dbh_m(s, 12) < d);
    }
}

namespace {
/// MAVS's competition written out pair by pair, as ecosystem.cpp's loops are (every pair, both
/// orders; the smaller circle dies, equal circles both): the reference for mavs_step.
std::vector<char> mavs_pairs_brute_force(const Population& pop, const std::vector<Species>& sp) {
    std::vector<char> killed(pop.size(), 0);
    auto r = [&](std::size_t k) {
        return 0.5 * sp[pop.species[k]].height_to_diameter_ratio * pop.height_m[k];
    };
    for (std::size_t i = 0; i < pop.size(); ++i)
        for (std::size_t j = 0; j < pop.size(); ++j)
            if (i != j &&
                std::hypot(pop.x_m[i] - pop.x_m[j], pop.y_m[i] - pop.y_m[j]) < r(i) + r(j))
                killed[r(i) > r(j) ? j : i] = 1;
    return killed;
}
} // namespace

TEST_CASE("MAVS's ecosystem step: heights on its curve, its arrivals, every overlapping pair",
          "[eco][processes][light_only][mavs]") {
    World w;
    for (auto& s : w.species) s.height_to_diameter_ratio = 0.5; // circles that meet often
    SECTION("the competition equals MAVS's pair loops on random stands") {
        for (std::uint64_t seed = 1; seed <= 20; ++seed) {
            for (auto& s : w.species) s.new_per_area_per_yr = 0;
            Population pop = w.population(seed, 150);
            PlantSums sums;
            const auto before = pop.size();
            Rng rng(seed);
            std::vector<char> dead = mavs_step(pop, w.species, w.canopy.plant_grid, 1.0,
                                               w.nursery(Competition::light_only), rng, sums);
            REQUIRE(pop.size() == before);
            const std::vector<char> expected = mavs_pairs_brute_force(pop, w.species);
            std::int64_t overlap = 0;
            for (std::size_t k = 0; k < pop.size(); ++k) {
                const bool aged = pop.age_yr[k] > w.species[pop.species[k]].max_age_yr;
                CHECK((dead[k] != 0) == (expected[k] != 0 || aged));
                overlap += dead[k] == static_cast<char>(DeathCause::overlap);
            }
            CHECK(static_cast<double>(overlap) == sums.deaths_overlap);
            CHECK(sums.deaths_overlap > 0);
        }
    }
    SECTION(
        "a chain: the middle plant, overtopped, still kills the smallest; equal ones both die") {
        Population pop;
        Nursery make = w.nursery(Competition::light_only);
        for (const double x : {1.0, 5.5, 7.5, 11.5, 13.5}) pop.push(make.make(0, x, 8, 0.0));
        const double h[] = {12.0, 8.0, 4.0, 6.0, 6.0}; // circles 3, 2, 1, 1.5, 1.5 m (slow growth)
        for (std::size_t k = 0; k < 5; ++k) pop.height_m[k] = h[k];
        for (auto& s : w.species) s.new_per_area_per_yr = 0;
        w.species[0].max_height_m = 30;
        w.species[0].growth_rate_per_yr = 0.005;
        PlantSums sums;
        Rng rng(1);
        const auto dead = mavs_step(pop, w.species, w.canopy.plant_grid, 1.0, make, rng, sums);
        CHECK(dead[0] == 0);
        CHECK(dead[1] == static_cast<char>(DeathCause::overlap));
        CHECK(dead[2] == static_cast<char>(DeathCause::overlap)); // a greedy rule would keep it
        CHECK(dead[3] == static_cast<char>(DeathCause::overlap));
        CHECK(dead[4] == static_cast<char>(DeathCause::overlap));
    }
    SECTION("a lone plant follows H(t) = Hmax (1 - exp(-r t)) and dies once over Max Age") {
        Species& s = w.species[0];
        s.growth_rate_per_yr = 0.05;
        s.max_age_yr = 30;
        for (auto& q : w.species) q.new_per_area_per_yr = 0;
        Population pop;
        Nursery make = w.nursery(Competition::light_only);
        pop.push(make.make(0, 5, 5, 0.0));
        pop.height_m[0] = 3.0;
        const double t0 = -std::log(1 - 3.0 / s.max_height_m) / s.growth_rate_per_yr;
        Rng rng(1);
        for (int year = 1; year <= 31; ++year) {
            PlantSums sums;
            const auto dead = mavs_step(pop, w.species, w.canopy.plant_grid, 1.0, make, rng, sums);
            CHECK(pop.height_m[0] ==
                  Approx(s.max_height_m * (1 - std::exp(-s.growth_rate_per_yr * (t0 + year))))
                      .epsilon(1e-12));
            CHECK(pop.dbh_m[0] == Approx(allometry::dbh_from_height_m(s, pop.height_m[0])));
            CHECK(allometry::height_m(s, pop.dbh_m[0]) ==
                  Approx(std::max(pop.height_m[0], kBreastHeightM)).epsilon(1e-9));
            CHECK((dead[0] == static_cast<char>(DeathCause::age)) == (year > 30));
        }
    }
    SECTION("arrivals: floor(A g n) plus one with the remainder's probability, heights in "
            "[0, H(1)]") {
        const auto& g = w.canopy.plant_grid;
        const double area = g.width_m() * g.height_m(); // 256 m2
        for (auto& s : w.species) s.new_per_area_per_yr = 0;
        w.species[0].new_per_area_per_yr = 0.0123; // A n = 3.1488
        const double density = 2.5;                // A g n = 7.872
        const double expected = area * density * 0.0123;
        Rng rng(7);
        double total = 0;
        const int years = 4000;
        Nursery make = w.nursery(Competition::light_only);
        for (int y = 0; y < years; ++y) {
            Population pop;
            PlantSums sums;
            (void)mavs_step(pop, w.species, g, density, make, rng, sums);
            CHECK((pop.size() == 7 || pop.size() == 8));
            for (std::size_t k = 0; k < pop.size(); ++k) {
                CHECK(pop.age_yr[k] == 1);
                CHECK(pop.height_m[k] <= mavs_height_m(w.species[0], 2.0));
            }
            total += static_cast<double>(pop.size());
        }
        // The remainder 0.872 is a Bernoulli draw: its mean within 4 sigma.
        const double sigma = std::sqrt(0.872 * 0.128 / years);
        CHECK(std::abs(total / years - expected) < 4 * sigma);
    }
}

TEST_CASE("carbon budget: closes on consistent sums and names the year when a kilogram appears",
          "[eco][processes][carbon]") {
    World w;
    Population pop = w.population(3, 20);
    CarbonLedger ledger;
    ledger.stock_at_year_start_kg = carbon(pop);
    PlantSums sums;
    carbon_balance(pop, w.species, day_climate(w.species, 200, 20.0),
                   std::vector<double>(pop.size(), 1.0), std::vector<double>(pop.size(), 0.0),
                   GrowthModel::light_and_turnover, sums);
    const CarbonStocks c = close_carbon_budget(pop, sums, DeadWoodBudget{}, 1, ledger);
    CHECK(std::abs(c.residual_kg) < 1e-9 * std::max(1.0, c.wood_kg));
    CHECK(ledger.stock_at_year_start_kg == Approx(c.wood_kg + c.reserve_kg));
    pop.wood_kg[0] += 1.0;
    CHECK_THROWS_WITH(close_carbon_budget(pop, PlantSums{}, DeadWoodBudget{}, 2, ledger),
                      Catch::Contains("carbon budget broke in year 2"));
}

TEST_CASE("the year's water: each yearly sum is its days' sum, and every mode asks for water",
          "[eco][water]") {
    // Coupled and light-only stands on the small scene: the yearly water columns are the daily
    // budget summed over each year; light-only plants transpire too under FAO-56 (their leaves
    // shade the soil and ask for water), and nothing under paper 002's light-only baseline.
    const std::string mode = GENERATE("coupled", "light_only");
    const bool paper = GENERATE(false, true);
    nlohmann::json j = test::small_scene(3, mode);
    if (paper) j["hydrology"]["evapotranspiration"] = "paper002";
    INFO(mode << (paper ? ", paper 002" : ", FAO-56"));
    const auto scene = eco::load_eco_scene(j, test::data_dir() / "scenes");
    eco::Ecosystem e(scene);
    for (int y = 0; y < 3; ++y) e.run_year();
    const Table& daily = e.daily();
    const Table& yearly = e.yearly();
    REQUIRE(yearly.rows() == 3);
    for (const char* c : {"rain_mm", "evaporation_mm", "transpiration_mm", "interception_mm",
                          "runoff_out_mm", "drainage_out_mm", "recharge_mm"}) {
        for (std::size_t y = 0; y < 3; ++y) {
            double sum = 0;
            for (std::size_t d = 365 * y; d < 365 * (y + 1); ++d) sum += daily.column(c)[d];
            CHECK(yearly.column(c)[y] == Approx(sum).epsilon(1e-12).margin(1e-12));
        }
    }
    double transpired = 0;
    for (double v : yearly.column("transpiration_mm")) transpired += v;
    if (mode == "light_only" && paper)
        CHECK(transpired == 0.0);
    else
        CHECK(transpired > 10.0);
    CHECK(yearly.column("rain_mm")[0] > 0);
}

TEST_CASE("growth models: light_and_turnover closes its carbon budget and sheds litter that paper "
          "002's model does not",
          "[eco][growth]") {
    // The same small stand for 3 years under each growth model. The run checks the carbon budget
    // every year end (it throws past 1e-9); the leaves and fine roots rebuilt under
    // light_and_turnover leave as litter in the turnover column, where paper 002's model turns
    // over only the wood surplus of trees at their maximum diameter.
    std::vector<double> turnover;
    for (const char* model : {"paper002", "light_and_turnover"}) {
        nlohmann::json j = test::small_scene(3);
        j["vegetation"]["growth"] = model;
        j["vegetation"]["shading"] = "beer_lambert";
        INFO(model);
        eco::Ecosystem e(eco::load_eco_scene(j, test::data_dir() / "scenes"));
        for (int y = 0; y < 3; ++y) REQUIRE_NOTHROW(e.run_year());
        CHECK(std::abs(e.carbon_residual_relative()) < 1e-9);
        double sum = 0;
        for (const double v : e.yearly().column("turnover_kg")) sum += v;
        turnover.push_back(sum);
    }
    CHECK(turnover[0] == 0.0);
    CHECK(turnover[1] > 0.0);
}

TEST_CASE("seedbed: a seed in a small opening of a closed canopy gets its gap's light",
          "[eco][processes][establishment]") {
    // Full shade everywhere but one plant cell. By the cell's own light (paper 002's shading) a
    // seed there always passes the light test; by the gap's light over a 5 x 5 window (a top
    // height of 4 cells) it never does, and in a clearing wider than the window it always does.
    World w;
    w.species[0].germination_min_light = 0.3;
    w.species[0].germination_probability = 1.0;
    w.species[0].texture_tolerance_pct = 1e6; // the soil never refuses
    w.species[0].ph = {6.5, 1e6};
    auto& shade = w.canopy.ground_shade;
    for (std::int64_t c = 0; c < shade.size(); ++c) shade.data()[c] = 1.0;
    const auto& g = w.canopy.plant_grid;
    const int ci = g.nx / 2, cj = g.ny / 2;
    shade(ci, cj) = 0.0;
    const double x = g.x_of(ci), y = g.y_of(cj);
    const RasterD gap = gap_light(shade, 2 * g.cell_size_m);
    Seedbed own = w.seedbed();
    Seedbed by_gap = w.seedbed();
    by_gap.cell_light = gap;
    Rng rng(5, "test.seedbed");
    int own_ok = 0, gap_ok = 0;
    for (int k = 0; k < 50; ++k) {
        own_ok += own.establishes(w.species[0], x, y, rng);
        gap_ok += by_gap.establishes(w.species[0], x, y, rng);
    }
    CHECK(own_ok == 50);
    CHECK(gap_ok == 0);
    for (int j = cj - 3; j <= cj + 3; ++j)
        for (int i = ci - 3; i <= ci + 3; ++i) shade(i, j) = 0.0;
    const RasterD clearing = gap_light(shade, 2 * g.cell_size_m);
    by_gap.cell_light = clearing;
    for (int k = 0; k < 50; ++k) gap_ok += by_gap.establishes(w.species[0], x, y, rng);
    CHECK(gap_ok == 50);
}

TEST_CASE("seedbed: under the gap light a recruit's chance scales with its growth in that light",
          "[eco][processes][establishment]") {
    // A uniform light L everywhere: by the gap light the fraction established is p f_L(L) (the
    // species' light response of production), by the cell's own light (paper 002's shading) it is
    // p; binomial bounds of 4.5 standard deviations over several lights and half-saturations.
    World w;
    Species& s = w.species[0];
    s.germination_min_light = 0.0;
    s.germination_probability = 0.6;
    s.texture_tolerance_pct = 1e6;
    s.ph = {6.5, 1e6};
    const auto& g = w.canopy.plant_grid;
    int case_no = 0;
    for (const double k_half : {0.1, 0.3, 1.0}) {
        for (const double light : {0.05, 0.2, 0.5, 1.0}) {
            CAPTURE(k_half, light);
            s.light_half_saturation = k_half;
            auto& shade = w.canopy.ground_shade;
            for (std::int64_t c = 0; c < shade.size(); ++c) shade.data()[c] = 1.0 - light;
            Seedbed own = w.seedbed();
            Seedbed by_gap = w.seedbed();
            by_gap.cell_light = RasterD(g, light);
            Rng rng(static_cast<std::uint64_t>(++case_no), "test.seedbed.growth");
            const int n = 4000;
            int own_ok = 0, gap_ok = 0;
            for (int k = 0; k < n; ++k) {
                const double x = rng.uniform() * g.width_m(), y = rng.uniform() * g.height_m();
                own_ok += own.establishes(s, x, y, rng);
                gap_ok += by_gap.establishes(s, x, y, rng);
            }
            const double p_own = 0.6, p_gap = 0.6 * light_factor(k_half, light);
            CHECK(std::abs(own_ok - n * p_own) < 4.5 * std::sqrt(n * p_own * (1 - p_own)));
            CHECK(std::abs(gap_ok - n * p_gap) < 4.5 * std::sqrt(n * p_gap * (1 - p_gap)) + 1e-9);
            if (light < 1.0) CHECK(p_gap < 0.95 * p_own); // the test can tell them apart
        }
    }
    // The ledger blames the light for a draw the soil alone would have passed.
    s.germination_probability = 1.0;
    s.light_half_saturation = 0.3;
    std::vector<SpeciesLedger> ledger(w.species.size());
    Seedbed by_gap = w.seedbed();
    by_gap.cell_light = RasterD(g, 0.1);
    by_gap.ledger = &ledger;
    Rng rng(99, "test.seedbed.ledger");
    int ok = 0;
    for (int k = 0; k < 2000; ++k) ok += by_gap.establishes(s, 5.0, 5.0, rng);
    const SpeciesLedger& l = ledger[0];
    CHECK(l.attempts == 2000);
    CHECK(l.established == ok);
    CHECK(l.failed_draw == 0);
    CHECK(l.failed_light == 2000 - ok);
    CHECK(l.failed_light > 0);
}

TEST_CASE("the plants stay ordered by their stem's cell through births, deaths and both year ends",
          "[eco][population]") {
    // The per-cell passes rely on it for their speed (sort_by_stem_cell); the year's recruits are
    // appended and must be sorted in before the canopy is rebuilt.
    // In birth order (vegetation.plant_order = birth) the ids rise instead.
    const std::string mode = GENERATE("coupled", "light_only");
    const bool birth = GENERATE(false, true);
    INFO(mode << (birth ? ", birth order" : ", stem-cell order"));
    nlohmann::json js = test::small_scene(4, mode);
    if (birth) js["vegetation"]["plant_order"] = "birth";
    const auto scene = eco::load_eco_scene(js, test::data_dir() / "scenes");
    eco::Ecosystem e(scene);
    const GridSpec& g = e.plant_grid();
    std::int64_t first_max_id = -1, max_id = -1;
    for (int y = 0; y <= 4; ++y) {
        if (y > 0) e.run_year();
        const eco::Population& pop = e.plants();
        REQUIRE(pop.size() > 1);
        std::int64_t last = -1;
        for (std::size_t k = 0; k < pop.size(); ++k) {
            const auto [i, j] = g.clamped_cell(pop.x_m[k], pop.y_m[k]);
            const std::int64_t key = birth ? pop.id[k] : static_cast<std::int64_t>(j) * g.nx + i;
            CHECK(key >= last);
            last = key;
        }
        max_id = *std::max_element(pop.id.begin(), pop.id.end());
        if (y == 0) first_max_id = max_id;
    }
    // Plants were born (ids above the first year's), so the check saw recruits sorted in.
    CHECK(max_id > first_max_id);
}
