// Births, ageing and deaths of the plants, in both competition modes, and the yearly carbon
// budget (processes.hpp).
#include "ecoterra/eco/dispersal.hpp"
#include "ecoterra/eco/growth.hpp"
#include "ecoterra/eco/processes.hpp"
#include "ecoterra/error.hpp"
#include "ecoterra/units.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

namespace ecoterra::eco {

namespace {
/// Light-only mode: diameters approach the one at which H = 95 % of Hmax (MAVS's saturating
/// growth curve applied to the stem, see docs/ecosystem.md s6).
constexpr double kLightOnlyHeightFraction = 0.95;
/// Age on the light-only curve of an initial stem: the diameter's share of D95 is capped here (a
/// stem at or above D95 gets the age of this share), and 1 - share floored at kMinRemainder.
constexpr double kLightOnlyMaxShareOfD95 = 0.999;
constexpr double kMinRemainder = 1e-9;
/// MAVS's height curve is inverted for heights up to this share of Max Height.
constexpr double kMavsMaxHeightShare = 0.999;
/// The yearly carbon check: |cumulative residual| may reach this share of the cumulative
/// throughput (at least 1 kg of it) plus kCarbonStockRounding of the stock.
constexpr double kCarbonTolerance = 1e-9;
constexpr double kCarbonStockRounding = 1e-12;
constexpr char kAge = static_cast<char>(DeathCause::age);

/// The diameter at which H = kLightOnlyHeightFraction * Hmax, m.
double light_only_d95_m(const Species& s) {
    return -std::log(1 - kLightOnlyHeightFraction) / s.height_dbh_slope_per_cm / kCmPerM;
}
/// MAVS's competitive radius is half of its height-to-diameter ratio times the height.
double mavs_competition_radius_m(const Species& s, double height_m) {
    return 0.5 * s.height_to_diameter_ratio * height_m;
}
/// Whether (x, y) lies on the grid, its far edges excluded.
bool on_grid(const GridSpec& g, double x, double y) {
    return g.contains_point(x, y) && x < g.origin_x_m + g.width_m() &&
           y < g.origin_y_m + g.height_m();
}
} // namespace

Plant Nursery::make(std::uint16_t sp, double x, double y, double dbh) const {
    const Species& s = species[sp];
    Plant p;
    p.id = next_id++;
    p.species = sp;
    p.x_m = x;
    p.y_m = y;
    p.z_m = dem.sample_bilinear(x, y);
    p.dbh_m = dbh;
    if (s.life_form == LifeForm::object) {
        allometry::apply(s, p); // full size, no carbon
    } else if (competition == Competition::light_only) {
        p.dbh_m = 0;
        allometry::apply(s, p);
        p.height_m = 0;
    } else {
        allometry::apply(s, p);
        p.wood_kg = allometry::stem_mass_kg(s, dbh);
        p.reserve_kg =
            s.initial_reserve_fraction * s.reserve_capacity_kg_per_m2_leaf * p.leaf_area_m2;
        p.mass_at_year_start_kg = p.wood_kg + p.reserve_kg;
    }
    const auto [i, j] = soil.grid().clamped_cell(x, y);
    p.soil_factor = soil_suitability(s, soil, i, j);
    return p;
}

bool Seedbed::establishes(const Species& s, double x, double y, Rng& rng) const {
    const double draw = rng.uniform(); // always drawn: the stream does not depend on the tests
    const auto [i, j] = canopy.plant_grid.clamped_cell(x, y);
    const int hi = i / canopy.map.factor, hj = j / canopy.map.factor;
    const std::int64_t cell = static_cast<std::int64_t>(hj) * canopy.map.hydro_nx + hi;
    // Light through the crowns and then through the grass and herbs (none without a ground layer).
    double light = cell_light ? (*cell_light)(i, j) : 1.0 - canopy.ground_shade(i, j);
    if (!ground.empty()) light *= ground.transmission(species, cell, extinction);
    SpeciesLedger* l = ledger ? &(*ledger)[static_cast<std::size_t>(&s - species.data())] : nullptr;
    if (l) l->attempts += 1;
    if (light < s.germination_min_light) {
        if (l) l->failed_light += 1;
        return false;
    }
    if (water.relative(hi, hj) < s.germination_min_soil_water) {
        if (l) l->failed_water += 1;
        return false;
    }
    if (lakes.owner(cell) != 0) {
        if (l) l->failed_pond += 1;
        return false;
    }
    // Under the gap light a recruit must also grow to its entry size in that light: its chance
    // scales with the species' light response of production (growth.hpp's light_factor). One
    // uniform serves both tests: it fails the light if draw >= grow, else draw / grow is uniform
    // and the soil's draw passes if draw < grow * germination probability * suitability.
    const double grow = cell_light ? light_factor(s.light_half_saturation, light) : 1.0;
    if (!(draw < grow)) {
        if (l) l->failed_light += 1;
        return false;
    }
    const double tex =
        texture_factor(s.texture, s.texture_tolerance_pct, water.soil.sand_pct(hi, hj),
                       water.soil.silt_pct(hi, hj), water.soil.clay_pct(hi, hj));
    const double ph = ph_factor(s.ph, water.soil.ph(hi, hj));
    // germination probability x soil_suitability's product, scaled by the growth factor
    const bool ok = draw < grow * (s.germination_probability * (tex * ph));
    if (l) {
        l->draws += 1;
        l->texture_factor_sum += tex;
        l->ph_factor_sum += ph;
        (ok ? l->established : l->failed_draw) += 1;
    }
    return ok;
}

std::vector<char> ageing_and_mortality(Population& pop, const std::vector<Species>& species,
                                       Rng& rng, PlantSums& sums, GrowthModel model) {
    std::vector<char> dead(pop.size(), 0);
    for (std::size_t k = 0; k < pop.size(); ++k) {
        const Species& s = species[pop.species[k]];
        const double u = rng.uniform(); // drawn for every plant: the stream stays aligned
        if (!pop.alive[k]) continue;    // starved this year, counted then
        pop.age_yr[k] += 1;
        if (s.life_form == LifeForm::object) { // no growth, no background death: removed at Max Age
            if (pop.age_yr[k] >= s.max_age_yr) {
                dead[k] = kAge;
                sums.deaths_age += 1;
            }
            continue;
        }
        update_growth_efficiency(pop.wood_kg[k], pop.reserve_kg[k], pop.leaf_area_m2[k],
                                 pop.mass_at_year_start_kg[k], pop.turnover_kg[k],
                                 pop.growth_efficiency[k]);
        const double suppression = suppression_mortality(s, pop.growth_efficiency[k], model);
        const double background = background_mortality(s, pop.dbh_m[k]);
        if (pop.age_yr[k] >= s.max_age_yr) {
            dead[k] = kAge;
            sums.deaths_age += 1;
        } else if (u < background) {
            dead[k] = static_cast<char>(DeathCause::background);
            sums.deaths_background += 1;
        } else if (u < background + suppression) {
            dead[k] = static_cast<char>(DeathCause::suppression);
            sums.deaths_suppression += 1;
        }
    }
    return dead;
}

std::vector<Plant> seed_dispersal(const Population& pop, const std::vector<char>& dead,
                                  const std::vector<Species>& species, const GridSpec& grid,
                                  const Seedbed& bed, const Nursery& nursery, Rng& rng,
                                  PlantSums& sums) {
    std::vector<Plant> recruits;
    for (std::size_t k = 0; k < pop.size(); ++k) {
        const Species& s = species[pop.species[k]];
        if (dead[k] || !pop.alive[k] || s.life_form == LifeForm::object ||
            pop.age_yr[k] < s.maturity_age_yr)
            continue;
        const double vigor = pop.growth_days[k] > 0 ? pop.growth_sum[k] / pop.growth_days[k] : 0.0;
        const std::int64_t n = poisson(rng, seeds_per_year(s, pop.dbh_m[k], vigor));
        sums.seeds += static_cast<double>(n);
        for (std::int64_t q = 0; q < n; ++q) {
            const double d = sample_dispersal_distance(s.dispersal, rng);
            const double a = 2.0 * std::numbers::pi * rng.uniform();
            const double x = pop.x_m[k] + d * std::cos(a), y = pop.y_m[k] + d * std::sin(a);
            if (bed.ledger) {
                SpeciesLedger& l = (*bed.ledger)[pop.species[k]];
                (on_grid(grid, x, y) ? l.seeds_landed : l.seeds_lost) += 1;
            }
            if (!on_grid(grid, x, y)) {
                sums.seeds_lost += 1;
                rng.uniform(); // keep the stream aligned with the landed case
                continue;
            }
            if (bed.establishes(s, x, y, rng))
                recruits.push_back(nursery.make(pop.species[k], x, y, s.recruit_dbh_m));
        }
    }
    return recruits;
}

void background_arrivals(const std::vector<Species>& species, const GridSpec& grid,
                         const Seedbed& bed, const Nursery& nursery, Rng& rng,
                         std::vector<Plant>& recruits) {
    const double area = grid.width_m() * grid.height_m();
    for (std::size_t sp = 0; sp < species.size(); ++sp) {
        const Species& s = species[sp];
        if (s.life_form == LifeForm::grass) continue; // arrives into the ground layer's cover
        const std::int64_t n = poisson(rng, s.new_per_area_per_yr * area);
        for (std::int64_t q = 0; q < n; ++q) {
            const double x = grid.origin_x_m + rng.uniform() * grid.width_m();
            const double y = grid.origin_y_m + rng.uniform() * grid.height_m();
            if (bed.ledger) {
                SpeciesLedger& l = (*bed.ledger)[sp];
                l.arrivals += 1;
                if (s.life_form == LifeForm::object) l.attempts += 1, l.established += 1;
            }
            if (s.life_form == LifeForm::object || bed.establishes(s, x, y, rng))
                recruits.push_back(
                    nursery.make(static_cast<std::uint16_t>(sp), x, y, s.recruit_dbh_m));
        }
    }
}

void remove_dead(Population& pop, PlantSums& sums) {
    // Called at every canopy refresh; most refreshes have no one to remove.
    if (std::find(pop.alive.begin(), pop.alive.end(), std::uint8_t{0}) == pop.alive.end()) return;
    std::vector<char> keep(pop.size());
    for (std::size_t k = 0; k < pop.size(); ++k) {
        keep[k] = pop.alive[k] ? 1 : 0;
        if (!keep[k]) sums.dead_carbon += pop.wood_kg[k] + pop.reserve_kg[k];
    }
    pop.keep_if(keep);
}

void sort_by_stem_cell(Population& pop, const GridSpec& grid) {
    const std::size_t n = pop.size();
    std::vector<std::int64_t> key(n);
    bool sorted = true;
    for (std::size_t k = 0; k < n; ++k) {
        const auto [i, j] = grid.clamped_cell(pop.x_m[k], pop.y_m[k]);
        key[k] = static_cast<std::int64_t>(j) * grid.nx + i;
        sorted = sorted && (k == 0 || key[k - 1] <= key[k]);
    }
    if (sorted) return;
    std::vector<std::uint32_t> order(n);
    std::iota(order.begin(), order.end(), 0u);
    std::stable_sort(order.begin(), order.end(),
                     [&](std::uint32_t a, std::uint32_t b) { return key[a] < key[b]; });
    pop.permute(order);
}

double light_only_dbh_m(const Species& s, double age_yr) {
    return light_only_d95_m(s) * (1 - std::exp(-s.growth_rate_per_yr * age_yr));
}

double light_only_age_yr(const Species& s, double dbh_m) {
    return std::ceil(-std::log(std::max(kMinRemainder, 1 - std::min(dbh_m / light_only_d95_m(s),
                                                                    kLightOnlyMaxShareOfD95))) /
                     s.growth_rate_per_yr);
}

std::vector<char> light_only_growth(Population& pop, const std::vector<Species>& species,
                                    PlantSums& sums) {
    std::vector<char> dead(pop.size(), 0);
    for (std::size_t k = 0; k < pop.size(); ++k) {
        const Species& s = species[pop.species[k]];
        pop.age_yr[k] += 1;
        if (pop.age_yr[k] >= s.max_age_yr) {
            dead[k] = kAge;
            sums.deaths_age += 1;
            continue;
        }
        if (s.life_form == LifeForm::object) continue;
        const allometry::Size z = allometry::size(s, light_only_dbh_m(s, pop.age_yr[k]));
        pop.dbh_m[k] = z.dbh_m;
        pop.height_m[k] = z.height_m;
        pop.crown_radius_m[k] = z.crown_radius_m;
        pop.leaf_area_m2[k] = z.leaf_area_m2;
    }
    return dead;
}

void light_only_arrivals(Population& pop, std::vector<char>& dead,
                         const std::vector<Species>& species, const GridSpec& grid,
                         const Nursery& nursery, Rng& rng, PlantSums& sums) {
    const double area = grid.width_m() * grid.height_m();
    for (std::size_t sp = 0; sp < species.size(); ++sp) {
        if (species[sp].life_form == LifeForm::grass) continue;
        const std::int64_t n = poisson(rng, species[sp].new_per_area_per_yr * area);
        for (std::int64_t q = 0; q < n; ++q) {
            const double x = grid.origin_x_m + rng.uniform() * grid.width_m();
            const double y = grid.origin_y_m + rng.uniform() * grid.height_m();
            pop.push(nursery.make(static_cast<std::uint16_t>(sp), x, y, 0.0));
            dead.push_back(0);
            sums.births += 1;
        }
    }
}

double mavs_height_m(const Species& s, double age_yr) {
    return s.max_height_m * -std::expm1(-s.growth_rate_per_yr * age_yr);
}

double mavs_age_yr(const Species& s, double height_m) {
    const double share = std::clamp(height_m / s.max_height_m, 0.0, kMavsMaxHeightShare);
    return -std::log1p(-share) / s.growth_rate_per_yr;
}

namespace {
/// A MAVS plant's size from its height: the diameter from the height curve's inverse, the crown
/// from the diameter.
void set_mavs_height(const Species& s, Population& pop, std::size_t k, double height_m) {
    const allometry::Size z = allometry::size(s, allometry::dbh_from_height_m(s, height_m));
    pop.height_m[k] = height_m;
    pop.dbh_m[k] = z.dbh_m;
    pop.crown_radius_m[k] = z.crown_radius_m;
    pop.leaf_area_m2[k] = z.leaf_area_m2;
}

void mavs_arrivals(Population& pop, const std::vector<Species>& species, const GridSpec& g,
                   double plant_density, const Nursery& nursery, Rng& rng, PlantSums& sums) {
    const double area = g.width_m() * g.height_m() * plant_density;
    for (std::size_t sp = 0; sp < species.size(); ++sp) {
        const Species& s = species[sp];
        if (s.life_form == LifeForm::grass) continue;
        const double expected = s.new_per_area_per_yr * area;
        const double whole = std::floor(expected);
        const auto n = static_cast<std::int64_t>(whole) + (rng.uniform() < expected - whole);
        for (std::int64_t q = 0; q < n; ++q) {
            const double x = g.origin_x_m + rng.uniform() * g.width_m();
            const double y = g.origin_y_m + rng.uniform() * g.height_m();
            const double h = rng.uniform() * mavs_height_m(s, 1.0);
            pop.push(nursery.make(static_cast<std::uint16_t>(sp), x, y, 0.0));
            if (s.life_form != LifeForm::object) set_mavs_height(s, pop, pop.size() - 1, h);
            sums.births += 1;
        }
    }
}

/// Circles in square buckets at least two of the largest radii wide: a circle can only overlap
/// one in its own or a neighbouring bucket.
class CircleBuckets {
public:
    CircleBuckets(const GridSpec& g, const std::vector<double>& radius) : m_g(g) {
        double rmax = 0;
        for (const double r : radius) rmax = std::max(rmax, r);
        m_size = std::max(2 * rmax, g.cell_size_m);
        m_nx = static_cast<int>(std::ceil(g.width_m() / m_size)) + 1;
        m_ny = static_cast<int>(std::ceil(g.height_m() / m_size)) + 1;
        m_items.resize(static_cast<std::size_t>(m_nx) * m_ny);
    }
    void add(std::size_t k, double x, double y) { m_items[slot(col(x), row(y))].push_back(k); }
    /// Calls f(k) for the circles in the buckets around (x, y) until f returns true; returns
    /// whether it did.
    template <class F>
    bool any_near(double x, double y, F&& f) const {
        const int cx = col(x), cy = row(y);
        for (int j = std::max(0, cy - 1); j <= std::min(m_ny - 1, cy + 1); ++j)
            for (int i = std::max(0, cx - 1); i <= std::min(m_nx - 1, cx + 1); ++i)
                for (const std::size_t k : m_items[slot(i, j)])
                    if (f(k)) return true;
        return false;
    }

private:
    int col(double x) const { return static_cast<int>((x - m_g.origin_x_m) / m_size); }
    int row(double y) const { return static_cast<int>((y - m_g.origin_y_m) / m_size); }
    std::size_t slot(int i, int j) const { return static_cast<std::size_t>(j) * m_nx + i; }
    const GridSpec& m_g;
    double m_size = 0;
    int m_nx = 0, m_ny = 0;
    std::vector<std::vector<std::size_t>> m_items;
};

/// Every pair of circles that overlap: the smaller dies, equal ones both.
void mavs_competition(const Population& pop, const std::vector<Species>& species, const GridSpec& g,
                      std::vector<char>& dead, PlantSums& sums) {
    const std::size_t n = pop.size();
    std::vector<double> radius(n);
    for (std::size_t k = 0; k < n; ++k)
        radius[k] = mavs_competition_radius_m(species[pop.species[k]], pop.height_m[k]);
    CircleBuckets buckets(g, radius);
    for (std::size_t k = 0; k < n; ++k) buckets.add(k, pop.x_m[k], pop.y_m[k]);
    std::vector<char> killed(n, 0);
    for (std::size_t i = 0; i < n; ++i)
        buckets.any_near(pop.x_m[i], pop.y_m[i], [&](std::size_t j) {
            if (j <= i || !(std::hypot(pop.x_m[i] - pop.x_m[j], pop.y_m[i] - pop.y_m[j]) <
                            radius[i] + radius[j]))
                return false;
            if (radius[i] >= radius[j]) killed[j] = 1;
            if (radius[j] >= radius[i]) killed[i] = 1;
            return false; // every pair
        });
    for (std::size_t k = 0; k < n; ++k)
        if (killed[k] && !dead[k]) {
            dead[k] = static_cast<char>(DeathCause::overlap);
            sums.deaths_overlap += 1;
        }
}
} // namespace

std::vector<char> mavs_step(Population& pop, const std::vector<Species>& species,
                            const GridSpec& grid, double plant_density, const Nursery& nursery,
                            Rng& rng, PlantSums& sums) {
    mavs_arrivals(pop, species, grid, plant_density, nursery, rng, sums);
    std::vector<char> dead(pop.size(), 0);
    for (std::size_t k = 0; k < pop.size(); ++k) {
        const Species& s = species[pop.species[k]];
        if (s.life_form != LifeForm::object)
            set_mavs_height(s, pop, k, mavs_height_m(s, mavs_age_yr(s, pop.height_m[k]) + 1));
        pop.age_yr[k] += 1;
        if (pop.age_yr[k] > s.max_age_yr) {
            dead[k] = kAge;
            sums.deaths_age += 1;
        }
    }
    mavs_competition(pop, species, grid, dead, sums);
    return dead;
}

void overlap_thinning(const Population& pop, std::vector<char>& dead,
                      const std::vector<Species>& species, const GridSpec& g, LightOnlyRadius rule,
                      PlantSums& sums) {
    const std::size_t n = pop.size();
    std::vector<std::size_t> order(n);
    for (std::size_t k = 0; k < n; ++k) order[k] = k;
    std::vector<double> radius(n);
    for (std::size_t k = 0; k < n; ++k)
        radius[k] = rule == LightOnlyRadius::mavs
                        ? mavs_competition_radius_m(species[pop.species[k]], pop.height_m[k])
                        : pop.crown_radius_m[k];
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return radius[a] > radius[b]; });
    // The kept plants: a plant overlapping a kept (larger) one dies.
    CircleBuckets kept(g, radius);
    for (const std::size_t k : order) {
        if (dead[k]) continue;
        const bool overlaps = kept.any_near(pop.x_m[k], pop.y_m[k], [&](std::size_t o) {
            return std::hypot(pop.x_m[k] - pop.x_m[o], pop.y_m[k] - pop.y_m[o]) <
                   radius[k] + radius[o];
        });
        if (overlaps) {
            dead[k] = static_cast<char>(DeathCause::overlap);
            sums.deaths_overlap += 1;
        } else {
            kept.add(k, pop.x_m[k], pop.y_m[k]);
        }
    }
}

