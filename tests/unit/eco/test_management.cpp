// Management (management.hpp): thinnings reach their target within one tree's basal area and
// take the smallest (from below) or largest (from above) stems, selection and clear cuts take what
// they name, conditions act only above their threshold (over many random stands); in the engine,
// the stumps equal the cut trees, the stump and slash split the stem as the taper says, and the
// carbon budget closes; impossible operations are refused, naming the key and the value.
#include "ecoterra/eco/deadwood.hpp"
#include "ecoterra/eco/ecosystem.hpp"
#include "ecoterra/eco/management.hpp"
#include "ecoterra/eco/scene_config.hpp"
#include "ecoterra/error.hpp"
#include "ecoterra/random.hpp"
#include "support/scenes.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

using namespace ecoterra;
using namespace ecoterra::eco;
using nlohmann::json;

namespace {

constexpr double kArea = 1e4; // 1 ha

double ba_m2_per_ha(double dbh) {
    return std::numbers::pi * dbh * dbh / 4 * 1e4 / kArea;
}

/// A random stand: trees (species 0) of DBH 0 (saplings) to 60 cm and a few shrubs (species 1).
Population stand(std::uint64_t seed, int n) {
    Rng rng(seed, "test.management");
    Population pop;
    for (int k = 0; k < n; ++k) {
        Plant p;
        p.id = k + 1;
        p.species = rng.uniform() < 0.1 ? 1 : 0;
        p.dbh_m = rng.uniform() < 0.15 ? 0.0 : rng.uniform(0.02, 0.6);
        pop.push(p);
    }
    return pop;
}

std::vector<Species> species() {
    std::vector<Species> sp(2);
    sp[0].name = "tree";
    sp[1].name = "shrub";
    sp[1].life_form = LifeForm::shrub;
    return sp;
}

double basal_area(const Population& pop, const std::vector<char>& dead,
                  const std::vector<Species>& sp) {
    double ba = 0;
    for (std::size_t k = 0; k < pop.size(); ++k)
        if (!dead[k] && sp[pop.species[k]].life_form == LifeForm::tree)
            ba += ba_m2_per_ha(pop.dbh_m[k]);
    return ba;
}

ManagementOptions one(const json& op, int years = 100) {
    return read_management({{"operations", json::array({op})}}, years);
}

} // namespace

TEST_CASE("management: thinnings reach their target within one tree's basal area, from below "
          "or above",
          "[eco][management][property]") {
    const auto sp = species();
    for (std::uint64_t seed = 1; seed <= 20; ++seed)
        for (const double target : {0.0, 5.0, 12.5, 20.0, 1000.0 / 3})
            for (const std::string type : {"thin_from_below", "thin_from_above"}) {
                CAPTURE(seed, target, type);
                const Population pop = stand(seed, 300);
                std::vector<char> dead(pop.size(), 0);
                // A tenth of the stand already dead this year: not cut again, not counted.
                for (std::size_t k = 0; k < pop.size(); k += 10) dead[k] = 3;
                const double before = basal_area(pop, dead, sp);
                const auto m = one({{"year", 7},
                                    {"type", type},
                                    {"target_basal_area_m2_per_ha", std::min(target, 500.0)}});
                const std::vector<char> prior = dead;
                const auto n = mark_harvest(m, pop, sp, kArea, 7, dead, 6);
                const double after = basal_area(pop, dead, sp);
                double largest_cut = 0, smallest_cut = 1e9, smallest_kept = 1e9, largest_kept = 0;
                std::int64_t cut = 0;
                for (std::size_t k = 0; k < pop.size(); ++k) {
                    const bool tree = sp[pop.species[k]].life_form == LifeForm::tree;
                    if (dead[k] == 6) {
                        ++cut;
                        CHECK(prior[k] == 0);
                        CHECK(tree);
                        CHECK(pop.dbh_m[k] > 0); // saplings are left
                        largest_cut = std::max(largest_cut, pop.dbh_m[k]);
                        smallest_cut = std::min(smallest_cut, pop.dbh_m[k]);
                    } else if (!dead[k] && tree && pop.dbh_m[k] > 0) {
                        smallest_kept = std::min(smallest_kept, pop.dbh_m[k]);
                        largest_kept = std::max(largest_kept, pop.dbh_m[k]);
                    }
                }
                CHECK(cut == n);
                if (before <= target) {
                    CHECK(n == 0);
                    continue;
                }
                CHECK(after <= target + 1e-9);
                // The last tree cut took it across: without it the stand was above the target.
                const double last = type == "thin_from_below" ? largest_cut : smallest_cut;
                CHECK(after + ba_m2_per_ha(last) > target);
                if (type == "thin_from_below")
                    CHECK(largest_cut <= smallest_kept);
                else
                    CHECK(smallest_cut >= largest_kept);
            }
}

