#include "ecoterra/eco/growth.hpp"

#include <algorithm>
#include <cmath>

namespace ecoterra::eco {

namespace {
double gauss(double d, double tol) {
    const double z = d / tol;
    return std::exp(-0.5 * z * z);
}

struct Centroids {
    std::array<std::array<double, 3>, hydro::kTextureCount> c{};
    Centroids() {
        // Mean composition of each class over a 0.5 % lattice of the triangle.
        std::array<double, hydro::kTextureCount> n{};
        constexpr int kSteps = 200;
        for (int i = 0; i <= kSteps; ++i)
            for (int j = 0; i + j <= kSteps; ++j) {
                const double sand = 100.0 * i / kSteps, clay = 100.0 * j / kSteps;
                const double silt = 100.0 - sand - clay;
                const auto t = static_cast<int>(hydro::classify_texture(sand, silt, clay));
                c[t][0] += sand;
                c[t][1] += silt;
                c[t][2] += clay;
                n[t] += 1;
            }
        for (int t = 0; t < hydro::kTextureCount; ++t)
            for (auto& v : c[t]) v /= n[t];
    }
};
} // namespace

std::array<double, 3> texture_centroid(hydro::Texture t) {
    static const Centroids table;
    return table.c[static_cast<int>(t)];
}

double shade_factor(const Preference& p, double s) {
    return s <= p.desired ? 1.0 : gauss(s - p.desired, p.tolerance);
}

double light_factor(double half_saturation, double light) {
    const double i = std::clamp(light, 0.0, 1.0);
    return i * (1.0 + half_saturation) / (i + half_saturation);
}

double crown_leaf_factor(const Species& s, GrowthModel model, double shade_fraction) {
    if (model == GrowthModel::paper002 || s.shaded_crown_leaf_fraction >= 1.0) return 1.0;
    const double f = s.shaded_crown_leaf_fraction;
    return f + (1.0 - f) * std::clamp(1.0 - shade_fraction, 0.0, 1.0);
}

double water_factor(const Preference& p, double x) {
    return x >= p.desired ? 1.0 : gauss(p.desired - x, p.tolerance);
}

double ph_factor(const Preference& p, double ph) {
    return gauss(ph - p.desired, p.tolerance);
}

double texture_factor(hydro::Texture desired, double tol, double sand, double silt, double clay) {
    if (hydro::classify_texture(sand, silt, clay) == desired) return 1.0;
    const auto c = texture_centroid(desired);
    const double d = std::sqrt((sand - c[0]) * (sand - c[0]) + (silt - c[1]) * (silt - c[1]) +
                               (clay - c[2]) * (clay - c[2]));
    return gauss(d, tol);
}

double phenology(const Species& s, int doy) {
    if (s.evergreen) return 1.0;
    return doy >= s.leaf_on_doy && doy < s.leaf_off_doy ? 1.0 : 0.0;
}

double temperature_factor(const Species& s, double t) {
    return std::clamp((t - s.temperature_base_c) / (s.temperature_optimum_c - s.temperature_base_c),
                      0.0, 1.0);
}

CarbonDay carbon_day(const Species& s, Plant& p, double growth, double phen, double tmean_c) {
    return carbon_day(s, p, growth, phen, temperature_factor(s, tmean_c),
                      std::pow(kQ10, (tmean_c - kRespirationRefC) / 10.0));
}

CarbonDay carbon_day(const Species& s, Plant& p, double growth, double phen, double f_temp,
                     double q10_factor) {
    CarbonPools pools{p.reserve_kg, p.wood_kg, p.turnover_kg};
    const CarbonDay c =
        carbon_day(s, p.leaf_area_m2, p.height_m, p.dbh_m, pools, growth, phen, f_temp, q10_factor,
                   0.0, s.respiration_kg_per_m2_leaf_per_m_per_yr);
    p.reserve_kg = pools.reserve_kg;
    p.wood_kg = pools.wood_kg;
    p.turnover_kg = pools.turnover_kg;
    return c;
}

CarbonDay carbon_day(const Species& s, double la, double height_m, double dbh_m, CarbonPools& p,
                     double growth, double phen, double f_temp, double q10_factor, double tissue_kg,
                     double r_m) {
    CarbonDay c;
    c.production_kg = s.max_production_kg_per_m2_leaf_per_day * la * growth * phen * f_temp;
    c.maintenance_kg = r_m / kDaysPerYear * la * height_m * q10_factor;
    c.growth_respiration_kg = kGrowthRespiration * tissue_kg;
    c.litter_kg = tissue_kg - c.growth_respiration_kg;
    const double net = c.production_kg - c.maintenance_kg - tissue_kg;
    const double cap = s.reserve_capacity_kg_per_m2_leaf * la;
    if (net >= 0) {
        c.to_reserve_kg = std::clamp(cap - p.reserve_kg, 0.0, net);
        const double rest = net - c.to_reserve_kg;
        const double w = wood_allocation(s, dbh_m);
        const double built = rest * w;
        c.turnover_kg = rest - built; // 0 below 0.9 D_max
        const double wood_respiration = kGrowthRespiration * built;
        c.growth_respiration_kg += wood_respiration;
        c.to_wood_kg = built - wood_respiration;
        p.reserve_kg += c.to_reserve_kg;
        p.wood_kg += c.to_wood_kg;
        p.turnover_kg += c.turnover_kg;
    } else {
        c.to_reserve_kg = net;
        p.reserve_kg += net;
        if (p.reserve_kg <= 0) c.starved = true;
    }
    return c;
}

double maintenance_coefficient(const Species& s, GrowthModel model) {
    return model == GrowthModel::paper002 ? s.respiration_kg_per_m2_leaf_per_m_per_yr
                                          : s.sapwood_respiration_kg_per_m2_leaf_per_m_per_yr;
}

double tissue_cost_kg_per_day(const Species& s, double leaf_area_m2) {
    const double leaf_mass = s.leaf_mass_per_area_kg_per_m2 * leaf_area_m2;
    const double per_yr = leaf_mass * (1.0 / s.leaf_lifespan_yr +
                                       s.fine_root_to_leaf_mass * s.fine_root_turnover_per_yr);
    return per_yr / (1.0 - kGrowthRespiration) / kDaysPerYear;
}

double wood_allocation(const Species& s, double d) {
    const double dmax = s.max_stem_diameter_m;
    if (!(dmax > 0)) return 1.0;
    return std::clamp((dmax - d) / ((1.0 - kWoodTaperStart) * dmax), 0.0, 1.0);
}

double update_growth_efficiency(Plant& p) {
    return update_growth_efficiency(p.wood_kg, p.reserve_kg, p.leaf_area_m2,
                                    p.mass_at_year_start_kg, p.turnover_kg, p.growth_efficiency);
}

double update_growth_efficiency(double wood_kg, double reserve_kg, double leaf_area_m2,
                                double& mass_at_year_start_kg, double& turnover_kg,
                                double& mean_efficiency) {
    const double mass = wood_kg + reserve_kg;
    // Carbon turned over at the maximum diameter counts as growth: such a plant is not suppressed.
    const double e = (mass - mass_at_year_start_kg + turnover_kg) / std::max(leaf_area_m2, 1e-12);
    mass_at_year_start_kg = mass;
    turnover_kg = 0;
    mean_efficiency = std::isnan(mean_efficiency)
                          ? e
                          : mean_efficiency + kSuppressionSmoothing * (e - mean_efficiency);
    return e;
}

double background_mortality(const Species& s, double stem_diameter_m) {
    double m = s.background_mortality_per_yr;
    if (s.senescence_mortality_per_yr > 0.0 && stem_diameter_m > 0.0)
        m += s.senescence_mortality_per_yr *
             std::pow(stem_diameter_m / s.senescence_diameter_m, s.senescence_exponent);
    return std::min(m, 1.0);
}

double suppression_mortality(const Species& s, double mean_efficiency, GrowthModel model) {
    const double threshold = s.suppression_growth_efficiency_kg_per_m2_leaf_per_yr;
    if (!(threshold > 0) || model != GrowthModel::paper002) return 0.0;
    return s.suppression_mortality_per_yr * std::clamp(1.0 - mean_efficiency / threshold, 0.0, 1.0);
}

} // namespace ecoterra::eco
