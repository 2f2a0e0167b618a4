// Dead wood (deadwood.hpp): the decay classes and geometry against their sources, a single log
// decaying at its rate, snags falling at FVS-FFE's rate (many snags, a statistical test), fall
// directions on slopes and on the flat, the checkpoint, and the engine: living stand unchanged by
// dead wood, the dead-wood budget closing year by year, bad keys refused.
#include "ecoterra/eco/deadwood.hpp"
#include "ecoterra/eco/ecosystem.hpp"
#include "ecoterra/eco/scene_config.hpp"
#include "ecoterra/error.hpp"
#include "support/scenes.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <fstream>
#include <numbers>

using namespace ecoterra;
using namespace ecoterra::eco;

namespace {

constexpr double kPi = std::numbers::pi;

GridSpec grid(int n, double cell) {
    GridSpec g;
    g.nx = g.ny = n;
    g.cell_size_m = cell;
    return g;
}

/// A plane z = sx x over a 100 m square (sx = 0: flat).
RasterD plane(double sx) {
    RasterD r(grid(50, 2.0), 0.0);
    for (int j = 0; j < 50; ++j)
        for (int i = 0; i < 50; ++i) r(i, j) = sx * (i + 0.5) * 2.0;
    return r;
}

/// `n` dead trees of one size at the middle of the plane, of species 0.
Population dead_trees(int n, double dbh_m, double height_m, double wood_kg) {
    Population pop;
    for (int k = 0; k < n; ++k) {
        Plant p;
        p.id = k + 1;
        p.x_m = 40.0 + 20.0 * (k % 100) / 100.0;
        p.y_m = 40.0 + 20.0 * (k / 100 % 100) / 100.0;
        p.dbh_m = dbh_m;
        p.height_m = height_m;
        p.wood_kg = wood_kg;
        pop.push(p);
        pop.alive.back() = 0;
    }
    return pop;
}

std::vector<Species> one_tree_species() {
    std::vector<Species> sp(1);
    sp[0].name = "tree";
    return sp;
}

} // namespace

TEST_CASE("dead wood: decay classes, snag tops and the taper follow their sources",
          "[eco][deadwood]") {
    using namespace deadwood;
    // iLand's thresholds: > 0.9 class 1, > 0.7 class 2, > 0.4 class 3, > 0.2 class 4, else 5.
    CHECK(decay_class(1.0) == 1);
    CHECK(decay_class(0.9000001) == 1);
    CHECK(decay_class(0.9) == 2);
    CHECK(decay_class(0.7) == 3);
    CHECK(decay_class(0.4) == 4);
    CHECK(decay_class(0.2) == 5);
    CHECK(decay_class(0.0) == 5);
    // A snag keeps its whole height in class 1, loses its top (above 10.16 cm) with the class, and
    // never its bole; the heights fall with the class.
    const double dbh = 0.4, h = 25.0;
    const double z4 = h - 0.1016 / dbh * (h - 1.3);
    CHECK(snag_height_m(dbh, h, 1) == Approx(h));
    CHECK(snag_height_m(dbh, h, 2) == Approx(z4 + 0.5 * (h - z4)));
    CHECK(snag_height_m(dbh, h, 5) == Approx(z4));
    for (int c = 1; c < 5; ++c) CHECK(snag_height_m(dbh, h, c + 1) < snag_height_m(dbh, h, c));
    // The bole's diameter where the top starts is the top diameter.
    CHECK(stem_diameter_m(dbh, h, z4) == Approx(0.1016));
    CHECK(stem_diameter_m(dbh, h, 0.5) == dbh);
    CHECK(stem_diameter_m(dbh, h, h) == 0.0);
    // Relative density falls with the class (Domke et al. 2011), so a piece's volume is never
    // more than its stem at death, and a class-5 piece keeps a fraction of it.
    Species s;
    DeadStem d;
    d.mass0_kg = 600.0;
    for (double f = 1.0; f > 0.05; f -= 0.01) {
        d.mass_kg = f * d.mass0_kg;
        CHECK(volume_m3(s, d) <= d.mass0_kg / s.wood_density_kg_per_m3 * (1 + 1e-12));
    }
    d.mass_kg = 0.1 * d.mass0_kg;
    CHECK(volume_m3(s, d) == Approx(1.0 * 0.1 / 0.52));
}

