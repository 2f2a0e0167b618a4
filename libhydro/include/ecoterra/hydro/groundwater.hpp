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
// Two time integrators (GroundwaterSolver):
// - implicit (the default): TR-BDF2 steps (GroundwaterNumerics::substeps per call), each stage
//   linearised (transmissivities frozen over it) and solved by conjugate gradients preconditioned
//   with an aggregation multigrid V-cycle (multigrid.hpp). Each stage's heads are then advanced by
//   the face fluxes of its solved heads, so storage change + outflow equal the recharge to
//   rounding whatever the solver's tolerance. Work grows in proportion to the cells.
// - cvode (the reference): SUNDIALS CVODE (Hindmarsh et al. 2005), BDF with Newton iterations, an
//   analytic sparse Jacobian and the KLU direct solver, error-controlled. The cumulative outflow
//   is an extra ODE variable, so the budget uses the integrated boundary flux. Every SUNDIALS call
//   is checked; the context, integrator, vectors, matrix and solver are owned by RAII wrappers.
#include "ecoterra/archive.hpp"
#include "ecoterra/raster.hpp"

#include <memory>
#include <vector>

namespace ecoterra::hydro {

enum class GroundwaterBoundary { fixed_head, no_flow };
enum class GroundwaterSolver { implicit, cvode };

/// How the heads are integrated. The implicit solver is second order in its step: after a year of
/// daily recharge on 1 m cells its water table differs from CVODE's by up to 1.6 cm at 1 step a
/// day, 0.63 cm at 2 and 0.066 cm at 4, on the worst of four terrains
/// (tests/verification/test_groundwater.cpp; backward Euler, first order, gave 3.1, 1.7 and
/// 0.87 cm at the same cost).
struct GroundwaterNumerics {
    GroundwaterSolver solver = GroundwaterSolver::implicit;
    int substeps = 2; ///< TR-BDF2 steps per call of step() (implicit solver)
    /// The implicit solver's stages stop when the residual stands for at most this root mean
    /// square change of head, m: an order below the error of 2 steps a day against CVODE.
    double head_tolerance_m = 1e-5;
    /// Aquifer cells are this many terrain cells on a side (1: the terrain's own cells). With a
    /// factor f > 1 the aquifer is solved on cells f times larger, which must divide the terrain's
    /// columns and rows: each takes its f x f terrain cells' mean surface, base and initial head,
    /// the geometric mean of their conductivities and the sum of their recharge; the water table
    /// of a terrain cell is the aquifer's heads interpolated bilinearly between the aquifer cells'
    /// centres, and where it stands above the terrain cell's surface that water seeps out there
    /// and leaves its aquifer cell's storage (docs/hydrology.md s6).
    int aquifer_cell_factor = 1;
};

struct GroundwaterResult {
    double outflow_m3 = 0;          ///< water that left through fixed-head edges
    std::vector<double> seepage_m3; ///< water table above the surface, removed, per cell
};

class Groundwater {
public:
    /// Head starts at surface - initial_depth_m; base at surface - thickness_m.
    Groundwater(const RasterD& surface, const RasterF& ksat_m_per_s, double specific_yield,
                double thickness_m, double initial_depth_m, GroundwaterNumerics numerics = {});
    /// General form: base elevation and initial head rasters, per-side boundaries
    /// (west, east, south, north).
    Groundwater(const RasterD& surface, const RasterD& base, const RasterD& initial_head,
                const RasterF& ksat_m_per_s, double specific_yield,
                std::array<GroundwaterBoundary, 4> sides, GroundwaterNumerics numerics = {});
    ~Groundwater();
    Groundwater(Groundwater&&) noexcept;
    Groundwater& operator=(Groundwater&&) noexcept;

    /// Integrates dt seconds with recharge per terrain cell (m3 over the step, spread evenly in
    /// time); the seepage is per terrain cell too.
    GroundwaterResult step(double dt_s, const std::vector<double>& recharge_m3);

    /// The water table on the terrain's cells, m (under a coarser aquifer: interpolated, at most
    /// the surface, and at the surface where the last step seeped).
    RasterD head() const;
    /// S_y (h - b) A summed over the cells that evolve, m3.
    double storage_m3() const;
    /// Work done so far (for benchmarks): CVODE's internal steps, or the implicit solver's
    /// conjugate-gradient iterations.
    long steps_taken() const;
    GroundwaterSolver solver() const;

    /// Checkpoint: heads, cumulative outflow, integrator time and step-size hint (and, under a
    /// coarser aquifer, which terrain cells seeped). Both solvers write the same layout, so a run
    /// may resume with the other solver.
    void save_state(ArchiveWriter& a) const;
    void load_state(ArchiveReader& a);

    struct Impl;   ///< the aquifer and its heads; each solver derives from it
    struct Coarse; ///< the terrain's grid under an aquifer of coarser cells

private:
    void init(const RasterD& surface, const RasterD& base, const RasterD& initial_head,
              const RasterF& ksat, double sy, std::array<GroundwaterBoundary, 4> sides,
              GroundwaterNumerics numerics);
    /// Water-table seepage on the terrain's cells under a coarser aquifer; fills r.seepage_m3.
    void seep_coarse(GroundwaterResult& r);

    std::unique_ptr<Impl> m;
    std::unique_ptr<Coarse> m_coarse; ///< null when the aquifer uses the terrain's cells
};

} // namespace ecoterra::hydro
