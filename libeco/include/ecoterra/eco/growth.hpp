#pragma once
// Growth percentage and the daily carbohydrate balance (paper 002 s3; equations rebuilt in
// docs/ecosystem.md s3).
//
// clang-format off
// Factors, each in [0, 1]: Gaussian responses around the species' desired state (Preference:
// desired, tolerance):
//   shade    f_s = 1 if s <= s*, else exp(-((s - s*)/tol)^2 / 2)    s = shade fraction, 0..1
//   water    f_w = 1 if x >= x*, else exp(-((x* - x)/tol)^2 / 2)    x = fraction of demand met
//   pH       f_p = exp(-((pH - pH*)/tol)^2 / 2)
//   texture  f_t = 1 in the desired USDA class, else exp(-(d/tol)^2 / 2), d = distance in
//            percentage points (sand, silt, clay) from the cell's composition to the class centroid
//   growth percentage  G = f_s f_w f_t f_p       (vegetation.growth = paper002, the default)
//   or, with light_and_turnover (experimental), the light itself in place of the preference:
//   light    f_L = I (1 + K) / (I + K)       I = 1 - s, the fraction of full sun on the crown;
//            K = light_half_saturation. A rectangular hyperbola (Michaelis-Menten), normalised to 1
//            in full sun, as SORTIE-ND's growth in light (Pacala et al. 1994, 1996): shade-tolerant
//            species (low K) keep more of their production in shade, intolerant ones (high K)
//            lose it, and with a higher p_max they outgrow the tolerant ones in the open.
//   growth percentage  G = f_L f_w f_t f_p
//   and leaves and fine roots turn over and are rebuilt (light_and_turnover; none in paper 002's):
//   tissue  Q = LA LMA (1/L_leaf + r_fr k_fr) / (1 - g) / 365 a day, LMA = leaf mass per area,
//           L_leaf = leaf life span (yr), r_fr = fine-root mass per leaf mass, k_fr = fine-root
//           turnover (1/yr), g = kGrowthRespiration; paid before the reserve and wood, so a
//           plant in shade has a light compensation point below which it loses carbon
// Daily carbohydrate (kg CH2O) of a plant of leaf area LA (m2, in leaf) and height H (m):
//   production   P = p_max LA G phen(doy) f_T(T)          f_T = clamp((T - T_b)/(T_o - T_b), 0, 1)
//   maintenance  R = r_m / 365 LA H Q10^((T - 20)/10)     pipe model: sapwood ~ LA x H (Shinozaki
//                                                         et al. 1964); Q10 = 2 (Ryan 1991)
//   with p_max = max_production_kg_per_m2_leaf_per_day, r_m =
//   respiration_kg_per_m2_leaf_per_m_per_yr (paper 002's model: all maintenance) or
//   sapwood_respiration_kg_per_m2_leaf_per_m_per_yr (light_and_turnover, where the tissue cost
//   carries the leaves and fine roots), T_b = temperature_base_c, T_o = temperature_optimum_c
//   and T the day's mean air temperature (degC).
//   A surplus P - R - Q fills the reserve up to C_max = reserve_capacity_kg_per_m2_leaf x LA; of the
//   rest the share w(D) builds wood after growth respiration (the fraction kGrowthRespiration of
//   it, Penning de Vries 1975) and 1 - w(D) is turned over (litter), with
//   w(D) = clamp((D_max - D) / (0.1 D_max), 0, 1), D_max = max_stem_diameter_m (1 when 0): full
//   allocation to wood below 0.9 D_max, none at D_max, as the diameter growth of the JABOWA and
//   FORET gap models ends at D_max (Botkin et al. 1972). A deficit drains the reserve; an empty
//   reserve kills the plant (starvation) on that day (its reserve overdrawn by that day's deficit,
//   which the carbon budget counts as the dead plant's).
// Growth suppression (yearly, after LPJ-GUESS's greff_min): the growth efficiency
//   e = (wood + reserve - their value a year ago + turnover) / LA  (kg m-2 yr-1) enters a running mean
//   e_bar <- e_bar + (e - e_bar)/3; the death probability is mu_max clamp(1 - e_bar/e_min, 0, 1)
//   with e_min = suppression_growth_efficiency_kg_per_m2_leaf_per_yr and
//   mu_max = suppression_mortality_per_yr. Paper 002's model only: under light_and_turnover a
//   plant below its light compensation point loses carbon and dies when its reserve is spent
//   (starvation), which is the suppression death of that model.
// clang-format on
#include "ecoterra/eco/plant.hpp"
#include "ecoterra/hydro/weather.hpp"