TEST_CASE(
    "management: selection and clear cuts take what they name, conditions and years act as given",
    "[eco][management]") {
    const auto sp = species();
    const Population pop = stand(3, 400);
    std::vector<char> dead(pop.size(), 0);
    auto n = mark_harvest(one({{"year", 5}, {"type", "selection"}, {"min_dbh_m", 0.4}}), pop, sp,
                          kArea, 5, dead, 6);
    std::int64_t expect = 0;
    for (std::size_t k = 0; k < pop.size(); ++k) {
        const bool take = sp[pop.species[k]].life_form == LifeForm::tree && pop.dbh_m[k] >= 0.4;
        CHECK((dead[k] == 6) == take);
        expect += take;
    }
    CHECK(n == expect);
    // Another year: nothing.
    std::fill(dead.begin(), dead.end(), 0);
    CHECK(mark_harvest(one({{"year", 5}, {"type", "clear_cut"}}), pop, sp, kArea, 6, dead, 6) == 0);
    // A clear cut takes every tree at breast height, leaves saplings and shrubs.
    CHECK(mark_harvest(one({{"year", 6}, {"type", "clear_cut"}}), pop, sp, kArea, 6, dead, 6) > 0);
    for (std::size_t k = 0; k < pop.size(); ++k)
        CHECK((dead[k] == 6) ==
              (sp[pop.species[k]].life_form == LifeForm::tree && pop.dbh_m[k] > 0));
    // A condition acts in any year the basal area is above it, not at or below.
    std::fill(dead.begin(), dead.end(), 0);
    const double ba = basal_area(pop, dead, sp);
    const json cond = {{"when_basal_area_above_m2_per_ha", ba},
                       {"type", "thin_from_above"},
                       {"target_basal_area_m2_per_ha", ba / 2}};
    CHECK(mark_harvest(one(cond), pop, sp, kArea, 1, dead, 6) == 0);
    json lower = cond;
    lower["when_basal_area_above_m2_per_ha"] = ba - 1e-6;
    CHECK(mark_harvest(one(lower), pop, sp, kArea, 77, dead, 6) > 0);
    CHECK(basal_area(pop, dead, sp) <= ba / 2 + 1e-9);
}

TEST_CASE("management: a stump and its slash split the stem as the taper says",
          "[eco][management][deadwood]") {
    namespace dw = deadwood;
    // A cylinder to 1.3 m and a cone above: the closed form at the base, at 1.3 m, at the top.
    const double D = 0.4, H = 25;
    const double total = 1.3 + (H - 1.3) / 3;
    CHECK(dw::stem_volume_fraction_below(H, 0) == 0);
    CHECK(dw::stem_volume_fraction_below(H, 0.2) == Approx(0.2 / total));
    CHECK(dw::stem_volume_fraction_below(H, 1.3) == Approx(1.3 / total));
    CHECK(dw::stem_volume_fraction_below(H, H) == Approx(1));
    const double z = 10;
    const double cone = (H - 1.3) / 3 * (1 - std::pow((H - z) / (H - 1.3), 3));
    CHECK(dw::stem_volume_fraction_below(H, z) == Approx((1.3 + cone) / total));
    // The merchantable top: where the taper reaches 10.16 cm.
    const double z4 = dw::top_start_m(D, H);
    CHECK(dw::stem_diameter_m(D, H, z4) == Approx(0.1016));
    // A cut tree in the dead wood: a stump of the stump height, slash from z4 to the top; the
    // stem between them is gone.
    Population pop;
    Plant p;
    p.id = 9;
    p.x_m = p.y_m = 50;
    p.dbh_m = D;
    p.height_m = H;
    p.wood_kg = 1000;
    pop.push(p);
    pop.alive.back() = 0;
    std::vector<Species> sp(1);
    DeadWoodOptions o;
    o.stump_height_m = 0.25;
    DeadWood d(o, 1);
    const std::vector<char> causes = {static_cast<char>(DeathCause::harvest)};
    d.take_dead(pop, sp, &causes, false, 4);
    REQUIRE(d.pieces().size() == 2);
    const DeadStem& stump = d.pieces()[0];
    const DeadStem& slash = d.pieces()[1];
    CHECK(stump.piece == static_cast<std::uint8_t>(PieceKind::stump));
    CHECK(stump.standing == 1);
    CHECK(stump.length_m == 0.25);
    CHECK(stump.mass0_kg == Approx(1000 * dw::stem_volume_fraction_below(H, 0.25)));
    CHECK(slash.piece == static_cast<std::uint8_t>(PieceKind::slash));
    CHECK(slash.standing == 0);
    CHECK(slash.offset_m == Approx(z4));
    CHECK(slash.length_m == Approx(H - z4));
    CHECK(std::hypot(slash.x_m - 50, slash.y_m - 50) == Approx(z4));
    CHECK(slash.mass0_kg == Approx(1000 * (1 - dw::stem_volume_fraction_below(H, z4))));
    CHECK(d.sums().input_kg == Approx(stump.mass0_kg + slash.mass0_kg));
    CHECK(d.sums().cut_kept_kg == Approx(d.sums().input_kg));
    // Stumps stand and keep their height as they decay; they never fall.
    RasterD flat(GridSpec{50, 50, 2.0, 0.0, 0.0}, 0.0);
    for (int y = 5; y < 60; ++y) d.step_year(sp, flat, y);
    for (const auto& s : d.pieces())
        if (s.piece == static_cast<std::uint8_t>(PieceKind::stump)) {
            CHECK(s.standing == 1);
            CHECK(s.length_m == 0.25);
        }
}

