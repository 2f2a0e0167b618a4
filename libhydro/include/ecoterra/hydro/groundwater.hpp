#pragma once
// Lateral saturated groundwater flow: the Dupuit-Boussinesq equation for an unconfined aquifer on
// an impermeable base b (Bear 1972, ch. 8; Boussinesq 1904):
//   S_y dh/dt = div( K (h - b) grad h ) + R
// h: water-table elevation (m); S_y: specific yield; K: saturated conductivity (m/s); R: recharge
// (m/s). Finite volumes on the raster: between edge-sharing cells i and n the flow is
//   Q_in = K_f max(h_f - b_f, t_min) (h_n - h_i)        (m3/s; face width = cell length)
// with K_f the harmonic mean of K_i and K_n, h_f and b_f arithmetic means, t_min = 1 mm. With the
// arithmetic face head, K_f h_f (h_n - h_i) = K_f (h_n^2 - h_i^2) / 2, so the steady discrete
// solution for a uniform aquifer is exact for Dupuit's parabola.
// Boundaries: each side of the domain is either a fixed head (its edge cells keep their head;
// flow into them leaves the domain and is counted) or no flow.
// Time integration: SUNDIALS CVODE (Hindmarsh et al. 2005), BDF with Newton iterations, an
// analytic sparse Jacobian and the KLU direct solver. The cumulative outflow is an extra ODE
// variable, so the budget uses the integrated boundary flux. Every SUNDIALS call is checked; the
// context, integrator, vectors, matrix and solver are owned by RAII wrappers.
#include "ecoterra/archive.hpp"
#include "ecoterra/raster.hpp"

#include <memory>
#include <vector>

namespace ecoterra::hydro {

enum class GroundwaterBoundary { fixed_head, no_flow };

struct GroundwaterResult {
    double outflow_m3 = 0;          ///< water that left through fixed-head edges
    std::vector<double> seepage_m3; ///< water table above the surface, removed, per cell
};

class Groundwater {
public:
    /// Head starts at surface - initial_depth_m; base at surface - thickness_m.
    Groundwater(const RasterD& surface, const RasterF& ksat_m_per_s, double specific_yield,
                double thickness_m, double initial_depth_m);
    /// General form: base elevation and initial head rasters, per-side boundaries
    /// (west, east, south, north).
    Groundwater(const RasterD& surface, const RasterD& base, const RasterD& initial_head,
                const RasterF& ksat_m_per_s, double specific_yield,
                std::array<GroundwaterBoundary, 4> sides);
    ~Groundwater();

    /// Integrates dt seconds with recharge per cell (m3 over the step, spread evenly in time).
    GroundwaterResult step(double dt_s, const std::vector<double>& recharge_m3);

    RasterD head() const;
    /// S_y (h - b) A summed over the cells that evolve, m3.
    double storage_m3() const;
    /// Steps CVODE took so far (for benchmarks).
    long steps_taken() const;

    /// Checkpoint: heads, cumulative outflow, integrator time and step-size hint.
    void save_state(ArchiveWriter& a) const;
    void load_state(ArchiveReader& a);

private:
    struct Impl;
    std::unique_ptr<Impl> m;
};

} // namespace ecoterra::hydro
