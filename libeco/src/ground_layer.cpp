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

double GroundLayer::leaf_area_index(const std::vector<Species>& sp, std::int64_t c,
                                    const std::vector<double>& phen) const {
    double lai = 0;
    for (std::size_t g = 0; g < m_species.size(); ++g)
        lai += sp[m_species[g]].leaf_area_per_crown_area * cover(g, c) * phen[m_species[g]];
    return lai;
}

double GroundLayer::root_depth_m(const std::vector<Species>& sp, std::int64_t c) const {
    double a = 0, z = 0;
    for (std::size_t g = 0; g < m_species.size(); ++g) {
        a += cover(g, c);
        z += cover(g, c) * sp[m_species[g]].root_depth_m;
    }
    return a > 0 ? z / a : 0.0;
}

void GroundLayer::accumulate(const std::vector<Species>& sp, const std::vector<GroundCell>& env,
                             double dt, const std::vector<double>& phen,
                             const std::vector<double>& ftemp) {
    if (m_species.empty()) return;
    const std::size_t ng = m_species.size();
    const auto n = static_cast<std::size_t>(m_cells);
#pragma omp parallel for schedule(static) if (m_cells >= parallel_min_items())
    for (std::int64_t ci = 0; ci < m_cells; ++ci) {
        const auto c = static_cast<std::size_t>(ci);
        const GroundCell& e = env[c];
        // The crowns' shade changes at canopy refreshes only: its factors are kept per cell.
        if (!(m_shade_seen[c] == e.crown_shade)) {
            m_shade_seen[c] = e.crown_shade;
            for (std::size_t g = 0; g < ng; ++g)
                m_shade_soil[g * n + c] =
                    shade_factor(sp[m_species[g]].shade, e.crown_shade) * m_soil[g * n + c];
        }
        for (std::size_t g = 0; g < ng; ++g) {
            const Species& s = sp[m_species[g]];
            const std::size_t k = g * n + c;
            m_growth_sum[k] += s.growth_rate_per_yr * m_shade_soil[k] *
                               water_factor(s.water, e.water_met) * phen[m_species[g]] *
                               ftemp[m_species[g]] * dt;
            const bool est = !e.ponded && e.relative_water >= s.germination_min_soil_water &&
                             1.0 - e.crown_shade >= s.germination_min_light;
            if (est)
                m_arrival_sum[k] += s.new_per_area_per_yr * kArrivalCoverM2 *
                                    s.germination_probability * m_soil[k] * dt;
        }
    }
    m_pending_yr += dt;
}

void GroundLayer::apply(const std::vector<Species>& sp) {
    if (m_species.empty() || !(m_pending_yr > 0)) return;
    const std::size_t ng = m_species.size();
    const auto n = static_cast<std::size_t>(m_cells);
    const double t = m_pending_yr;
#pragma omp parallel for schedule(static) if (m_cells >= parallel_min_items())
    for (std::int64_t ci = 0; ci < m_cells; ++ci) {
        const auto c = static_cast<std::size_t>(ci);
        const double free = std::max(0.0, 1.0 - total(ci));
        double sum = 0;
        for (std::size_t g = 0; g < ng; ++g) {
            const Species& s = sp[m_species[g]];
            const std::size_t k = g * n + c;
            const double turnover = 1.0 / s.max_age_yr + s.background_mortality_per_yr;
            double& a = m_cover[k];
            a = a * std::exp(m_growth_sum[k] * free - turnover * t) + m_arrival_sum[k] * free;
            m_growth_sum[k] = m_arrival_sum[k] = 0;
            sum += a;
        }
        if (sum > 1.0)
            for (std::size_t g = 0; g < ng; ++g) m_cover[g * n + c] /= sum;
    }
    m_pending_yr = 0;
}

void GroundLayer::step(const std::vector<Species>& sp, const std::vector<GroundCell>& env,
                       double dt, const std::vector<double>& phen,
                       const std::vector<double>& ftemp) {
    accumulate(sp, env, dt, phen, ftemp);
    apply(sp);
}

void GroundLayer::set_raw(std::vector<double> v) {
    if (v.size() != m_cover.size())
        throw CheckpointError("the checkpoint's ground layer has " + std::to_string(v.size()) +
                              " values, the scene's " + std::to_string(m_cover.size()));
    m_cover = std::move(v);
}

} // namespace ecoterra::eco