TEST_CASE("management in the engine: stumps equal the cut trees, the series record the harvest, "
          "the budget closes",
          "[eco][management][engine]") {
    for (const std::string mode : {"coupled", "light_only"}) {
        CAPTURE(mode);
        auto j = test::small_scene(12, mode);
        j["vegetation"]["management"] = {
            {"stump_height_m", 0.3},
            {"operations",
             {{{"year", 4}, {"type", "thin_from_below"}, {"target_basal_area_m2_per_ha", 8}},
              {{"year", 9}, {"type", "selection"}, {"min_dbh_m", 0.2}}}}};
        const EcoScene sc = load_eco_scene(j, test::data_dir() / "scenes");
        Ecosystem e(sc);
        for (int y = 1; y <= 12; ++y) {
            e.run_year();
            const Table& t = e.yearly();
            const std::size_t r = t.rows() - 1;
            const double cut = t.column("harvested_stems")[r];
            CAPTURE(y);
            if (y == 4) {
                REQUIRE(cut > 0);
                CHECK(t.column("basal_area_m2_per_ha")[r] <= 8 + 1e-9);
            }
            if (y == 9) CHECK(cut > 0);
            if (y != 4 && y != 9) CHECK(cut == 0);
            // One stump per cut tree, at the stump height.
            std::int64_t stumps = 0;
            for (const auto& d : e.dead_wood().pieces())
                if (d.piece == static_cast<std::uint8_t>(PieceKind::stump) && d.year_died == y) {
                    ++stumps;
                    CHECK(d.length_m == 0.3);
                    CHECK(d.cause == static_cast<std::uint8_t>(DeathCause::harvest));
                }
            CHECK(stumps == static_cast<std::int64_t>(cut));
            CHECK(t.column("harvested_wood_kg")[r] >= 0);
            CHECK(t.column("harvested_basal_area_m2_per_ha")[r] >= 0);
        }
        CHECK(e.carbon_residual_relative() < 1e-9);
        // The stumps at year end per ha match the pieces.
        std::int64_t stumps = 0;
        for (const auto& d : e.dead_wood().pieces())
            stumps += d.piece == static_cast<std::uint8_t>(PieceKind::stump);
        const auto& g = e.plant_grid();
        CHECK(e.yearly().column("stumps_per_ha").back() ==
              Approx(static_cast<double>(stumps) * 1e4 / (g.width_m() * g.height_m())));
    }
}

