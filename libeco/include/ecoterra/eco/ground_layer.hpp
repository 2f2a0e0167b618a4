#pragma once
// The ground layer: grasses and herbs as a cover fraction per hydrology cell and species
// (docs/ecosystem.md s9), not as individuals. MAVS's grasses arrive at 0.1-3 plants per m2 and
// year; as individuals a hectare would hold a million of them.
//
// clang-format off
// For a grass species g in a cell c with cover a (fraction of the cell's ground) and the cell's
// total ground cover A = sum over species of a, over a step dt (yr):
//   growth percentage   G = f_s(s_c) f_w(x_c) f_t f_p               growth.hpp's factors; s_c the
//                                                                   crowns' shade over the cell,
//                                                                   x_c the share of the ground
//                                                                   layer's water demand met
//   growth rate         gamma = r G phen f_T / season                r = "Growth Rate", 1/yr over
//                                                                   the growing season (season =
//                                                                   leaf-on share of the year, 1
//                                                                   for evergreens)
//   turnover            mu = 1 / "Max Age" + background mortality   1/yr
//   arrivals            F = N a0 e (1 - A)                          N = "Num New Per Area",
//                                                                   a0 = kArrivalCoverM2 per
//                                                                   arrival, e = establishment
//   a <- a exp((gamma (1 - A) - mu) dt) + F dt, and the covers scaled down where their sum
//   exceeds 1 (logistic growth into the free ground, an exponential step that keeps a >= 0).
//   The engine sums gamma dt and N a0 e dt over the days of a canopy interval (7) and steps
//   once with them, A held at the interval's start (accumulate(), apply()).
//   establishment e = p_germ f_t f_p when the light under the crowns (1 - s_c) is at least
//   germination.min_light, the relative extractable water at least germination.min_soil_water,
//   and no water stands on the cell; else 0.
// Water: the demand is tau LAI a A_cell phen ET0 (m3; FAO-56's clipped grass has LAI 2.88 and
// transpires ET0, so tau = 0.35 m3 per m2 leaf per m of ET0 gives ET0 at full cover), taken only
// from above the roots' depth z: the request is at most (theta - theta_wp) min(z, root zone) A_cell.
// Shade on the ground below: the layer passes exp(-k LAI a) of the light reaching it to seedlings
// (Beer-Lambert, k = the scene's extinction coefficient).
// clang-format on
#include "ecoterra/eco/species.hpp"

#include <cstdint>
#include <limits>
#include <vector>

namespace ecoterra::eco {

/// Cover one arriving grass plant brings, m2 (a tuft 11 cm across).
inline constexpr double kArrivalCoverM2 = 0.01;

/// What the ground layer sees of one cell in a step.
struct GroundCell {
    double crown_shade = 0;    ///< shade of the crowns above the ground, 0..1
    double water_met = 1;      ///< share of the layer's water demand supplied, 0..1
    double relative_water = 1; ///< relative extractable soil water (theta - wp) / (fc - wp)
    bool ponded = false;       ///< water stands on the cell (no establishment)
};

class GroundLayer {
public:
    GroundLayer() = default;
    /// The grass species of `species` on `cells` cells, with their soil factors (texture x pH of
    /// each cell, `soil_factor(species index, cell)`).
    template <class SoilFactor>
    GroundLayer(const std::vector<Species>& species, std::int64_t cells, SoilFactor soil_factor) {
        for (std::size_t k = 0; k < species.size(); ++k)
            if (species[k].life_form == LifeForm::grass)
                m_species.push_back(static_cast<std::uint16_t>(k));
        m_cells = cells;
        m_cover.assign(m_species.size() * static_cast<std::size_t>(cells), 0.0);
        m_soil.resize(m_cover.size());
        m_shade_soil.assign(m_cover.size(), 0.0);
        m_growth_sum.assign(m_cover.size(), 0.0);
        m_arrival_sum.assign(m_cover.size(), 0.0);
        m_shade_seen.assign(static_cast<std::size_t>(cells),
                            std::numeric_limits<double>::quiet_NaN());
        for (std::size_t g = 0; g < m_species.size(); ++g)
            for (std::int64_t c = 0; c < cells; ++c)
                m_soil[g * static_cast<std::size_t>(cells) + static_cast<std::size_t>(c)] =
                    soil_factor(m_species[g], c);
    }

    bool empty() const { return m_species.empty(); }
    /// The species indices (into the ecosystem) of the layer, in layer order.
    const std::vector<std::uint16_t>& species() const { return m_species; }
    std::int64_t cells() const { return m_cells; }
    double cover(std::size_t g, std::int64_t c) const {
        return m_cover[g * static_cast<std::size_t>(m_cells) + static_cast<std::size_t>(c)];
    }
    /// Total cover of a cell, 0..1.
    double total(std::int64_t c) const;
    /// The light the layer lets through to the soil of a cell, 0..1.
    double transmission(const std::vector<Species>& sp, std::int64_t c, double k) const;
    /// Water demand of a cell's layer, m3 (phen per ecosystem species, et0 in m).
    /// Today's leaf area index of cell c (leaf area per crown area x cover x phenology).
    double leaf_area_index(const std::vector<Species>& sp, std::int64_t c,
                           const std::vector<double>& phen) const;
    double demand_m3(const std::vector<Species>& sp, std::int64_t c,
                     const std::vector<double>& phen, double et0_m, double cell_area_m2) const;
    /// Cover-weighted root depth of a cell's layer, m (0 without cover).
    double root_depth_m(const std::vector<Species>& sp, std::int64_t c) const;
    /// Adds a day (dt years) of growth and arrivals to the pending sums (phen, already divided by
    /// the season's share of the year, and f_T per ecosystem species). The cover changes at
    /// apply().
    void accumulate(const std::vector<Species>& sp, const std::vector<GroundCell>& env,
                    double dt_yr, const std::vector<double>& phen,
                    const std::vector<double>& ftemp);
    /// One step over the pending time T with the summed rates: a <- a exp(S_g (1 - A) - mu T) +
    /// S_F (1 - A), S_g = sum of gamma dt and S_F of the arrivals' F dt over the days, A the total
    /// cover at the step's start (operator splitting: the free ground is held over the days the
    /// engine collects, one canopy interval).
    void apply(const std::vector<Species>& sp);
    /// accumulate() then apply(): one step of dt years.
    void step(const std::vector<Species>& sp, const std::vector<GroundCell>& env, double dt_yr,
              const std::vector<double>& phen, const std::vector<double>& ftemp);
    /// Whether accumulated days wait for apply() (a checkpoint must not be taken then).
    bool pending() const { return m_pending_yr > 0; }

    const std::vector<double>& raw() const { return m_cover; }
    void set_raw(std::vector<double> v);

private:
    std::vector<std::uint16_t> m_species;
    std::int64_t m_cells = 0;
    std::vector<double> m_cover, m_soil;
    /// Derived, not state: shade factor x soil factor per species and cell, for the crown shade
    /// m_shade_seen of the cell (recomputed when it changes; NaN: never computed).
    std::vector<double> m_shade_soil, m_shade_seen;
    /// Pending sums since the last apply(): growth rate x dt and arrivals x dt per species and
    /// cell, and the time, yr.
    std::vector<double> m_growth_sum, m_arrival_sum;
    double m_pending_yr = 0;
};

} // namespace ecoterra::eco
