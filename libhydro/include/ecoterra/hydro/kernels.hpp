#pragma once
// The processes of the hydrology day as kernels: each a function over explicit inputs and
// outputs that a test can drive alone. HydrologyModel::step composes them in this order:
//
//   1. lake_losses        standing water (as yesterday's equilibrium left it) evaporates at the
//                         open-water rate E0 and infiltrates into the soil under it (percolating
//                         to the water table with groundwater on)
//   2. rain_on_lakes      rain on standing water joins it
//   3. partition_rain     rain elsewhere (less what canopy_interception held) splits into runoff
//                         and infiltration; water above the soil's ceiling (porosity, or field
//                         capacity under paper 002) percolates (paper 002 with groundwater) or
//                         runs off (saturation excess)
//   4. route_runoff       run-on, every cell after the cells above it; dry cells absorb up to
//                         their ceiling, the rest reaches a catchment or leaves through the edge
//   5. Catchments::equilibrate   the standing water settles (fills, spills, merges, splits)
//   6. evapotranspiration FAO-56: soil evaporation plus transpiration, each limited
//                         (evapotranspiration_fao56_range, after canopy_interception split the
//                         rain); paper 002: the larger of the surface demand and the plants'
//                         request; never below the wilting point; then gravity_drainage_range
//                         below the roots (6 to 9 run a block of cells at a time)
//   7. groundwater_exchange      the water table moves; where it reaches the surface it seeps out
//                                into the standing water, which settles again
//   8. close_budget       storage changes and the residual, checked against the tolerance
//   9. critical_layer_day the top layer vehicles bear on (0-0.3 m) follows the day's fluxes
//                         within the root zone's water (it moves water between the top and the
//                         rest of the root zone, never into or out of the soil)
//
// Kernels that accumulate a flux add to an accumulator passed by reference, so that the sums are
// taken in one fixed order whatever the composition.
#include "ecoterra/hydro/catchments.hpp"
#include "ecoterra/hydro/routing.hpp"
#include "ecoterra/hydro/runoff.hpp"
#include "ecoterra/hydro/soil.hpp"
#include "ecoterra/units.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace ecoterra::hydro {

class Groundwater;
enum class RunoffMethod;

/// The root-zone soil of every cell: water content (changed by the kernels) and its limits.
struct SoilColumns {
    double* theta;               ///< volumetric water content, m3/m3
    const float* field_capacity; ///< m3/m3
    const float* wilting_point;  ///< m3/m3
    const float* ksat_m_per_s;   ///< saturated conductivity (percolation limit), m/s
    double depth_m;              ///< root-zone depth
    double cell_area_m2;
    /// The most the soil holds, m3/m3: the field capacity where nothing drains (paper 002; null
    /// means field_capacity), the porosity where water above it drains by gravity.
    const float* ceiling = nullptr;
    /// Depletion of the evaporating surface layer, mm (FAO-56 De); null without the two-stage
    /// soil evaporation. Infiltration refills it.
    double* surface_depletion_mm = nullptr;
    double ceiling_at(std::int64_t k) const { return ceiling ? ceiling[k] : field_capacity[k]; }
    /// Infiltration of `m3` into cell k: the surface layer's depletion falls by its depth.
    void refill_surface(std::int64_t k, double m3) const {
        if (surface_depletion_mm)
            surface_depletion_mm[k] =
                std::max(0.0, surface_depletion_mm[k] - m3 / cell_area_m2 * kMmPerM);
    }
};

/// 1. Open-water evaporation (e0_mm over each catchment's wet cells) and infiltration under
///    standing water; with `recharge` (m3 per cell), percolation at Ksat x 1 day. Adds to the
///    accumulators, m3.
void lake_losses(Catchments& lakes, const RasterD& dem, const SoilColumns& soil, double e0_mm,
                 std::vector<double>* recharge, double& evaporation_m3, double& infiltration_m3);

/// 2. Rain (m) on every catchment's wet cells joins it.
void rain_on_lakes(Catchments& lakes, double rain_m, double cell_area_m2);

/// How rain splits on a dry cell.
struct RainPartition {
    RunoffMethod method;
    double rain_m = 0, rain_mm = 0;
    const double* runoff_coefficient; ///< per cell (coefficients method)
    const double* slope;              ///< rise/run per cell (curve-number method)
    double flat_slope = 0;            ///< below it a cell absorbs everything (curve number)
    const double* vegetation_density;
    const std::uint8_t* texture;
    const double* intercepted_m = nullptr; ///< rain held and evaporated by the canopy, per cell
};

