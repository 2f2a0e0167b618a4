#pragma once
// Plants and their allometry (docs/ecosystem.md s2; reference forest.md s2).
// clang-format off
//   height     H(D) = h0 + (Hmax - h0) (1 - exp(-b D_cm))       m   SORTIE-ND, Chapman-Richards family;
//                                                                   h0 = 1.3 m for trees, 0 for shrubs
//   crown      R(D) = clamp(c1 D_cm^c2, kMinCrownRadiusM, Rmax)  m   SORTIE-ND power law
//   roots      root radius = crown radius                            Goodin, Hudson et al. 2024 (paper 002) s3
//   leaf area  LA = LAI_c pi R^2                                 m2
//   stem mass  M(D) = rho F (pi/4) D^2 H(D)                      kg  F = kStemFormFactor
// with D the trunk diameter at breast height (1.3 m) of a tree or the stem diameter at the ground of
// a shrub, in m, and D_cm = 100 D. An object has H = Hmax, R = 0.5 ratio Hmax (MAVS's radius), no
// leaves, and D = ratio Hmax (its footprint's diameter); the Species members
// are Hmax = max_height_m, b = height_dbh_slope_per_cm, c1 = crown_radius_coefficient_m,
// c2 = crown_radius_exponent, Rmax = max_crown_radius_m, LAI_c = leaf_area_per_crown_area,
// rho = wood_density_kg_per_m3.
// clang-format on
#include "ecoterra/eco/species.hpp"
#include "ecoterra/units.hpp"

#include <cstddef>
#include <cstdint>
#include <limits>

namespace ecoterra::eco {

/// Stem form factor: stem volume / (basal area x height); 0.5 for a paraboloid (Husch, Beers &
/// Kershaw 2003, Forest Mensuration, ch. 6).
inline constexpr double kStemFormFactor = 0.5;
/// The smallest crown a plant has (a seedling still occupies the cell holding its stem), m.
inline constexpr double kMinCrownRadiusM = 0.1;

struct Plant {
    std::int64_t id = 0;
    double x_m = 0, y_m = 0, z_m = 0;
    double dbh_m = 0; ///< the allometry's diameter: a tree's at breast height, a shrub's at the
                      ///< ground, an object's footprint (see measured_at_breast_height)
    double height_m = 0, crown_radius_m = 0;
    double age_yr = 0;
    double reserve_kg = 0; ///< carbohydrate store
    double wood_kg = 0;    ///< stem dry mass (carbohydrate built into wood)
    // Cached at the canopy refresh:
    double leaf_area_m2 = 0;
    double shade_fraction = 0;
    double soil_factor = 1; ///< texture x pH factors at the plant's cell (constant)
    // Accumulated over the current year:
    double growth_sum = 0; ///< sum of the daily growth percentage (0..1) over leaf-on days
    double growth_days = 0;
    double mass_at_year_start_kg = 0; ///< wood + reserve at the last year end
    double turnover_kg = 0;           ///< carbon turned over this year (at the maximum diameter)
    /// Running mean of the yearly growth efficiency (net wood + reserve increment per m2 leaf),
    /// kg m-2 yr-1; NaN until the plant's first year end.
    double growth_efficiency = std::numeric_limits<double>::quiet_NaN();
    std::uint16_t species = 0;
    bool alive = true; ///< false from a starvation death until the next canopy refresh removes it
    std::uint8_t reserved_[5]{}; ///< explicit, zeroed: format-6 checkpoints hold plants as bytes
};
static_assert(sizeof(Plant) % 8 == 0 && offsetof(Plant, reserved_) + 5 == sizeof(Plant),
              "Plant must keep the layout of format-6 checkpoints, which hold plants as bytes");

namespace allometry {
double height_m(const Species& s, double dbh_m);
double crown_radius_m(const Species& s, double dbh_m);
double leaf_area_m2(const Species& s, double crown_radius_m);
double stem_mass_kg(const Species& s, double dbh_m);
/// Inverse of stem_mass_kg (Newton on a monotone function, bracketed).
double dbh_from_stem_mass(const Species& s, double mass_kg, double guess_m);
/// Inverse of height_m: 0 at or below the curve's base height, capped at max_stem_diameter_m
/// (the curve only approaches Max Height).
double dbh_from_height_m(const Species& s, double height_m);
/// An object's diameter: ratio x Max Height, m.
double object_diameter_m(const Species& s);
/// A plant's size from its diameter: an object's diameter is its footprint's.
struct Size {
    double dbh_m = 0, height_m = 0, crown_radius_m = 0, leaf_area_m2 = 0;
};
Size size(const Species& s, double dbh_m);
/// Sets height, crown radius and leaf area from dbh (an object's dbh to its diameter).
void apply(const Species& s, Plant& p);
} // namespace allometry

} // namespace ecoterra::eco
