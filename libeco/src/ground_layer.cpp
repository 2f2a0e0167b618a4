#include "ecoterra/eco/ground_layer.hpp"

#include "ecoterra/eco/growth.hpp"
#include "ecoterra/error.hpp"
#include "ecoterra/parallel.hpp"

#include <algorithm>
#include <cmath>

namespace ecoterra::eco {

double GroundLayer::total(std::int64_t c) const {
    double a = 0;
    for (std::size_t g = 0; g < m_species.size(); ++g) a += cover(g, c);
    return a;
}

double GroundLayer::transmission(const std::vector<Species>& sp, std::int64_t c, double k) const {
    double lai = 0;
    for (std::size_t g = 0; g < m_species.size(); ++g)
        lai += sp[m_species[g]].leaf_area_per_crown_area * cover(g, c);
    return std::exp(-k * lai);
}

double GroundLayer::demand_m3(const std::vector<Species>& sp, std::int64_t c,
                              const std::vector<double>& phen, double et0_m,
                              double cell_area_m2) const {
    double d = 0;
    for (std::size_t g = 0; g < m_species.size(); ++g) {
        const Species& s = sp[m_species[g]];
        d += s.transpiration_per_leaf_area * s.leaf_area_per_crown_area * cover(g, c) *
             phen[m_species[g]];
    }
    return d * cell_area_m2 * et0_m;
}

double GroundLayer::root_depth_m(const std::vector<Species>& sp, std::int64_t c) const {
    double a = 0, z = 0;
    for (std::size_t g = 0; g < m_species.size(); ++g) {
        a += cover(g, c);
        z += cover(g, c) * sp[m_species[g]].root_depth_m;
    }
    return a > 0 ? z / a : 0.0;
}

void GroundLayer::step(const std::vector<Species>& sp, const std::vector<GroundCell>& env,
                       double dt, const std::vector<double>& phen,
                       const std::vector<double>& ftemp) {
    if (m_species.empty()) return;
    const std::size_t ng = m_species.size();
    const auto n = static_cast<std::size_t>(m_cells);
#pragma omp parallel for schedule(static) if (m_cells >= parallel_min_items())
    for (std::int64_t ci = 0; ci < m_cells; ++ci) {
        const auto c = static_cast<std::size_t>(ci);
        const GroundCell& e = env[c];
        const double free = std::max(0.0, 1.0 - total(ci));
        double sum = 0;
        for (std::size_t g = 0; g < ng; ++g) {
            const Species& s = sp[m_species[g]];
            double& a = m_cover[g * n + c];
            const double soil = m_soil[g * n + c];
            const double growth = s.growth_rate_per_yr * shade_factor(s.shade, e.crown_shade) *
                                  water_factor(s.water, e.water_met) * soil * phen[m_species[g]] *
                                  ftemp[m_species[g]];
            const double turnover = 1.0 / s.max_age_yr + s.background_mortality_per_yr;
            const bool est = !e.ponded && e.relative_water >= s.germination_min_soil_water &&
                             1.0 - e.crown_shade >= s.germination_min_light;
            const double arrivals = est ? s.new_per_area_per_yr * kArrivalCoverM2 *
                                              s.germination_probability * soil * free
                                        : 0.0;
            a = a * std::exp((growth * free - turnover) * dt) + arrivals * dt;
            sum += a;
        }
        if (sum > 1.0)
            for (std::size_t g = 0; g < ng; ++g) m_cover[g * n + c] /= sum;
    }
}

void GroundLayer::set_raw(std::vector<double> v) {
    if (v.size() != m_cover.size())
        throw CheckpointError("the checkpoint's ground layer has " + std::to_string(v.size()) +
                              " values, the scene's " + std::to_string(m_cover.size()));
    m_cover = std::move(v);
}

} // namespace ecoterra::eco