/// 3. Rain on each dry cell: infiltration raises theta up to field capacity, the excess
///    percolates (with `recharge`) or runs off. Writes `runoff` (m3 per cell, 0 under standing
///    water) and adds the infiltration, m3. Cells in parallel, summed in fixed blocks.
void partition_rain(const Catchments& lakes, const SoilColumns& soil, const RainPartition& rain,
                    std::vector<double>& runoff, std::vector<double>* recharge,
                    double& infiltration_m3);

/// 4. Run-on in `order` (every cell after its higher neighbours): runoff reaching an outlet or
///    standing water joins the catchments, a dry cell absorbs up to its deficit, a pit starts a
///    catchment, the rest moves on (D8 receiver or MFD shares). Consumes `runoff`; adds the
///    absorbed water to the infiltration, m3.
void route_runoff(Catchments& lakes, const SoilColumns& soil,
                  const std::vector<std::int64_t>& order, Routing routing,
                  std::vector<double>& runoff, double& infiltration_m3);

/// The evaporative demands of the day, mm.
struct SurfaceDemand {
    double bare_soil_mm = 0, grass_mm = 0;
    const double* vegetation_density;
    double grass_density_threshold = 0;
};

/// 6. Evapotranspiration of each dry cell: the larger of its surface demand and the plants'
///    request (`request_mm` per cell, may be null), limited by the water above the wilting point.
///    Writes the water supplied to the plants (`supplied_mm`) and adds transpiration and soil
///    evaporation, m3.
void evapotranspiration(const Catchments& lakes, const SoilColumns& soil, std::int64_t cells,
                        const SurfaceDemand& demand, const double* request_mm, double* supplied_mm,
                        double& transpiration_m3, double& evaporation_m3);
/// evapotranspiration over the cells [begin, end) only, each sum taken in cell order and then
/// added (the building block of the grid-wide pass and of HydrologyModel's soil day).
void evapotranspiration_range(const Catchments& lakes, const SoilColumns& soil, std::int64_t begin,
                              std::int64_t end, const SurfaceDemand& demand,
                              const double* request_mm, double* supplied_mm,
                              double& transpiration_m3, double& evaporation_m3);

/// Gash's (1979) analytical interception model in its sparse-canopy form (Gash, Lloyd & Lachaud
/// 1995), one storm per rain day.
struct InterceptionParams {
    double storage_per_lai_mm = 0.2;   ///< canopy storage capacity per unit leaf area index, mm
    double evaporation_to_rain = 0.05; ///< mean wet-canopy evaporation rate / mean rain rate
};

/// Rain held on a canopy and evaporated, mm over the ground: the leaves (leaf area index `lai`)
/// cover the fraction `cover`, whose storage capacity is Sc = s LAI / c; a storm of P >= P' =
/// -(Sc / e) ln(1 - e) saturates it and loses c [P' + e (P - P')], a smaller one c P (e = E/R).
double gash_interception_mm(double rain_mm, double lai, double cover, const InterceptionParams& p);

/// 2b. Interception on every dry cell (none over standing water): writes `intercepted_m` (m per
/// cell) and adds the total, m3.
void canopy_interception(const Catchments& lakes, const double* lai, const double* cover,
                         double rain_mm, const InterceptionParams& p, double cell_area_m2,
                         std::vector<double>& intercepted_m, double& interception_m3);

/// The day's FAO-56 dual-coefficient terms (Allen et al. 1998 ch. 7).
struct Fao56Day {
    double et0_mm = 0;               ///< grass reference evapotranspiration
    double kc_max = 1.2;             ///< upper limit of Kcb + Ke (eq. 72, standard climate)
    double depletion_fraction = 0.5; ///< p: transpiration falls below (1 - p) of TAW (eq. 84)
    double default_kcb = 1.0;        ///< Kcb of full cover where no plant asks (hydrology alone)
    const double* cover;             ///< fraction of the ground under leaves, per cell
    const double* intercepted_m;     ///< today's interception per cell (may be null)
    const float* tew_mm;             ///< total evaporable water of the surface layer (eq. 73)
    double tew_scale = 1.0;          ///< today's factor on tew_mm (EvaporableWater)
    const double* kr;                ///< evaporation reduction at the day's start (eq. 74)
};

