#pragma once
// The aquifer shared by the groundwater solvers: rasters, the evolving cells, the face
// transmissivity and the state (heads of the evolving cells and the cumulative outflow).
#include "ecoterra/hydro/groundwater.hpp"

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

namespace ecoterra::hydro {

inline constexpr double kMinSaturatedThickness = 1e-3; ///< t_min, m

struct Groundwater::Impl {
    GridSpec grid;
    std::vector<double> surface, base, head_fixed, k;
    double sy = 0.2, area = 1.0;
    std::vector<std::int64_t> cell_of_var; ///< evolving cells
    std::vector<std::int32_t> var_of_cell; ///< -1 for fixed-head cells
    std::vector<double> rate;              ///< recharge per variable, m3/s
    /// The state: heads of the evolving cells (m), then the cumulative outflow (m3).
    std::vector<double> y;
    long steps = 0;
    double t_now = 0;     ///< integrator time, s
    double last_step = 0; ///< the last internal step size, s (CVODE's restart hint)

    Impl(const RasterD& surf, const RasterD& b, const RasterD& h0, const RasterF& ks,
         double specific_yield, std::array<GroundwaterBoundary, 4> sides);
    virtual ~Impl() = default;
    /// Advances y by dt_s with the recharge rates in `rate`.
    virtual void advance(double dt_s) = 0;
    /// Heads changed outside the integrator (seepage, a checkpoint).
    virtual void heads_changed() {}
    virtual GroundwaterSolver solver() const = 0;

    std::int64_t nvar() const { return static_cast<std::int64_t>(cell_of_var.size()); }
    template <class F>
    void neighbours(std::int64_t c, F&& f) const {
        const int i = static_cast<int>(c % grid.nx), j = static_cast<int>(c / grid.nx);
        for (const auto& o : kVonNeumannOffsets) {
            const int a = i + o[0], b = j + o[1];
            if (grid.contains(a, b)) f(static_cast<std::int64_t>(b) * grid.nx + a);
        }
    }
    double head_of(std::int64_t c, const double* h) const {
        const std::int32_t v = var_of_cell[c];
        return v >= 0 ? h[v] : head_fixed[c];
    }
    /// Face transmissivity (m2/s, the face width equals the distance) and its derivative with
    /// respect to either head.
    std::pair<double, double> face(std::int64_t a, std::int64_t b, double ha, double hb) const {
        const double kf = (k[a] > 0 && k[b] > 0) ? 2.0 * k[a] * k[b] / (k[a] + k[b]) : 0.0;
        const double sat = 0.5 * (ha + hb) - 0.5 * (base[a] + base[b]);
        if (sat <= kMinSaturatedThickness) return {kf * kMinSaturatedThickness, 0.0};
        return {kf * sat, 0.5 * kf};
    }
};

/// The terrain's grid under an aquifer of cells f x f terrain cells large (aquifer_cell_factor).
struct Groundwater::Coarse {
    GridSpec fine;                ///< the terrain's grid
    GridSpec aquifer;             ///< the aquifer's
    int f = 1;                    ///< terrain cells to an aquifer cell's side
    std::vector<double> surface;  ///< of the terrain cells, m
    std::vector<double> recharge; ///< per aquifer cell over a step, m3
    std::vector<double> heads;    ///< of every aquifer cell, fixed or evolving, m (scratch)
    std::vector<double> seep;     ///< per aquifer cell over a step, m3
    /// Terrain cells that seeped at the last step: their water table is at the surface (state).
    std::vector<std::uint8_t> seeping;

    Coarse(const RasterD& surface, int factor);
    /// The aquifer's rasters: each aquifer cell's terrain cells' mean (the surface, the base, the
    /// initial head) or geometric mean (the conductivity).
    RasterD mean(const RasterD& r) const;
    RasterF geometric_mean(const RasterF& k) const;
    /// The recharge summed over each aquifer cell's terrain cells (in row order within a cell).
    const std::vector<double>& restrict(const std::vector<double>& fine_m3);
    /// Calls f(c, C, h) for each terrain cell c of the aquifer row J: C its aquifer cell and h the
    /// aquifer cells' heads `hs` interpolated bilinearly to its centre (clamped to the outer
    /// aquifer cells' centres at the edges).
    template <class F>
    void interpolate_row(const double* hs, int J, F&& fn) const {
        const int ax = aquifer.nx, ay = aquifer.ny;
        for (int j = J * f; j < (J + 1) * f; ++j) {
            const double y = std::clamp((j + 0.5) / f - 0.5, 0.0, ay - 1.0);
            const int j0 = std::min(static_cast<int>(y), ay - 1), j1 = std::min(j0 + 1, ay - 1);
            const double wy = y - j0;
            for (int i = 0; i < fine.nx; ++i) {
                const double x = std::clamp((i + 0.5) / f - 0.5, 0.0, ax - 1.0);
                const int i0 = std::min(static_cast<int>(x), ax - 1), i1 = std::min(i0 + 1, ax - 1);
                const double wx = x - i0;
                const double* r0 = hs + static_cast<std::int64_t>(j0) * ax;
                const double* r1 = hs + static_cast<std::int64_t>(j1) * ax;
                const double h = (1 - wy) * ((1 - wx) * r0[i0] + wx * r0[i1]) +
                                 wy * ((1 - wx) * r1[i0] + wx * r1[i1]);
                fn(static_cast<std::int64_t>(j) * fine.nx + i,
                   static_cast<std::int64_t>(J) * ax + i / f, h);
            }
        }
    }
};

std::unique_ptr<Groundwater::Impl> make_cvode_groundwater(const RasterD& surf, const RasterD& b,
                                                          const RasterD& h0, const RasterF& ks,
                                                          double sy,
                                                          std::array<GroundwaterBoundary, 4> sides);
std::unique_ptr<Groundwater::Impl>
make_implicit_groundwater(const RasterD& surf, const RasterD& b, const RasterD& h0,
                          const RasterF& ks, double sy, std::array<GroundwaterBoundary, 4> sides,
                          int substeps, double head_tolerance_m);

} // namespace ecoterra::hydro