TEST_CASE("dead wood: snag fall spans are FVS-FFE's NI base rates", "[eco][deadwood]") {
    // FFE NI: a share 0.064311 - 0.001679 D_in of the original snags falls each year (at least
    // 0.01): 10 in 4.8 %/yr, 20 in 3.1 %/yr, 30 in 1.4 %/yr (reference deadwood.md, derived from
    // fmsfall.f); 40 in is at the floor.
    const Species s;
    for (const auto& [inches, pct] :
         std::vector<std::pair<double, double>>{{10, 4.8}, {20, 3.1}, {30, 1.4}, {40, 1.0}}) {
        CAPTURE(inches);
        const double span = deadwood::snag_fall_span_yr(s, inches * 0.0254);
        CHECK(100.0 / span == Approx(pct).margin(0.05));
    }
    Species fast;
    fast.snag_fall_multiplier = 2.0;
    CHECK(deadwood::snag_fall_span_yr(fast, 0.254) ==
          Approx(0.5 * deadwood::snag_fall_span_yr(s, 0.254)));
}

TEST_CASE("dead wood: a single log decays at its rate through the five classes and vanishes",
          "[eco][deadwood]") {
    auto species = one_tree_species();
    const double k = 0.054; // Herrmann et al. 2015, Fagus sylvatica
    species[0].deadwood_decay_rate_per_yr = k;
    species[0].snag_decay_rate_per_yr = k;
    const RasterD dem = plane(0.0);
    DeadWood dw(DeadWoodOptions{}, 7);
    const double m0 = 800.0;
    dw.take_dead(dead_trees(1, 0.35, 22.0, m0), species, nullptr, false, 1);
    REQUIRE(dw.pieces().size() == 1);
    CHECK(dw.sums().input_kg == m0);
    CHECK(dw.pieces()[0].cause == static_cast<std::uint8_t>(DeathCause::starvation));
    double decayed = 0;
    std::array<int, 6> first_year{}; // first year in each class
    int gone = 0;
    for (int year = 2; year <= 100 && !gone; ++year) {
        dw.reset_sums();
        const double before = dw.stock_kg();
        dw.step_year(species, dem, year);
        decayed += dw.sums().decay_kg;
        CHECK(before - dw.stock_kg() == Approx(dw.sums().decay_kg).margin(1e-9));
        if (dw.pieces().empty()) {
            gone = year;
            break;
        }
        const double t = year - 1;
        CHECK(dw.pieces()[0].mass_kg == Approx(m0 * std::exp(-k * t)).epsilon(1e-12));
        const int c = deadwood::decay_class(dw.pieces()[0].mass_kg / m0);
        if (!first_year[static_cast<std::size_t>(c)])
            first_year[static_cast<std::size_t>(c)] = year;
    }
    // Class c begins in the first whole year after death at which exp(-k t) <= its threshold.
    const std::array<double, 4> thresholds = {0.9, 0.7, 0.4, 0.2};
    for (int c = 2; c <= 5; ++c) {
        CAPTURE(c);
        const double t = std::ceil(std::log(1.0 / thresholds[static_cast<std::size_t>(c - 2)]) / k);
        CHECK(first_year[static_cast<std::size_t>(c)] == 1 + static_cast<int>(t));
    }
    // It vanishes in the first year below 5 % of its mass, and all of it has decayed.
    CHECK(gone == 1 + static_cast<int>(std::ceil(std::log(20.0) / k)));
    CHECK(decayed == Approx(m0).epsilon(1e-12));
}