/// Today's factor on FAO-56 eq. 73's TEW: min(1, sqrt(ET0 / 5 mm/day)), the square-root
/// dependence on the evaporative demand of FAO-56's initial-stage TEW (ch. 6, Figs. 29-30: 13
/// sqrt(ET0) up to 28 mm on medium and fine soils, 7 sqrt(ET0) up to 15 mm on coarse ones).
inline double evaporable_water_scale(double et0_mm) {
    return et0_mm >= 5.0 ? 1.0 : std::sqrt(std::max(0.0, et0_mm) / 5.0);
}

/// FAO-56 eq. 74's Kr from the layer's TEW and REW (mm) scaled by `tew_scale` (REW at most 90 % of
/// the scaled TEW, as init_soil_layers bounds it) and its depletion at the day's start.
inline double evaporation_reduction(double tew_mm, double rew_mm, double tew_scale,
                                    double depletion_mm) {
    const double tew = tew_mm * tew_scale;
    const double rew = tew_scale < 1.0 ? std::min(rew_mm, 0.9 * tew) : rew_mm;
    return tew > rew ? std::clamp((tew - depletion_mm) / (tew - rew), 0.0, 1.0) : 0.0;
}

/// One cell's FAO-56 day (evapotranspiration_fao56's arithmetic): its inputs and what it gives.
struct Fao56Cell {
    double cover = 0, held_mm = 0;               ///< leaf cover; today's interception, mm
    double request_mm = 0;                       ///< the plants' request (used when `has_request`)
    double tew_mm = 0, kr = 1, depletion_mm = 0; ///< the surface layer (used when `has_surface`)
    double theta = 0, wilting_point = 0, field_capacity = 0;
    bool lake = false, has_request = false, has_surface = false;
};
struct Fao56Out {
    double transpiration_mm = 0, evaporation_mm = 0, theta = 0, depletion_mm = 0;
};

/// evapotranspiration_fao56 for one cell of root-zone depth `depth_m` (the definition the grid
/// pass computes, cell by cell, in evapotranspiration_fao56_cells), in scalars: `request_mm`
/// counts where `has_request`, the surface layer (`tew_mm`, `kr`, `depletion_mm`) where
/// `has_surface`.
inline void fao56_values(const Fao56Day& day, double c, double held_mm, bool has_request,
                         double request_mm, bool has_surface, double tew_mm, double kr,
                         double depletion_mm, double th, double wp, double fc, bool lake,
                         double depth_m, double& t, double& e, double& theta1, double& depletion1) {
    const double et0 = day.et0_mm;
    // Transpiration: what the plants ask, at most the energy their leaves receive.
    const double energy = std::max(0.0, c * day.kc_max * et0 - held_mm);
    const double t_pot =
        std::min(energy, has_request ? std::max(0.0, request_mm) : day.default_kcb * c * et0);
    // Loop invariants (hoisted out of the cells' loop): the vector units divide slowly.
    const double inv_et0 = et0 > 0 ? 1.0 / et0 : 0.0;
    const double theta_per_mm = 1.0 / (kMmPerM * depth_m);
    const double kcb = t_pot * inv_et0;
    // Soil evaporation from the exposed fraction, falling as the surface layer dries.
    const double few = std::max(0.01, 1.0 - c);
    // At most what the surface layer has left (eq. 77 bounds De by TEW, today's).
    const double tew = tew_mm * day.tew_scale;
    const double left = has_surface ? few * std::max(0.0, tew - depletion_mm) : 0.0;
    const double e_pot =
        lake ? 0.0
             : std::min(left,
                        kr * std::max(0.0, std::min(day.kc_max - kcb, few * day.kc_max)) * et0);
    const double p = day.depletion_fraction;
    const double ks = std::clamp((th - wp) / std::max((1.0 - p) * (fc - wp), 1e-9), 0.0, 1.0);
    t = ks * t_pot; // mm
    e = e_pot;
    const double avail = std::max(0.0, (th - wp) * depth_m) * kMmPerM;
    const double scale = avail / (t + e);
    const bool short_of_water = t + e > avail;
    t = short_of_water ? t * scale : t;
    e = short_of_water ? e * scale : e;
    theta1 = th - (t + e) * theta_per_mm;
    // A layer drier than today's TEW evaporates nothing and keeps its depletion.
    depletion1 = has_surface ? std::min(std::max(tew, depletion_mm), depletion_mm + e / few) : 0.0;
}

/// fao56_values of a cell's inputs.
inline Fao56Out fao56_cell(const Fao56Day& day, const Fao56Cell& in, double depth_m) {
    Fao56Out out;
    fao56_values(day, in.cover, in.held_mm, in.has_request, in.request_mm, in.has_surface,
                 in.tew_mm, in.kr, in.depletion_mm, in.theta, in.wilting_point, in.field_capacity,
                 in.lake, depth_m, out.transpiration_mm, out.evaporation_mm, out.theta,
                 out.depletion_mm);
    return out;
}

