// The soil day's per-cell arithmetic over many cells, in loops the compiler vectorises: FAO-56
// evapotranspiration (fao56_cell) and the critical layer's parts, the hottest per-cell-day passes
// of the default hydrology after the drainage. CMakeLists.txt compiles this file as drainage.cpp
// (-fno-trapping-math: the branches become selects; -ffp-contract=off: every clone computes the
// per-cell functions' bits, as the tests "[fao56]" and "[critical_layer]" check).
#include "ecoterra/fastmath.hpp"
#include "ecoterra/hydro/kernels.hpp"

namespace ecoterra::hydro {
namespace {

/// The loop with its optional inputs fixed (no test inside it, so it vectorises), inlined into
/// each clone below.
template <bool Held, bool Request, bool Surface>
[[gnu::always_inline]] inline void fao56_loop(std::int64_t n, const Fao56Day& day,
                                              const Fao56Cells& c, double depth_m, double area) {
    const double *cover = c.cover, *held = c.intercepted_m, *request = c.request_mm, *kr = c.kr;
    const double* lake = c.lake;
    const float *tew = c.tew_mm, *wp = c.wilting_point, *fc = c.field_capacity;
    double *theta = c.theta, *depletion = c.depletion_mm, *supplied = c.supplied_mm,
           *transpiration_m3 = c.transpiration_m3, *evaporation_m3 = c.evaporation_m3;
    const Fao56Day d = day;
    const double m3_per_mm = area / kMmPerM;
    // Every array is its own: without ivdep the loop needs more run-time overlap checks than GCC
    // makes and stays scalar.
    ECOTERRA_IVDEP
    for (std::int64_t k = 0; k < n; ++k) {
        double t, e, th, de;
        fao56_values(d, cover[k], Held ? held[k] * kMmPerM : 0.0, Request,
                     Request ? request[k] : 0.0, Surface, tew[k], kr[k],
                     Surface ? depletion[k] : 0.0, theta[k], wp[k], fc[k], lake[k] != 0.0, depth_m,
                     t, e, th, de);
        theta[k] = th;
        if constexpr (Surface) depletion[k] = de;
        supplied[k] = t;
        transpiration_m3[k] = t * m3_per_mm;
        evaporation_m3[k] = e * m3_per_mm;
    }
}

} // namespace

ECOTERRA_CLONES
void evapotranspiration_fao56_cells(std::int64_t n, const Fao56Day& day, const Fao56Cells& c,
                                    double depth_m, double area) {
    const bool held = c.intercepted_m != nullptr, request = c.request_mm != nullptr,
               surface = c.depletion_mm != nullptr;
    if (held && request && surface) return fao56_loop<true, true, true>(n, day, c, depth_m, area);
    if (held && request) return fao56_loop<true, true, false>(n, day, c, depth_m, area);
    if (held && surface) return fao56_loop<true, false, true>(n, day, c, depth_m, area);
    if (held) return fao56_loop<true, false, false>(n, day, c, depth_m, area);
    if (request && surface) return fao56_loop<false, true, true>(n, day, c, depth_m, area);
    if (request) return fao56_loop<false, true, false>(n, day, c, depth_m, area);
    if (surface) return fao56_loop<false, false, true>(n, day, c, depth_m, area);
    fao56_loop<false, false, false>(n, day, c, depth_m, area);
}

namespace {
CriticalLayerCell layer_cell(const CriticalLayerCells& c, std::int64_t k) {
    CriticalLayerCell l;
    l.depth_m = c.depth_m;
    l.root_depth_m = c.root_depth_m;
    l.ceiling = c.ceiling[k];
    l.wilting_point = c.wilting_point[k];
    l.porosity = c.porosity[k];
    l.exponent = c.exponent[k];
    return l;
}
} // namespace

ECOTERRA_CLONES
void critical_layer_wetted_cells(std::int64_t n, const CriticalLayerCells& c, const double* theta0,
                                 double* wetted, double* drains) {
    const CriticalLayerCells cc = c;
    ECOTERRA_IVDEP
    for (std::int64_t k = 0; k < n; ++k) {
        const CriticalLayerCell l = layer_cell(cc, k);
        const double inflow_m =
            std::max(0.0, cc.theta_wet[k] - cc.theta_start[k]) * cc.root_depth_m;
        const double w = critical_layer_wetted(l, theta0[k], inflow_m);
        wetted[k] = w;
        drains[k] = critical_layer_drains(l, w, cc.column_theta[k]) ? 1.0 : 0.0;
    }
}

ECOTERRA_CLONES
void critical_layer_rest_cells(std::int64_t n, const CriticalLayerCells& c, const double* wetted,
                               const double* drains, const double* drained, double* theta1) {
    const CriticalLayerCells cc = c;
    ECOTERRA_IVDEP
    for (std::int64_t k = 0; k < n; ++k) {
        const CriticalLayerCell l = layer_cell(cc, k);
        const double column = cc.column_theta[k];
        const double transpiration_m = cc.transpiration_mm[k] / kMmPerM;
        const double et_m = std::max(0.0, cc.theta_wet[k] - cc.theta_et[k]) * cc.root_depth_m;
        const double evaporation_m = std::max(0.0, et_m - transpiration_m);
        const double from = drains[k] != 0.0 ? std::max(drained[k], column) : wetted[k];
        theta1[k] = critical_layer_rest(l, from, evaporation_m, transpiration_m, column);
    }
}

} // namespace ecoterra::hydro
