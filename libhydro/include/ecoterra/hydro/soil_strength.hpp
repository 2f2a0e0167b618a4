#pragma once
// Soil strength for vehicles (docs/mobility.md s7): the rating cone index RCI of a cell from its
// USDA texture and its volumetric soil water, by Sullivan & Anderson's (2000, ERDC) texture-class
// form RCI = exp(a + b ln(mc)), mc the gravimetric water content in per cent (reference
// trafficability.md s2b, the coefficients as the WLDAS_RCI script applies them to the STATSGO
// texture classes; the volumetric water is made gravimetric with the class's bulk density, Morris
// & Lowery 1988). RCI is in psi, as the Army's cone index is; rating_cone_index_kpa converts.
#include "ecoterra/hydro/soil.hpp"
#include "ecoterra/units.hpp"

namespace ecoterra::hydro {

/// The coefficients of a texture class: RCI = exp(a + b ln(mc)), and its bulk density.
struct ConeIndexCoefficients {
    double a = 0, b = 0;
    double bulk_density_g_per_cm3 = 1.5;
};
ConeIndexCoefficients cone_index_coefficients(Texture t);

/// Rating cone index, psi, of a soil of texture `t` at volumetric water theta (m3/m3). The
/// gravimetric content is held within [1, 100] % (the form is a power law: unbounded at 0).
double rating_cone_index_psi(Texture t, double theta_m3_per_m3);
inline double rating_cone_index_kpa(Texture t, double theta_m3_per_m3) {
    return rating_cone_index_psi(t, theta_m3_per_m3) * kKpaPerPsi;
}

/// The rating cone index of every cell of `soil` at the soil water `theta` (same grid), kPa.
RasterD rating_cone_index_map_kpa(const SoilMap& soil, const RasterD& theta);

} // namespace ecoterra::hydro