/// fao56_cell for `n` cells at once (arrays from the first of them): `lake[k]` 1 under standing
/// water; `intercepted_m`, `request_mm` and `depletion_mm` may be null (no interception,
/// no plants' request: Kcb_default c ET0, no surface layer). Updates `theta` and `depletion_mm`,
/// writes `supplied_mm` and, per cell of `cell_area_m2`, the transpiration and evaporation in m3
/// (mm / 1000 x area: the terms the grid pass sums in cell order). A loop vectorised for the
/// machine with the same bits as fao56_cell (soil_cells.cpp).
struct Fao56Cells {
    const double *cover, *intercepted_m, *request_mm, *kr;
    const float *tew_mm, *wilting_point, *field_capacity;
    const double* lake; ///< 1 under standing water, 0 elsewhere (a double: it vectorises)
    double *theta, *depletion_mm, *supplied_mm, *transpiration_m3, *evaporation_m3;
};
void evapotranspiration_fao56_cells(std::int64_t n, const Fao56Day& day, const Fao56Cells& c,
                                    double depth_m, double cell_area_m2);

/// 6. Evapotranspiration as the sum of two limited fluxes (FAO-56 eq. 69-77). Per cell:
///    transpiration T = Ks min(request, c Kc_max ET0 - I) (the energy on its leaves less what the
///    wet canopy used; `request_mm` null: Kcb_default c ET0); soil evaporation E = Kr min(Kc_max
///    - Kcb, few Kc_max) ET0 with few = 1 - c (none under standing water); both scaled down
///    together to the water above the wilting point. The surface layer's depletion grows by E /
///    few. Over the cells [begin, end) (HydrologyModel runs it a block at a time): writes
///    `supplied_mm` and adds transpiration and evaporation, m3, summed as
///    evapotranspiration_range does.
void evapotranspiration_fao56_range(const Catchments& lakes, const SoilColumns& soil,
                                    std::int64_t begin, std::int64_t end, const Fao56Day& day,
                                    const double* request_mm, double* supplied_mm,
                                    double& transpiration_m3, double& evaporation_m3);

/// 6b. Drainage below the root zone by gravity (unit gradient) at the unsaturated conductivity
///     K(theta) = Ks (theta / theta_s)^n, n = 3 + 2 / lambda (Saxton & Rawls 2006 eq. 16; theta_s
///     the porosity), integrated exactly over `dt_s`: u = theta / theta_s follows du/dt = -a u^n,
///     a = Ks / (d theta_s), so u1 = (u0^(1-n) + (n-1) a dt)^(-1/(n-1)). The water drained joins
///     `recharge` (m3 per cell, groundwater on) or leaves the domain (added to drained_m3).
///     Over the cells [begin, end); `scratch` is indexed as the cells and receives the drained
///     water contents before the wilting floor.
void gravity_drainage_range(const SoilColumns& soil, const float* porosity, const float* exponent,
                            std::int64_t begin, std::int64_t end, double dt_s,
                            std::vector<double>* recharge, double& drained_m3, double* scratch);

/// theta after `dt_s` of gravity drainage from `theta0` (the exact solution above), computed with
/// fastmath.hpp's single-precision logarithm and exponential for the drained fraction (within
/// about 1e-5 of it; theta itself in double, within 6e-8 of the double-precision form).
double drained_theta(double theta0, double porosity, double exponent, double ksat_m_per_s,
                     double depth_m, double dt_s);

/// drained_theta for `n` cells at once, `theta1[k]` from `theta0[k]` and the cell's soil: the
/// same bits as the scalar function, in a loop vectorised for the machine (drainage.cpp).
void drained_theta_cells(std::int64_t n, const double* theta0, const float* porosity,
                         const float* exponent, const float* ksat_m_per_s, double depth_m,
                         double dt_s, double* theta1);

/// A cell's critical layer: the top `depth_m` of the root zone (`root_depth_m` deep), whose water
/// decides the soil's strength under a vehicle (docs/hydrology.md s5b).
struct CriticalLayerCell {
    double depth_m = 0.3, root_depth_m = 1.0;
    double ceiling = 0;       ///< the most the soil holds, m3/m3 (SoilColumns::ceiling_at)
    double wilting_point = 0; ///< m3/m3
    double porosity = 0, exponent = 0, ksat_m_per_s = 0; ///< gravity drainage (drained_theta)
};

