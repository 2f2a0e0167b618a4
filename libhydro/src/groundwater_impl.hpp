#pragma once
// The aquifer shared by the groundwater solvers: rasters, the evolving cells, the face
// transmissivity and the state (heads of the evolving cells and the cumulative outflow).
#include "ecoterra/hydro/groundwater.hpp"

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

std::unique_ptr<Groundwater::Impl> make_cvode_groundwater(const RasterD& surf, const RasterD& b,
                                                          const RasterD& h0, const RasterF& ks,
                                                          double sy,
                                                          std::array<GroundwaterBoundary, 4> sides);
std::unique_ptr<Groundwater::Impl>
make_implicit_groundwater(const RasterD& surf, const RasterD& b, const RasterD& h0,
                          const RasterF& ks, double sy, std::array<GroundwaterBoundary, 4> sides,
                          int substeps, double head_tolerance_m);

} // namespace ecoterra::hydro
