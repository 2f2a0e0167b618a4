// Soil strength for vehicles: rating cone index from texture and soil water (soil_strength.hpp).
#include "ecoterra/hydro/soil_strength.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace ecoterra::hydro {

namespace {
// Sullivan & Anderson (2000) by STATSGO texture code (reference trafficability.md s2b): codes 1
// (sand), 2-3, 7, 10 (loamy sand, sandy loam, sandy clay loam, sandy clay), 4-5 (silt loam,
// silt), 6, 8, 9 (loam, silty clay loam, clay loam), 11-12 (silty clay, clay); bulk densities of
// the classes, g/cm3 (Morris & Lowery 1988 as the script gives them).
constexpr ConeIndexCoefficients kSand{3.987, 0.815, 1.75};
constexpr double kCoarseA = 12.542, kCoarseB = -2.955;
constexpr double kSiltA = 11.936, kSiltB = -2.407;
constexpr double kLoamA = 15.506, kLoamB = -3.530;
constexpr double kClayA = 13.686, kClayB = -2.705;
constexpr double kMinMoisturePct = 1, kMaxMoisturePct = 100;
} // namespace

ConeIndexCoefficients cone_index_coefficients(Texture t) {
    switch (t) {
    case Texture::sand:
        return kSand;
    case Texture::loamy_sand:
        return {kCoarseA, kCoarseB, 1.75};
    case Texture::sandy_loam:
        return {kCoarseA, kCoarseB, 1.70};
    case Texture::silt_loam:
        return {kSiltA, kSiltB, 1.45};
    case Texture::silt:
        return {kSiltA, kSiltB, 1.42};
    case Texture::loam:
        return {kLoamA, kLoamB, 1.55};
    case Texture::sandy_clay_loam:
        return {kCoarseA, kCoarseB, 1.65};
    case Texture::silty_clay_loam:
        return {kLoamA, kLoamB, 1.42};
    case Texture::clay_loam:
        return {kLoamA, kLoamB, 1.50};
    case Texture::sandy_clay:
        return {kCoarseA, kCoarseB, 1.60};
    case Texture::silty_clay:
        return {kClayA, kClayB, 1.40};
    case Texture::clay:
        return {kClayA, kClayB, 1.40};
    }
    return {kLoamA, kLoamB, 1.55};
}

double rating_cone_index_psi(Texture t, double theta) {
    const ConeIndexCoefficients c = cone_index_coefficients(t);
    // Volumetric to gravimetric: theta_g = theta_v rho_w / rho_b, in per cent.
    const double mc =
        std::clamp(100.0 * theta / c.bulk_density_g_per_cm3, kMinMoisturePct, kMaxMoisturePct);
    return std::exp(c.a + c.b * std::log(mc));
}

RasterD rating_cone_index_map_kpa(const SoilMap& soil, const RasterD& theta) {
    RasterD out(theta.grid(), 0.0);
    for (int j = 0; j < theta.ny(); ++j)
        for (int i = 0; i < theta.nx(); ++i)
            out(i, j) =
                rating_cone_index_kpa(static_cast<Texture>(soil.texture(i, j)), theta(i, j));
    return out;
}

} // namespace ecoterra::hydro