TEST_CASE("remove_plants cuts the plants named mid-year as a thinning cuts them: stumps, harvest "
          "sums, budgets",
          "[eco][management][engine]") {
    for (const std::string mode : {"coupled", "light_only"}) {
        CAPTURE(mode);
        const EcoScene sc = load_eco_scene(test::small_scene(8, mode), test::data_dir() / "scenes");
        Ecosystem e(sc);
        for (int y = 0; y < 5; ++y) e.run_year();
        for (int d = 0; d < 100; ++d) e.step_day(); // mid-year
        std::vector<std::int64_t> ids, kept;
        for (std::size_t k = 0; k < e.plants().size(); ++k)
            (k % 3 == 0 ? ids : kept).push_back(e.plants().id[k]);
        REQUIRE(ids.size() > 3);
        // An id that is not a living plant: refused, naming it, nothing removed.
        std::vector<std::int64_t> bad = ids;
        bad.push_back(987654321);
        const std::size_t n0 = e.plants().size();
        CHECK_THROWS_WITH(e.remove_plants(bad), Catch::Contains("987654321"));
        CHECK(e.plants().size() == n0);
        CHECK(e.remove_plants(ids) == ids.size());
        std::vector<std::int64_t> left(e.plants().id.begin(), e.plants().id.end());
        for (const auto id : ids) CHECK(std::find(left.begin(), left.end(), id) == left.end());
        for (const auto id : kept) // the others stay, unless they starved in the meantime
            if (std::find(left.begin(), left.end(), id) == left.end()) CHECK(mode == "coupled");
        std::int64_t stumps = 0;
        for (const auto& d : e.dead_wood().pieces())
            if (d.piece == static_cast<std::uint8_t>(PieceKind::stump) &&
                d.cause == static_cast<std::uint8_t>(DeathCause::harvest))
                ++stumps;
        // Every cut tree (a tree at breast height) leaves a stump; seedlings leave none.
        CHECK(stumps > 0);
        CHECK(stumps <= static_cast<std::int64_t>(ids.size()));
        e.run_year();
        CHECK(e.yearly().column("harvested_stems").back() == static_cast<double>(ids.size()));
        CHECK(e.carbon_residual_relative() < 1e-9);
        CHECK(std::abs(e.hydrology().cumulative_residual_m3()) <=
              1e-9 * e.hydrology().cumulative_throughput_m3());
    }
}

TEST_CASE("management: impossible operations are refused, naming the key and the value",
          "[eco][management][input]") {
    auto refuse = [](const json& op, const std::string& what) {
        auto j = test::small_scene(20);
        j["vegetation"]["management"] = {{"operations", json::array({op})}};
        CAPTURE(op.dump());
        CHECK_THROWS_WITH(load_eco_scene(j, test::data_dir() / "scenes"), Catch::Contains(what));
    };
    refuse({{"year", 0}, {"type", "clear_cut"}}, "vegetation.management.operations[0].year = 0");
    refuse({{"year", 21}, {"type", "clear_cut"}}, "year = 21 is outside [1, 20]");
    refuse({{"year", 2.5}, {"type", "clear_cut"}}, "not a whole year");
    refuse({{"year", 5}, {"type", "burn"}}, "type = 'burn'");
    refuse({{"year", 5}, {"type", "thin_from_below"}}, "target_basal_area_m2_per_ha is needed");
    refuse({{"year", 5}, {"type", "thin_from_below"}, {"target_basal_area_m2_per_ha", -1}},
           "target_basal_area_m2_per_ha = -1");
    refuse({{"year", 5}, {"type", "thin_from_above"}, {"target_basal_area_m2_per_ha", 900}},
           "= 900 is outside");
    refuse({{"year", 5}, {"type", "selection"}}, "min_dbh_m is needed");
    refuse({{"year", 5}, {"type", "clear_cut"}, {"min_dbh_m", 0.3}}, "selection cuts only");
    refuse({{"type", "clear_cut"}}, "either year or when_basal_area_above_m2_per_ha");
    refuse({{"when_basal_area_above_m2_per_ha", 20},
            {"type", "thin_from_below"},
            {"target_basal_area_m2_per_ha", 25}},
           "must exceed target_basal_area_m2_per_ha = 25");
    refuse({{"year", 5}, {"type", "clear_cut"}, {"when", 3}}, "unknown");
    auto j = test::small_scene(20);
    j["vegetation"]["management"] = {{"stump_height_m", -0.1}};
    CHECK_THROWS_WITH(load_eco_scene(j, test::data_dir() / "scenes"),
                      Catch::Contains("vegetation.management.stump_height_m = -0.1"));
    j["vegetation"]["management"] = {{"operations", json::array({json{{"year", 3}}})}};
    CHECK_THROWS_WITH(load_eco_scene(j, test::data_dir() / "scenes"),
                      Catch::Contains("operations[0]"));
}
