#pragma once
// Soils: USDA texture classes and their hydraulic properties.
//
// Texture class from sand/silt/clay percentages: the 12 USDA classes by the NRCS rules as clarified
// by Benham, Ahrens & Nettleton (2009), evaluated in the order of reference hydrology.md s3.1.
//
// Class-average properties (volumetric, m3/m3; saturated conductivity in m/s): Rawls, Brakensiek &
// Saxton (1982), Trans. ASAE 25:1316, Table 2 (porosity, field capacity at 33 kPa, wilting point at
// 1500 kPa, Ks), confirmed by Campbell & Norman (1998) Table 9.1. Rawls et al. give no silt class;
// for silt ecoterra substitutes the Schaake (2000) ARS class average (VIC soil table): porosity
// 0.52, FC 0.28, WP 0.08, with Ks 0.68 cm/h taken from silt loam (Schaake's 8.59 cm/h belongs to a
// table whose Ks values run an order of magnitude above Rawls'; mixing them would make silt
// 13x more conductive than silt loam).
//
// Saxton & Rawls (2006), SSSAJ 70:1569, pedotransfer equations (S, C fractions, OM in %):
//   theta1500t = -0.024S + 0.487C + 0.006OM + 0.005 S OM - 0.013 C OM + 0.068 S C + 0.031
//   WP = theta1500t + (0.14 theta1500t - 0.02)
//   theta33t = -0.251S + 0.195C + 0.011OM + 0.006 S OM - 0.027 C OM + 0.452 S C + 0.299
//   FC = theta33t + (1.283 theta33t^2 - 0.374 theta33t - 0.015)
//   thetaS33t = 0.278S + 0.034C + 0.022OM - 0.018 S OM - 0.027 C OM - 0.584 S C + 0.078
//   thetaS33 = thetaS33t + (0.636 thetaS33t - 0.107)
//   thetaS = FC + thetaS33 - 0.097S + 0.043
//   lambda = (ln FC - ln WP) / (ln 1500 - ln 33);  Ks = 1930 (thetaS - FC)^(3 - lambda) mm/h
#include "ecoterra/catalog.hpp"
#include "ecoterra/raster.hpp"

#include <array>
#include <cstdint>
#include <optional>
#include <string>

namespace ecoterra::hydro {

enum class Texture : std::uint8_t {
    sand = 0,
    loamy_sand,
    sandy_loam,
    loam,
    silt_loam,
    silt,
    sandy_clay_loam,
    clay_loam,
    silty_clay_loam,
    sandy_clay,
    silty_clay,
    clay,
};
inline constexpr int kTextureCount = 12;

/// Snake-case name ("silty_clay_loam"); parse_texture accepts it and "silty clay loam".
std::string texture_name(Texture t);
std::optional<Texture> parse_texture(const std::string& name);

/// Percent sand, silt and clay (each >= 0, summing to 100 within +-2), pH in [0, 14].
struct SoilComposition {
    double sand_pct = 10, silt_pct = 80, clay_pct = 10;
    double ph = 6.5;
    std::optional<double> organic_matter_pct; ///< enables Saxton & Rawls 2006
    /// Throws InputError naming `where` and the field if out of range.
    void validate(const std::string& where) const;
};

/// USDA texture class. Requires a valid composition (percentages are normalised to sum 100).
Texture classify_texture(double sand_pct, double silt_pct, double clay_pct);

struct SoilProperties {
    Texture texture = Texture::silt;
    double porosity = 0;       ///< m3/m3
    double field_capacity = 0; ///< m3/m3 at 33 kPa
    double wilting_point = 0;  ///< m3/m3 at 1500 kPa
    double ksat_m_per_s = 0;   ///< saturated hydraulic conductivity, m/s
    double ph = 6.5;
    std::string source; ///< "rawls1982", "rawls1982+schaake2000 (silt)", "saxton_rawls2006"
};

/// Readily evaporable water of a bare surface layer, mm: the middle of FAO-56 Table 19's range
/// for the class (Allen et al. 1998; sand 2-7, loamy sand 4-8, sandy loam 6-10, loam 8-10, silt
/// loam, silt and silty clay loam 8-11, silty clay and clay 8-12). Table 19 has no sandy clay
/// loam, clay loam or sandy clay; ecoterra gives them 8, 9.5 and 9 (between their neighbours).
double readily_evaporable_water_mm(Texture t);

/// Exponent n of the unsaturated conductivity K(theta) = Ks (theta / theta_s)^n (Saxton & Rawls
/// 2006 eq. 16): n = 3 + 2 / lambda, lambda = (ln FC - ln WP) / (ln 1500 - ln 33).
double conductivity_exponent(double field_capacity, double wilting_point);

/// Rawls et al. 1982 class averages (silt substituted as stated in the header).
SoilProperties class_properties(Texture t);

/// Saxton & Rawls 2006 from fractions and organic matter (%).
SoilProperties saxton_rawls_2006(double sand_pct, double clay_pct, double organic_matter_pct);

/// Properties of a composition: Saxton & Rawls when organic matter is given, else the class table.
SoilProperties soil_properties(const SoilComposition& c);

/// A soil map: per-cell composition and derived properties on a grid.
struct SoilMap {
    RasterF sand_pct, silt_pct, clay_pct, ph;
    RasterU8 texture;
    RasterF porosity, field_capacity, wilting_point, ksat_m_per_s;
    const GridSpec& grid() const { return texture.grid(); }
};

SoilMap uniform_soil(const GridSpec& grid, const SoilComposition& c);

/// Seeded random soil: smooth Perlin fields (feature size patch_size_m) perturb the sand and clay
/// fractions around `mean` by up to +-amplitude_pct, and pH by +-ph_amplitude; silt takes the rest.
struct RandomSoilParams {
    SoilComposition mean;
    double amplitude_pct = 15.0;
    double ph_amplitude = 0.5;
    double patch_size_m = 50.0;
    void validate() const;
};
SoilMap random_soil(const GridSpec& grid, const RandomSoilParams& p, std::uint64_t seed);

/// The keys of a soil composition (scene section soil.uniform).
const ParamCatalog<SoilComposition>& soil_composition_catalog();
/// The keys of a random soil (scene section soil.random): the composition keys as the mean, and
/// the amplitudes and patch size of the Perlin fields.
const ParamCatalog<RandomSoilParams>& random_soil_catalog();

/// A soil map from per-cell rasters (percent sand, silt, clay; optional pH) on the same grid.
SoilMap soil_from_rasters(const RasterD& sand, const RasterD& silt, const RasterD& clay,
                          const RasterD* ph, const std::string& source_name);

} // namespace ecoterra::hydro