namespace ecoterra::eco {

inline constexpr double kGrowthRespiration = 0.25; ///< fraction of new wood's carbohydrate
inline constexpr double kQ10 = 2.0;                ///< maintenance respiration per 10 degC
inline constexpr double kRespirationRefC = 20.0;   ///< reference temperature of r_m, degC
using hydro::kDaysPerYear;

double shade_factor(const Preference& p, double shade_fraction);
/// The growth model (vegetation.growth): paper 002's (the default: the shade preference, no tissue
/// turnover) or light_and_turnover (experimental: production saturating in light; leaves and fine
/// roots rebuilt as they turn over; water demand in proportion to the crown's light).
enum class GrowthModel { paper002, light_and_turnover };
/// f_L(I) = I (1 + K) / (I + K), I clamped to [0, 1]: 0 in the dark, 1 in full sun.
double light_factor(double half_saturation, double light);
/// The factor the growth model chooses for a plant with this shade fraction.
inline double light_or_shade_factor(const Species& s, GrowthModel model, double shade_fraction) {
    return model == GrowthModel::paper002
               ? shade_factor(s.shade, shade_fraction)
               : light_factor(s.light_half_saturation, 1.0 - shade_fraction);
}
/// The crown's leaf area as a fraction of its full-light allometric leaf area: under
/// light_and_turnover f + (1 - f) I, f = shaded_crown_leaf_fraction and I = 1 - shade_fraction
/// (a shaded crown holds a monolayer of leaves, a sunlit one several: Horn 1971), 1 under
/// paper 002's model.
double crown_leaf_factor(const Species& s, GrowthModel model, double shade_fraction);
double water_factor(const Preference& p, double supply_fraction);
double ph_factor(const Preference& p, double ph);
double texture_factor(hydro::Texture desired, double tolerance_pct, double sand_pct,
                      double silt_pct, double clay_pct);
/// Centroid (sand, silt, clay %) of a USDA texture class over the texture triangle.
std::array<double, 3> texture_centroid(hydro::Texture t);

/// Leaf-on fraction on a day of year: 1 for evergreens, else 1 inside [leaf_on, leaf_off).
double phenology(const Species& s, int doy);
double temperature_factor(const Species& s, double tmean_c);

/// The share of the surplus that wood growth gets from D = kWoodTaperStart D_max on falls to 0.
inline constexpr double kWoodTaperStart = 0.9;
/// w(D): the share of the surplus (after the reserve) built into wood.
double wood_allocation(const Species& s, double dbh_m);

struct CarbonDay {
    double production_kg = 0, maintenance_kg = 0, growth_respiration_kg = 0;
    double to_reserve_kg = 0, to_wood_kg = 0, turnover_kg = 0;
    double litter_kg = 0; ///< leaves and fine roots rebuilt today (their construction less growth
                          ///< respiration), shed as litter
    bool starved = false;
};

/// The carbon pools carbon_day changes, kg.
struct CarbonPools {
    double reserve_kg = 0, wood_kg = 0, turnover_kg = 0;
};
/// One day of the carbohydrate balance of a plant of leaf area `leaf_area_m2` (in leaf), height
/// `height_m` and diameter `dbh_m`, with the day's temperature responses precomputed (`f_temp` =
/// f_T(T) of the species, `q10_factor` = Q10^((T - 20)/10)); updates `pools`.
/// `tissue_kg` is the day's cost of rebuilding leaves and fine roots (tissue_cost_kg_per_day; 0
/// in paper 002's model), paid before the reserve and wood; `r_m` the maintenance coefficient
/// (maintenance_coefficient), kg per m2 of leaf per m of height per year at 20 degC.
CarbonDay carbon_day(const Species& s, double leaf_area_m2, double height_m, double dbh_m,
                     CarbonPools& pools, double growth, double phen, double f_temp,
                     double q10_factor, double tissue_kg, double r_m);
/// The maintenance coefficient r_m the growth model uses: respiration_kg_per_m2_leaf_per_m_per_yr
/// (paper 002) or sapwood_respiration_kg_per_m2_leaf_per_m_per_yr (light_and_turnover).
double maintenance_coefficient(const Species& s, GrowthModel model);
/// Carbohydrate a plant of this leaf area spends a day rebuilding the leaves and fine roots that
/// turn over (vegetation.growth = light_and_turnover), growth respiration included, kg/day.
double tissue_cost_kg_per_day(const Species& s, double leaf_area_m2);
/// One day of the carbohydrate balance of plant `p` (its in-leaf leaf_area_m2 and height_m):
/// `growth` is the growth percentage G, `phen` the leaf-on fraction phen(doy), `tmean_c` the
/// day's mean air temperature. Updates the plant's reserve and wood.
CarbonDay carbon_day(const Species& s, Plant& p, double growth, double phen, double tmean_c);
/// The same with the day's temperature responses precomputed: `f_temp` = f_T(T) of the species and
/// `q10_factor` = Q10^((T - 20)/10).
CarbonDay carbon_day(const Species& s, Plant& p, double growth, double phen, double f_temp,
                     double q10_factor);

/// Weight of the newest year in the running mean of the growth efficiency: an exponential mean
/// with the centre of mass of a 5-year running mean (alpha = 2 / (5 + 1)).
inline constexpr double kSuppressionSmoothing = 1.0 / 3.0;

/// Year end: the plant's growth efficiency e = (wood + reserve - their value a year ago + the
/// year's turnover) / leaf area (kg m-2 yr-1) enters its running mean `mean_efficiency` (the first
/// year, NaN, sets it); the year's start mass becomes wood + reserve and the turnover restarts at
/// 0. Returns e.
double update_growth_efficiency(double wood_kg, double reserve_kg, double leaf_area_m2,
                                double& mass_at_year_start_kg, double& turnover_kg,
                                double& mean_efficiency);
double update_growth_efficiency(Plant& p);
/// The yearly death probability that does not depend on growth: the background rate plus the
/// size-related arm, m_b + m_s (D / D_s)^k (species.hpp), at most 1.
double background_mortality(const Species& s, double stem_diameter_m);
/// Yearly growth-suppression death probability mu_max * clamp(1 - mean e / e_min, 0, 1) (0 when
/// the species' threshold e_min is 0, and under light_and_turnover, whose suppressed plants
/// starve).
double suppression_mortality(const Species& s, double mean_efficiency,
                             GrowthModel model = GrowthModel::paper002);

} // namespace ecoterra::eco
