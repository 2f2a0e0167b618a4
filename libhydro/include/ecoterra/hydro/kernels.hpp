#pragma once
// The processes of the hydrology day as kernels: each a function over explicit inputs and
// outputs that a test can drive alone. HydrologyModel::step composes them in this order:
//
//   1. lake_losses        standing water (as yesterday's equilibrium left it) evaporates at the
//                         open-water rate E0 and infiltrates into the soil under it (percolating
//                         to the water table with groundwater on)
//   2. rain_on_lakes      rain on standing water joins it
//   3. partition_rain     rain elsewhere splits into runoff and infiltration; water above field
//                         capacity percolates (groundwater) or runs off (saturation excess)
//   4. route_runoff       run-on, every cell after the cells above it; dry cells absorb up to
//                         field capacity, the rest reaches a catchment or leaves through the edge
//   5. Catchments::equilibrate   the standing water settles (fills, spills, merges, splits)
//   6. evapotranspiration each dry cell loses the larger of its surface demand and the plants'
//                         request, never below the wilting point
//   7. groundwater_exchange      the water table moves; where it reaches the surface it seeps out
//                                into the standing water, which settles again
//   8. close_budget       storage changes and the residual, checked against the tolerance
//
// Kernels that accumulate a flux add to an accumulator passed by reference, so that the sums are
// taken in one fixed order whatever the composition.
#include "ecoterra/hydro/catchments.hpp"
#include "ecoterra/hydro/routing.hpp"
#include "ecoterra/hydro/runoff.hpp"
#include "ecoterra/hydro/soil.hpp"

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

/// 7. One day of groundwater flow with the day's `recharge` (m3 per cell): the outflow through
///    fixed-head edges (m3) is returned; water table above the surface seeps into the standing
///    water, which then settles again. Throws Error naming the day.
double groundwater_exchange(Groundwater& gw, Catchments& lakes, const std::vector<double>& recharge,
                            int day, int year, int doy);

} // namespace ecoterra::hydro