TEST_CASE("dead wood: snags fall at FFE's linear rate, larger ones later", "[eco][deadwood]") {
    auto species = one_tree_species();
    species[0].deadwood_decay_rate_per_yr = 0;
    species[0].snag_decay_rate_per_yr = 0;
    const RasterD dem = plane(0.0);
    const int n = 4000;
    for (const double inches : {10.0, 20.0}) {
        CAPTURE(inches);
        const double dbh = inches * 0.0254;
        const double span = deadwood::snag_fall_span_yr(species[0], dbh);
        DeadWood dw(DeadWoodOptions{}, 11);
        dw.take_dead(dead_trees(n, dbh, 20.0, 100.0), species, nullptr, false, 1);
        for (int year = 2; year <= 21; ++year) {
            dw.step_year(species, dem, year);
            const int t = year - 1;
            if (t % 5) continue;
            double fallen = 0;
            for (const auto& d : dw.pieces()) fallen += d.standing ? 0 : 1;
            const double p = std::min(1.0, t / span);
            const double sd = std::sqrt(n * p * (1 - p));
            CAPTURE(t, span, fallen);
            CHECK(std::abs(fallen - n * p) < 4 * sd + 1);
        }
    }
}

TEST_CASE("dead wood: stems fall downhill on a steep slope and anywhere on the flat",
          "[eco][deadwood]") {
    const int n = 4000;
    auto species = one_tree_species();
    species[0].snag_fall_multiplier = 100; // every snag falls in the year after its death
    for (const double slope : {0.0, 0.15, 0.5}) {
        CAPTURE(slope);
        const RasterD dem = plane(slope);
        DeadWood dw(DeadWoodOptions{}, 3);
        dw.take_dead(dead_trees(n, 0.3, 20.0, 100.0), species, nullptr, false, 1);
        dw.step_year(species, dem, 2);
        double c = 0, s = 0, near_downhill = 0;
        for (const auto& d : dw.pieces()) {
            REQUIRE(d.standing == 0);
            CHECK(d.azimuth_rad >= 0.0);
            CHECK(d.azimuth_rad < 2 * kPi);
            c += std::cos(d.azimuth_rad), s += std::sin(d.azimuth_rad);
            // Downhill is -x, azimuth pi.
            if (std::abs(d.azimuth_rad - kPi) <= 0.25 * kPi + 1e-12) near_downhill += 1;
        }
        const double share = near_downhill / n;
        // min(1, slope / 0.3) of the stems fall within 45 degrees of downhill, the rest anywhere
        // (a quarter of them there too).
        const double expected = std::min(1.0, slope / 0.3) + (1 - std::min(1.0, slope / 0.3)) / 4;
        CHECK(share ==
              Approx(expected).margin(4 * std::sqrt(expected * (1 - expected) / n) + 1e-9));
        if (slope == 0.0) CHECK(std::hypot(c, s) / n < 0.05); // no preferred direction
    }
}

TEST_CASE("dead wood: the checkpoint gives back the same pieces, stream and sums",
          "[eco][deadwood][checkpoint]") {
    auto species = one_tree_species();
    const RasterD dem = plane(0.1);
    DeadWood dw(DeadWoodOptions{}, 5);
    dw.take_dead(dead_trees(50, 0.25, 18.0, 150.0), species, nullptr, false, 1);
    for (int year = 2; year < 12; ++year) dw.step_year(species, dem, year);
    ArchiveWriter a;
    dw.save(a);
    DeadWood back(DeadWoodOptions{}, 99);
    ArchiveReader r(a.bytes().data(), a.bytes().size(), "dead wood");
    back.load(r);
    CHECK(r.at_end());
    REQUIRE(back.pieces().size() == dw.pieces().size());
    CHECK(std::memcmp(back.pieces().data(), dw.pieces().data(),
                      dw.pieces().size() * sizeof(DeadStem)) == 0);
    // The same stream: the next years are the same.
    dw.take_dead(dead_trees(20, 0.25, 18.0, 150.0), species, nullptr, false, 12);
    back.take_dead(dead_trees(20, 0.25, 18.0, 150.0), species, nullptr, false, 12);
    for (int year = 13; year < 20; ++year)
        dw.step_year(species, dem, year), back.step_year(species, dem, year);
    REQUIRE(back.pieces().size() == dw.pieces().size());
    CHECK(std::memcmp(back.pieces().data(), dw.pieces().data(),
                      dw.pieces().size() * sizeof(DeadStem)) == 0);
}

