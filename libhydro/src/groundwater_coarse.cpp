// An aquifer on cells coarser than the terrain's (GroundwaterNumerics::aquifer_cell_factor).
//
// The Dupuit-Forchheimer equation describes flow whose horizontal scale is well above the
// saturated thickness (Bear 1972, s8.2), and a day's diffusion length sqrt(K b t / S_y) is ~10 m
// for the default aquifer (K 7e-6 m/s, b 20 m, S_y 0.2), so aquifer cells of a few metres resolve
// what the equation represents while the terrain, soil and ponds keep their 1 m cells. The aquifer
// cell takes its terrain cells' mean surface, base and initial head (so its storage S_y (h - b) A
// is the sum of theirs under a level water table) and the geometric mean of their conductivities
// (the effective conductivity of a two-dimensional log-normal field; Matheron 1967, de Marsily
// 1986 s8.4). The recharge of its terrain cells is summed; the water table of each terrain cell is
// the aquifer heads interpolated bilinearly between the aquifer cells' centres, and where that
// stands above the terrain cell's surface, S_y (h - z) a seeps out of the terrain cell and leaves
// its aquifer cell's storage. Every step's seepage, outflow and storage change add up to its
// recharge to rounding, as on the terrain's own cells.
#include "ecoterra/error.hpp"
#include "ecoterra/hydro/multigrid.hpp"
#include "groundwater_impl.hpp"

#include <cmath>

namespace ecoterra::hydro {

Groundwater::Coarse::Coarse(const RasterD& surf, int factor) : fine(surf.grid()), f(factor) {
    if (f < 1)
        throw InputError("groundwater: the aquifer cell factor must be >= 1, got " +
                         std::to_string(f));
    if (fine.nx % f != 0 || fine.ny % f != 0)
        throw InputError("groundwater: the aquifer cell factor " + std::to_string(f) +
                         " does not divide the terrain's " + std::to_string(fine.nx) + " x " +
                         std::to_string(fine.ny) + " cells (choose a divisor of both)");
    aquifer =
        GridSpec{fine.nx / f, fine.ny / f, fine.cell_size_m * f, fine.origin_x_m, fine.origin_y_m};
    surface.assign(surf.data(), surf.data() + fine.size());
    const auto n = static_cast<std::size_t>(aquifer.size());
    recharge.assign(n, 0.0);
    heads.assign(n, 0.0);
    seep.assign(n, 0.0);
    seeping.assign(static_cast<std::size_t>(fine.size()), 0);
}

namespace {
/// Calls add(C, c) for every terrain cell c of every aquifer cell C of aquifer row J, in row order
/// within each aquifer cell's terrain cells.
template <class F>
void cells_of_row(const GridSpec& fine, int f, int J, F&& add) {
    const int ax = fine.nx / f;
    for (int j = J * f; j < (J + 1) * f; ++j)
        for (int i = 0; i < fine.nx; ++i)
            add(static_cast<std::int64_t>(J) * ax + i / f,
                static_cast<std::int64_t>(j) * fine.nx + i);
}
} // namespace

RasterD Groundwater::Coarse::mean(const RasterD& r) const {
    RasterD out(aquifer, 0.0);
    for (int J = 0; J < aquifer.ny; ++J)
        cells_of_row(fine, f, J,
                     [&](std::int64_t C, std::int64_t c) { out.data()[C] += r.data()[c]; });
    out.array() /= static_cast<double>(f) * f;
    return out;
}

RasterF Groundwater::Coarse::geometric_mean(const RasterF& k) const {
    RasterD logs(aquifer, 0.0), zero(aquifer, 0.0);
    for (int J = 0; J < aquifer.ny; ++J)
        cells_of_row(fine, f, J, [&](std::int64_t C, std::int64_t c) {
            const double v = k.data()[c];
            if (!(v >= 0) || !std::isfinite(v))
                throw InputError("groundwater: invalid conductivity at cell " + std::to_string(c));
            if (v > 0)
                logs.data()[C] += std::log(v);
            else
                zero.data()[C] = 1; // an impermeable terrain cell makes its aquifer cell so
        });
    RasterF out(aquifer, 0.0f);
    for (std::int64_t C = 0; C < aquifer.size(); ++C)
        if (zero.data()[C] == 0)
            out.data()[C] =
                static_cast<float>(std::exp(logs.data()[C] / (static_cast<double>(f) * f)));
    return out;
}

const std::vector<double>& Groundwater::Coarse::restrict(const std::vector<double>& fine_m3) {
#pragma omp parallel for schedule(static) if (parallel_grid(fine.size()))
    for (int J = 0; J < aquifer.ny; ++J) {
        std::fill_n(recharge.begin() + static_cast<std::int64_t>(J) * aquifer.nx, aquifer.nx, 0.0);
        cells_of_row(fine, f, J,
                     [&](std::int64_t C, std::int64_t c) { recharge[C] += fine_m3[c]; });
    }
    return recharge;
}

void Groundwater::seep_coarse(GroundwaterResult& r) {
    Coarse& cs = *m_coarse;
    for (std::int64_t C = 0; C < cs.aquifer.size(); ++C) cs.heads[C] = m->head_of(C, m->y.data());
    r.seepage_m3.assign(static_cast<std::size_t>(cs.fine.size()), 0.0);
    const double a = cs.fine.cell_size_m * cs.fine.cell_size_m;
    // Each aquifer row's terrain cells are its own: the sums do not depend on the thread count.
#pragma omp parallel for schedule(static) if (parallel_grid(cs.fine.size()))
    for (int J = 0; J < cs.aquifer.ny; ++J) {
        std::fill_n(cs.seep.begin() + static_cast<std::int64_t>(J) * cs.aquifer.nx, cs.aquifer.nx,
                    0.0);
        cs.interpolate_row(cs.heads.data(), J, [&](std::int64_t c, std::int64_t C, double h) {
            const bool seeps = h > cs.surface[c] && m->var_of_cell[C] >= 0;
            cs.seeping[c] = seeps;
            if (seeps) {
                const double s = m->sy * (h - cs.surface[c]) * a;
                r.seepage_m3[c] = s;
                cs.seep[C] += s;
            }
        });
    }
    bool seeped = false;
    for (std::int64_t v = 0; v < m->nvar(); ++v) {
        const double s = cs.seep[m->cell_of_var[v]];
        if (s > 0) {
            m->y[v] -= s / (m->sy * m->area);
            seeped = true;
        }
    }
    if (seeped) m->heads_changed();
}

} // namespace ecoterra::hydro
