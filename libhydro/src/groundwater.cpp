#include "ecoterra/hydro/groundwater.hpp"

#include "ecoterra/error.hpp"
#include "ecoterra/parallel.hpp"
#include "groundwater_impl.hpp"

#include <algorithm>
#include <cmath>

namespace ecoterra::hydro {

namespace {
void require_one_grid(const RasterD& surf, const RasterD& b, const RasterD& h0, const RasterF& ks) {
    const GridSpec& g = surf.grid();
    if (!(b.grid() == g) || !(h0.grid() == g) || !(ks.grid() == g))
        throw InputError("groundwater: base, head and conductivity rasters must share the "
                         "terrain's grid");
}
} // namespace

Groundwater::Impl::Impl(const RasterD& surf, const RasterD& b, const RasterD& h0, const RasterF& ks,
                        double specific_yield, std::array<GroundwaterBoundary, 4> sides) {
    grid = surf.grid();
    require_one_grid(surf, b, h0, ks);
    if (!(specific_yield > 0 && specific_yield < 1))
        throw InputError("groundwater: specific yield must be in (0, 1)");
    sy = specific_yield;
    area = grid.cell_size_m * grid.cell_size_m;
    const std::int64_t ncell = grid.size();
    surface.assign(surf.data(), surf.data() + ncell);
    base.assign(b.data(), b.data() + ncell);
    head_fixed.assign(h0.data(), h0.data() + ncell);
    k.resize(static_cast<std::size_t>(ncell));
    for (std::int64_t c = 0; c < ncell; ++c) {
        k[c] = ks.data()[c];
        if (!(k[c] >= 0) || !std::isfinite(base[c]) || !std::isfinite(head_fixed[c]))
            throw InputError("groundwater: invalid conductivity, base or head at cell " +
                             std::to_string(c));
    }
    var_of_cell.assign(static_cast<std::size_t>(ncell), -1);
    for (int j = 0; j < grid.ny; ++j)
        for (int i = 0; i < grid.nx; ++i) {
            const bool fixed = (i == 0 && sides[0] == GroundwaterBoundary::fixed_head) ||
                               (i == grid.nx - 1 && sides[1] == GroundwaterBoundary::fixed_head) ||
                               (j == 0 && sides[2] == GroundwaterBoundary::fixed_head) ||
                               (j == grid.ny - 1 && sides[3] == GroundwaterBoundary::fixed_head);
            if (fixed) continue;
            const std::int64_t c = static_cast<std::int64_t>(j) * grid.nx + i;
            var_of_cell[c] = static_cast<std::int32_t>(cell_of_var.size());
            cell_of_var.push_back(c);
        }
    const std::int64_t n = nvar();
    if (n == 0) throw InputError("groundwater: every cell is a fixed head; nothing evolves");
    rate.assign(static_cast<std::size_t>(n), 0.0);
    y.resize(static_cast<std::size_t>(n + 1));
    for (std::int64_t v = 0; v < n; ++v) y[v] = head_fixed[cell_of_var[v]];
    y[n] = 0.0;
}

namespace {
std::unique_ptr<Groundwater::Impl> make(const RasterD& surface, const RasterD& base,
                                        const RasterD& head, const RasterF& ksat, double sy,
                                        std::array<GroundwaterBoundary, 4> sides,
                                        GroundwaterNumerics numerics) {
    return numerics.solver == GroundwaterSolver::cvode
               ? make_cvode_groundwater(surface, base, head, ksat, sy, sides)
               : make_implicit_groundwater(surface, base, head, ksat, sy, sides, numerics.substeps,
                                           numerics.head_tolerance_m);
}
} // namespace

Groundwater::Groundwater(const RasterD& surface, const RasterF& ksat, double specific_yield,
                         double thickness_m, double initial_depth_m, GroundwaterNumerics numerics) {
    RasterD b = surface, h0 = surface;
    b.array() -= thickness_m;
    h0.array() -= initial_depth_m;
    using GB = GroundwaterBoundary;
    init(surface, b, h0, ksat, specific_yield,
         {GB::fixed_head, GB::fixed_head, GB::fixed_head, GB::fixed_head}, numerics);
}

Groundwater::Groundwater(const RasterD& surface, const RasterD& base, const RasterD& initial_head,
                         const RasterF& ksat, double specific_yield,
                         std::array<GroundwaterBoundary, 4> sides, GroundwaterNumerics numerics) {
    init(surface, base, initial_head, ksat, specific_yield, sides, numerics);
}

void Groundwater::init(const RasterD& surface, const RasterD& base, const RasterD& initial_head,
                       const RasterF& ksat, double sy, std::array<GroundwaterBoundary, 4> sides,
                       GroundwaterNumerics numerics) {
    if (numerics.aquifer_cell_factor == 1) {
        m = make(surface, base, initial_head, ksat, sy, sides, numerics);
        return;
    }
    require_one_grid(surface, base, initial_head, ksat);
    m_coarse = std::make_unique<Coarse>(surface, numerics.aquifer_cell_factor);
    const Coarse& cs = *m_coarse;
    m = make(cs.mean(surface), cs.mean(base), cs.mean(initial_head), cs.geometric_mean(ksat), sy,
             sides, numerics);
}

Groundwater::~Groundwater() = default;
Groundwater::Groundwater(Groundwater&&) noexcept = default;
Groundwater& Groundwater::operator=(Groundwater&&) noexcept = default;

GroundwaterResult Groundwater::step(double dt_s, const std::vector<double>& recharge_m3) {
    if (!(dt_s > 0)) throw InputError("groundwater: the time step must be > 0 s");
    const std::int64_t ncell = m_coarse ? m_coarse->fine.size() : m->grid.size();
    if (static_cast<std::int64_t>(recharge_m3.size()) != ncell)
        throw InputError("groundwater: the recharge has " + std::to_string(recharge_m3.size()) +
                         " cells for a grid of " + std::to_string(ncell));
    const std::vector<double>& recharge = m_coarse ? m_coarse->restrict(recharge_m3) : recharge_m3;
    const std::int64_t n = m->nvar();
    for (std::int64_t v = 0; v < n; ++v) m->rate[v] = recharge[m->cell_of_var[v]] / dt_s;
    const double out0 = m->y[n];
    m->advance(dt_s);
    GroundwaterResult r;
    r.outflow_m3 = m->y[n] - out0;
    // Recharge onto a fixed-head cell leaves through that boundary at once.
    for (std::int64_t c = 0; c < m->grid.size(); ++c)
        if (m->var_of_cell[c] < 0) r.outflow_m3 += recharge[c];
    if (m_coarse) {
        seep_coarse(r);
        return r;
    }
    r.seepage_m3.assign(static_cast<std::size_t>(m->grid.size()), 0.0);
    bool seeped = false;
    for (std::int64_t v = 0; v < n; ++v) {
        const std::int64_t c = m->cell_of_var[v];
        if (m->y[v] > m->surface[c]) {
            r.seepage_m3[c] = m->sy * (m->y[v] - m->surface[c]) * m->area;
            m->y[v] = m->surface[c];
            seeped = true;
        }
    }
    if (seeped) m->heads_changed();
    return r;
}

RasterD Groundwater::head() const {
    if (m_coarse) {
        const Coarse& cs = *m_coarse;
        std::vector<double> hs(static_cast<std::size_t>(cs.aquifer.size()));
        for (std::int64_t C = 0; C < cs.aquifer.size(); ++C) hs[C] = m->head_of(C, m->y.data());
        RasterD h(cs.fine);
        for (int J = 0; J < cs.aquifer.ny; ++J)
            cs.interpolate_row(hs.data(), J, [&](std::int64_t c, std::int64_t, double v) {
                // A seeping terrain cell is where the table meets the surface.
                h.data()[c] = cs.seeping[c] ? cs.surface[c] : std::min(v, cs.surface[c]);
            });
        return h;
    }
    RasterD h(m->grid);
    for (std::int64_t c = 0; c < m->grid.size(); ++c) h.data()[c] = m->head_of(c, m->y.data());
    return h;
}

double Groundwater::storage_m3() const {
    return compensated_sum(m->nvar(), [&](std::int64_t v) {
        return m->sy * (m->y[v] - m->base[m->cell_of_var[v]]) * m->area;
    });
}

long Groundwater::steps_taken() const {
    return m->steps;
}

GroundwaterSolver Groundwater::solver() const {
    return m->solver();
}

void Groundwater::save_state(ArchiveWriter& a) const {
    a.put_vector(m->y);
    a.put(m->t_now);
    a.put(m->last_step);
    a.put(m->steps);
    if (m_coarse) a.put_vector(m_coarse->seeping);
}

void Groundwater::load_state(ArchiveReader& a) {
    auto y = a.get_vector<double>();
    if (static_cast<std::int64_t>(y.size()) != m->nvar() + 1)
        throw CheckpointError("groundwater checkpoint: " + std::to_string(y.size()) +
                              " values for " + std::to_string(m->nvar() + 1) +
                              " unknowns (another terrain or aquifer_cell_factor?)");
    std::copy(y.begin(), y.end(), m->y.begin()); // the CVODE vector wraps this buffer
    m->t_now = a.get<double>();
    m->last_step = a.get<double>();
    m->steps = a.get<long>();
    if (m_coarse) {
        auto seeping = a.get_vector<std::uint8_t>();
        if (seeping.size() != m_coarse->seeping.size())
            throw CheckpointError("groundwater checkpoint: " + std::to_string(seeping.size()) +
                                  " seepage flags for " + std::to_string(m_coarse->seeping.size()) +
                                  " terrain cells");
        m_coarse->seeping = std::move(seeping);
    }
    m->heads_changed();
}

} // namespace ecoterra::hydro