TEST_CASE("dead wood in the engine: the living stand is the same, the dead wood's budget closes",
          "[eco][deadwood][engine][slow]") {
    for (const std::string mode : {"coupled", "light_only"}) {
        CAPTURE(mode);
        const int years = 30;
        auto j = test::small_scene(years, mode);
        const EcoScene with = load_eco_scene(j, test::data_dir() / "scenes");
        j["vegetation"]["deadwood"]["enabled"] = false;
        const EcoScene without = load_eco_scene(j, test::data_dir() / "scenes");
        Ecosystem a(with), b(without);
        for (int y = 0; y < years; ++y) a.run_year(), b.run_year();
        CHECK(a.plants().bitwise_equal(b.plants()));
        CHECK(b.dead_wood().pieces().empty());
        REQUIRE(!a.dead_wood().pieces().empty());
        const Table& t = a.yearly();
        const auto& stock = t.column("deadwood_stock_kg");
        const auto& input = t.column("deadwood_input_kg");
        const auto& decay = t.column("deadwood_decay_kg");
        const auto& dead = t.column("dead_carbon_kg");
        const auto& starved = t.column("deaths_starvation");
        double previous = 0, total_input = 0, total_dead = 0;
        for (std::size_t y = 0; y < t.rows(); ++y) {
            CAPTURE(y);
            CHECK(stock[y] == Approx(previous + input[y] - decay[y]).margin(1e-9 * (1 + stock[y])));
            // Coupled: the dead wood is the wood of trees that died, part of the dead carbon (wood
            // and reserve) in years without starvation; a starved tree's reserve is overdrawn by
            // its last day's deficit, which its dead carbon counts.
            if (mode == "coupled" && starved[y] == 0) CHECK(input[y] <= dead[y] + 1e-9);
            total_input += input[y], total_dead += dead[y];
            previous = stock[y];
        }
        // Over the run the overdrafts are small beside the dead trees' carbon.
        if (mode == "coupled") CHECK(total_input <= total_dead);
        // Every piece is a tree that died at or above the smallest DBH, inside the terrain.
        const auto& g = a.plant_grid();
        for (const auto& d : a.dead_wood().pieces()) {
            CHECK(d.dbh_m >= with.deadwood.min_dbh_m);
            CHECK(g.contains_point(d.x_m, d.y_m));
            CHECK(d.mass_kg <= d.mass0_kg);
            CHECK(d.year_died <= years);
        }
        CHECK(a.carbon_residual_relative() < 1e-9);
    }
}

TEST_CASE("dead wood: keys out of range are refused, naming the key and the value",
          "[eco][deadwood][bad_input]") {
    auto j = test::small_scene(1);
    j["vegetation"]["deadwood"]["min_dbh_m"] = -0.1;
    CHECK_THROWS_WITH(load_eco_scene(j, test::data_dir() / "scenes"),
                      Catch::Contains("vegetation.deadwood.min_dbh_m") && Catch::Contains("-0.1"));
    j = test::small_scene(1);
    j["vegetation"]["deadwood"]["removal_mass_fraction"] = 1.5;
    CHECK_THROWS_WITH(load_eco_scene(j, test::data_dir() / "scenes"),
                      Catch::Contains("removal_mass_fraction") && Catch::Contains("1.5"));
    j = test::small_scene(1);
    j["vegetation"]["deadwood"]["unknown"] = 1;
    CHECK_THROWS_WITH(load_eco_scene(j, test::data_dir() / "scenes"), Catch::Contains("unknown"));
    // A species with a negative decay rate.
    j = test::small_scene(1);
    nlohmann::json eco = nlohmann::json::parse(
        std::ifstream(test::data_dir() / "ecosystems/humid_subtropical_broadleaf.json"));
    eco["Species"][0]["physiology"]["deadwood"]["decay_rate_per_yr"] = -0.05;
    const test::TempDir dir;
    const auto path = dir / "eco.json";
    std::ofstream(path) << eco.dump();
    j["vegetation"]["ecosystem"] = path.string();
    CHECK_THROWS_WITH(load_eco_scene(j, test::data_dir() / "scenes"),
                      Catch::Contains("deadwood.decay_rate_per_yr") && Catch::Contains("-0.05"));
}