/// 9. The critical layer's water content at the day's end from `theta0` at its start, m3/m3.
///    The day's water into the soil (`inflow_m`, m) enters it first; it drains into the layer
///    below at K(theta) by gravity (drained_theta over its own depth), but not below the root
///    zone's water content at the day's end (a draining profile tends to a uniform one, so a wet
///    root zone keeps its top wet); the soil evaporation
///    (`evaporation_m`) leaves it first, down to half the wilting point (FAO-56's air-dry surface
///    layer); the transpiration (`transpiration_m`) leaves both layers in proportion to their
///    depth, down to the wilting point; what it cannot give or hold is the layer below's. Then
///    the layer's water is kept within what the root zone holds at the day's end
///    (`column_theta`): at most all of it and the layer's ceiling, at least what the layer below
///    cannot hold. The root zone's water is unchanged.
double critical_layer_day(const CriticalLayerCell& c, double theta0, double inflow_m,
                          double evaporation_m, double transpiration_m, double column_theta,
                          double dt_s);

/// critical_layer_day in its three parts, for loops that drain many cells at once
/// (drained_theta_cells): the layer's water content after the day's inflow; whether it drains
/// (it does only above the root zone's `column_theta`); the rest of the day from `theta_drained`
/// (drained_theta of the first part's result where it drains, that result where not).
inline double critical_layer_wetted(const CriticalLayerCell& c, double theta0, double inflow_m) {
    const double z = c.depth_m;
    return std::min(theta0 * z + std::max(0.0, inflow_m), c.ceiling * z) / z;
}

inline bool critical_layer_drains(const CriticalLayerCell& c, double theta_wetted,
                                  double column_theta) {
    // Gravity drains the layer at K(theta), but no drier than the root zone it drains into (a
    // draining profile tends to a uniform one; only evaporation and roots dry the top further).
    return c.porosity > 0 && c.exponent > 1 && theta_wetted > column_theta;
}

inline double critical_layer_rest(const CriticalLayerCell& c, double theta_drained,
                                  double evaporation_m, double transpiration_m,
                                  double column_theta) {
    const double z = c.depth_m, below = c.root_depth_m - c.depth_m;
    double w = theta_drained * z;
    w -= std::min(std::max(0.0, evaporation_m), std::max(0.0, w - 0.5 * c.wilting_point * z));
    w -= std::min(std::max(0.0, transpiration_m) * z / c.root_depth_m,
                  std::max(0.0, w - c.wilting_point * z));
    const double total = column_theta * c.root_depth_m;
    const double lo = std::max(0.0, total - c.ceiling * below), hi = std::min(c.ceiling * z, total);
    return std::clamp(w, lo, std::max(lo, hi)) / z;
}

/// The critical layer's day (critical_layer_day) for many cells at once, in the two parts around
/// the drainage: each array from the first cell; `ceiling` is SoilColumns::ceiling_at's; the
/// root zone's water at the day's start (`theta_start`), after the rain (`theta_wet`), after
/// evapotranspiration (`theta_et`) and at the day's end (`column_theta`). Loops vectorised for the
/// machine with the same bits as the per-cell parts (soil_cells.cpp).
struct CriticalLayerCells {
    double depth_m = 0.3, root_depth_m = 1.0;
    const float *ceiling, *wilting_point, *porosity, *exponent;
    const double *theta_start, *theta_wet, *theta_et, *column_theta;
    const double* transpiration_mm; ///< today's transpiration, mm (the root zone's)
};
/// critical_layer_wetted of each cell from the layer's `theta0`; `drains[k]` 1 where it drains
/// (critical_layer_drains), 0 where not.
void critical_layer_wetted_cells(std::int64_t n, const CriticalLayerCells& c, const double* theta0,
                                 double* wetted, double* drains);
/// critical_layer_rest of each cell: from max(`drained`, column) where `drains`, else from
/// `wetted`.
void critical_layer_rest_cells(std::int64_t n, const CriticalLayerCells& c, const double* wetted,
                               const double* drains, const double* drained, double* theta1);

/// 7. One day of groundwater flow with the day's `recharge` (m3 per cell): the outflow through
///    fixed-head edges (m3) is returned; water table above the surface seeps into the standing
///    water, which then settles again. Throws Error naming the day.
double groundwater_exchange(Groundwater& gw, Catchments& lakes, const std::vector<double>& recharge,
                            int day, int year, int doy);

} // namespace ecoterra::hydro
