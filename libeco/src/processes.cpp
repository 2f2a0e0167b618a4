// The daily plant processes and the canopy (processes.hpp).
#include "ecoterra/eco/processes.hpp"

#include "ecoterra/eco/growth.hpp"
#include "ecoterra/eco/windthrow.hpp"
#include "ecoterra/parallel.hpp"
#include "ecoterra/units.hpp"

#include <algorithm>
#include <cmath>

namespace ecoterra::eco {

namespace {
/// Field capacity minus wilting point below which the relative soil water is taken as dry.
constexpr double kMinAvailableWater = 1e-9;
} // namespace

double soil_suitability(const Species& s, const hydro::SoilMap& soil, int i, int j) {
    return texture_factor(s.texture, s.texture_tolerance_pct, soil.sand_pct(i, j),
                          soil.silt_pct(i, j), soil.clay_pct(i, j)) *
           ph_factor(s.ph, soil.ph(i, j));
}

double SoilWater::relative(int i, int j) const {
    const double wp = soil.wilting_point(i, j), fc = soil.field_capacity(i, j);
    return (theta(i, j) - wp) / std::max(fc - wp, kMinAvailableWater);
}

void plant_water_demand(const Population& pop, const std::vector<Species>& species,
                        const std::vector<double>& phen, double et0_m, GrowthModel model,
                        std::vector<double>& demand_m3) {
    const auto n = static_cast<std::int64_t>(pop.size());
    demand_m3.assign(pop.size(), 0.0);
    const bool by_light = model != GrowthModel::paper002;
#pragma omp parallel for schedule(static) if (n >= parallel_min_items())
    for (std::int64_t q = 0; q < n; ++q) {
        const auto k = static_cast<std::size_t>(q);
        if (!pop.alive[k]) continue;
        const auto sp = pop.species[k];
        const double light = by_light ? 1.0 - pop.shade_fraction[k] : 1.0;
        demand_m3[k] = species[sp].transpiration_per_leaf_area * pop.leaf_area_m2[k] * phen[sp] *
                       et0_m * light;
    }
}

void ground_water_request(const GroundLayer& ground, const std::vector<Species>& species,
                          const std::vector<double>& phen, double et0_m, const SoilWater& water,
                          double root_zone_depth_m, double cell_area_m2,
                          std::vector<double>& demand_m3, std::vector<double>& request_m3,
                          std::vector<double>& cell_request_m3) {
    // No ground layer, nothing asked: the two grids stay empty (their readers run only with a
    // ground layer) instead of being zeroed every day.
    if (ground.empty()) {
        demand_m3.clear();
        request_m3.clear();
        return;
    }
    const auto& grid = water.theta.grid();
    demand_m3.assign(cell_request_m3.size(), 0.0);
    request_m3.assign(cell_request_m3.size(), 0.0);
    for (std::int64_t c = 0; c < grid.size(); ++c) {
        const auto k = static_cast<std::size_t>(c);
        const double d = ground.demand_m3(species, c, phen, et0_m, cell_area_m2);
        if (!(d > 0)) continue;
        const int i = static_cast<int>(c % grid.nx), j = static_cast<int>(c / grid.nx);
        const double above = std::max(0.0, water.theta(i, j) - water.soil.wilting_point(i, j)) *
                             std::min(ground.root_depth_m(species, c), root_zone_depth_m) *
                             cell_area_m2;
        demand_m3[k] = d;
        request_m3[k] = std::min(d, above);
        cell_request_m3[k] += request_m3[k];
    }
}

void supply_fractions(const RootCells& roots, const RasterD& request_mm, const RasterD& supplied_mm,
                      std::vector<double>& ratio, std::vector<double>& fraction) {
    const std::int64_t cells = request_mm.size();
    ratio.resize(static_cast<std::size_t>(cells));
    const double *request = request_mm.data(), *supplied = supplied_mm.data();
    // Each cell on its own (a block per thread on large grids); the count of cells short of
    // water is a sum of whole numbers, exact in any order.
    const double short_cells =
        blocked_range_sums<1>(cells, [&](std::int64_t c0, std::int64_t c1, auto& sum) {
            double n = 0;
            for (std::int64_t c = c0; c < c1; ++c) {
                const double r = request[c];
                const double q = r > 0 ? std::min(1.0, supplied[c] / r) : 1.0;
                ratio[static_cast<std::size_t>(c)] = q;
                n += q == 1.0 ? 0.0 : 1.0;
            }
            sum[0] += n;
        })[0];
    if (short_cells == 0)
        fraction.assign(roots.size(), 1.0);
    else
        gather_supply(roots, ratio, fraction);
}

DayClimate day_climate(const std::vector<Species>& species, int doy, double tmean_c) {
    DayClimate d;
    d.q10 = std::pow(kQ10, (tmean_c - kRespirationRefC) / 10.0);
    d.phen.resize(species.size());
    d.ftemp.resize(species.size());
    for (std::size_t s = 0; s < species.size(); ++s) {
        d.phen[s] = phenology(species[s], doy);
        d.ftemp[s] = temperature_factor(species[s], tmean_c);
    }
    return d;
}

void carbon_balance(Population& pop, const std::vector<Species>& species, const DayClimate& day,
                    const std::vector<double>& fraction, const std::vector<double>& demand_m3,
                    GrowthModel model, PlantSums& sums) {
    const auto n = static_cast<std::int64_t>(pop.size());
    std::vector<CarbonDay> cd(pop.size());
#pragma omp parallel for schedule(static) if (n >= parallel_min_items())
    for (std::int64_t q = 0; q < n; ++q) {
        const auto k = static_cast<std::size_t>(q);
        const Species& s = species[pop.species[k]];
        if (!pop.alive[k] || s.life_form == LifeForm::object) continue;
        const double ph = day.phen[pop.species[k]];
        const double g = light_or_shade_factor(s, model, pop.shade_fraction[k]) *
                         water_factor(s.water, fraction[k]) * pop.soil_factor[k];
        if (ph > 0) {
            pop.growth_sum[k] += g;
            pop.growth_days[k] += 1;
        }
        CarbonPools pools{pop.reserve_kg[k], pop.wood_kg[k], pop.turnover_kg[k]};
        const double tissue =
            model == GrowthModel::paper002 ? 0.0 : tissue_cost_kg_per_day(s, pop.leaf_area_m2[k]);
        cd[k] = carbon_day(s, pop.leaf_area_m2[k], pop.height_m[k], pop.dbh_m[k], pools, g, ph,
                           day.ftemp[pop.species[k]], day.q10, tissue,
                           maintenance_coefficient(s, model));
        pop.reserve_kg[k] = pools.reserve_kg;
        pop.wood_kg[k] = pools.wood_kg;
        pop.turnover_kg[k] = pools.turnover_kg;
    }
    // Sums and starvation in plant order (one order whatever the thread count).
    for (std::size_t k = 0; k < pop.size(); ++k) {
        sums.production += cd[k].production_kg;
        sums.maintenance += cd[k].maintenance_kg;
        sums.growth_resp += cd[k].growth_respiration_kg;
        sums.turnover += cd[k].turnover_kg + cd[k].litter_kg;
        sums.demand_m3 += demand_m3[k];
        sums.supplied_m3 += demand_m3[k] * fraction[k];
        if (cd[k].starved) {
            // Dead from today: no more demand or carbon; removed at the next refresh.
            pop.alive[k] = 0;
            sums.deaths_starvation += 1;
        }
    }
}

void ground_environment(const std::vector<double>& cell_shade, const SoilWater& water,
                        const hydro::Catchments& lakes, const std::vector<double>* ratio,
                        const std::vector<double>& demand_m3, const std::vector<double>& request_m3,
                        std::vector<GroundCell>& env) {
    const auto& grid = water.theta.grid();
    env.resize(static_cast<std::size_t>(grid.size()));
    for (std::int64_t c = 0; c < grid.size(); ++c) {
        GroundCell& e = env[static_cast<std::size_t>(c)];
        const auto k = static_cast<std::size_t>(c);
        e.crown_shade = cell_shade[k];
        e.relative_water =
            water.relative(static_cast<int>(c % grid.nx), static_cast<int>(c / grid.nx));
        e.ponded = lakes.owner(c) != 0;
        e.water_met = 1.0;
        if (ratio && demand_m3[k] > 0) e.water_met = (*ratio)[k] * request_m3[k] / demand_m3[k];
    }
}

void refresh_structure(Population& pop, const std::vector<Species>& species, GrowthModel model) {
    const auto n = static_cast<std::int64_t>(pop.size());
#pragma omp parallel for schedule(static) if (n >= parallel_min_items())
    for (std::int64_t q = 0; q < n; ++q) {
        const auto k = static_cast<std::size_t>(q);
        const Species& s = species[pop.species[k]];
        if (s.life_form == LifeForm::object) continue;
        const double d = allometry::dbh_from_stem_mass(s, pop.wood_kg[k], pop.dbh_m[k]);
        const allometry::Size z = allometry::size(s, d);
        pop.dbh_m[k] = z.dbh_m;
        pop.height_m[k] = z.height_m;
        pop.crown_radius_m[k] = z.crown_radius_m;
        pop.leaf_area_m2[k] = z.leaf_area_m2 * crown_leaf_factor(s, model, pop.shade_fraction[k]);
    }
}

void Canopy::rebuild(const Population& pop) {
    crowns = crown_set(plant_grid, pop.x_m, pop.y_m, pop.crown_radius_m);
    roots = root_cells(crowns, map);
}

void Canopy::refresh(Population& pop, const std::vector<Species>& species, ShadingMode mode,
                     double extinction, GrowthModel model) {
    rebuild(pop);
    std::vector<double> lai(pop.size()), depth;
    if (mode == ShadingMode::crown_profile) depth.resize(pop.size());
    for (std::size_t k = 0; k < pop.size(); ++k) {
        const Species& s = species[pop.species[k]];
        lai[k] =
            s.life_form == LifeForm::object
                ? 0.0
                : s.leaf_area_per_crown_area * crown_leaf_factor(s, model, pop.shade_fraction[k]);
        if (!depth.empty()) depth[k] = wind::crown_depth_m(s, pop.height_m[k]);
    }
    pop.shade_fraction = compute_shading(plant_grid, crowns, pop.height_m, lai, mode, extinction,
                                         &ground_shade, depth);
    shade_per_cell();
}

void Canopy::shade_per_cell() {
    const std::int64_t hny = plant_grid.ny / map.factor;
    cell_shade.assign(static_cast<std::size_t>(hny * map.hydro_nx), 0.0);
    const double inv = 1.0 / (map.factor * map.factor);
    for (int j = 0; j < plant_grid.ny; ++j)
        for (int i = 0; i < plant_grid.nx; ++i)
            cell_shade[static_cast<std::size_t>(map.hydro(j, i))] += ground_shade(i, j) * inv;
    for (auto& v : cell_shade) v = std::clamp(v, 0.0, 1.0);
}

RasterD Canopy::vegetation_density(const GroundLayer& ground, const GridSpec& hydro_grid) const {
    RasterD density(hydro_grid, 0.0);
    const double inv = 1.0 / (map.factor * map.factor);
    for (int j = 0; j < plant_grid.ny; ++j)
        for (int i = 0; i < plant_grid.nx; ++i)
            density(i / map.factor, j / map.factor) += ground_shade(i, j) * inv;
    for (std::int64_t c = 0; c < density.size(); ++c) {
        const double crown = std::clamp(density.data()[c], 0.0, 1.0);
        density.data()[c] =
            ground.empty() ? crown
                           : 1.0 - (1.0 - crown) * (1.0 - std::clamp(ground.total(c), 0.0, 1.0));
    }
    return density;
}

double top_height_m(const Population& pop, const std::vector<Species>& species, double area_ha) {
    std::vector<double> h;
    for (std::size_t k = 0; k < pop.size(); ++k)
        if (pop.alive[k] && species[pop.species[k]].life_form == LifeForm::tree)
            h.push_back(pop.height_m[k]);
    if (h.empty()) return 0.0;
    const auto n =
        std::clamp<std::size_t>(static_cast<std::size_t>(std::lround(100 * area_ha)), 1, h.size());
    std::nth_element(h.begin(), h.begin() + static_cast<std::ptrdiff_t>(n - 1), h.end(),
                     std::greater<>());
    double sum = 0;
    for (std::size_t k = 0; k < n; ++k) sum += h[k];
    return sum / static_cast<double>(n);
}

RasterD gap_light(const RasterD& ground_shade, double half_width_m) {
    const GridSpec& g = ground_shade.grid();
    RasterD out(g, 0.0);
    const int r = static_cast<int>(std::floor(std::max(0.0, half_width_m) / g.cell_size_m));
    // Summed-area table of the ground light, (nx + 1) x (ny + 1): one pass, one fixed order, so
    // the same bits on any thread count; its rounding (about 1e-16 of the grid's sum) is far
    // below any germination threshold.
    const std::size_t w = static_cast<std::size_t>(g.nx) + 1;
    std::vector<double> sat(w * (static_cast<std::size_t>(g.ny) + 1), 0.0);
    for (int j = 0; j < g.ny; ++j)
        for (int i = 0; i < g.nx; ++i)
            sat[(j + 1) * w + i + 1] = (1.0 - ground_shade(i, j)) + sat[j * w + i + 1] +
                                       sat[(j + 1) * w + i] - sat[j * w + i];
    for (int j = 0; j < g.ny; ++j) {
        const int j0 = std::max(0, j - r), j1 = std::min(g.ny, j + r + 1);
        for (int i = 0; i < g.nx; ++i) {
            const int i0 = std::max(0, i - r), i1 = std::min(g.nx, i + r + 1);
            const double sum =
                sat[j1 * w + i1] - sat[j0 * w + i1] - sat[j1 * w + i0] + sat[j0 * w + i0];
            out(i, j) = std::clamp(sum / ((i1 - i0) * (j1 - j0)), 0.0, 1.0);
        }
    }
    return out;
}

} // namespace ecoterra::eco