CarbonStocks close_carbon_budget(const Population& pop, const PlantSums& sums,
                                 const DeadWoodBudget& dw, int year, CarbonLedger& ledger) {
    CarbonStocks c;
    for (std::size_t k = 0; k < pop.size(); ++k)
        c.wood_kg += pop.wood_kg[k], c.reserve_kg += pop.reserve_kg[k];
    c.deadwood_kg = dw.stock_kg;
    const double stock = c.wood_kg + c.reserve_kg + c.deadwood_kg;
    const double expected = ledger.stock_at_year_start_kg + sums.production - sums.maintenance -
                            sums.growth_resp + sums.recruit_carbon - sums.dead_carbon -
                            sums.turnover + dw.input_kg - dw.decay_kg;
    c.residual_kg = stock - expected;
    ledger.cumulative_residual_kg += c.residual_kg;
    ledger.cumulative_throughput_kg += sums.production + sums.maintenance + sums.growth_resp +
                                       sums.recruit_carbon + std::abs(sums.dead_carbon) +
                                       sums.turnover + dw.input_kg + dw.decay_kg;
    if (std::abs(ledger.cumulative_residual_kg) >
        kCarbonTolerance * std::max(ledger.cumulative_throughput_kg, 1.0) +
            kCarbonStockRounding * stock)
        throw Error("carbon budget broke in year " + std::to_string(year) + ": residual " +
                    format_number(ledger.cumulative_residual_kg) + " kg against a throughput of " +
                    format_number(ledger.cumulative_throughput_kg) + " kg");
    ledger.stock_at_year_start_kg = stock;
    return c;
}

} // namespace ecoterra::eco
