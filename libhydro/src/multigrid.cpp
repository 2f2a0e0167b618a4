#include "ecoterra/hydro/multigrid.hpp"

#include "ecoterra/error.hpp"
#include "ecoterra/parallel.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace ecoterra::hydro {

bool parallel_grid(std::int64_t cells) {
    return cells >= kGridParallelFactor * parallel_min_items();
}

namespace {

constexpr std::int64_t kCoarsestCells = 16; ///< stop aggregating at this many cells
constexpr int kCoarsestSweeps = 24;         ///< symmetric sweep pairs on the coarsest level

/// One red-black half sweep: cells with (i + j) % 2 == colour take their Gauss-Seidel value.
void sweep(const CellOperator& a, const std::vector<double>& inv_diag, const double* b, double* x,
           int colour) {
    const int nx = a.nx, ny = a.ny;
#pragma omp parallel for schedule(static) if (parallel_grid(a.size()))
    for (int j = 0; j < ny; ++j) {
        const std::int64_t row = static_cast<std::int64_t>(j) * nx;
        for (int i = (colour + j) & 1; i < nx; i += 2) {
            const std::int64_t k = row + i;
            double sum = b[k];
            if (i > 0) sum += a.cx[k - 1] * x[k - 1];
            if (i + 1 < nx) sum += a.cx[k] * x[k + 1];
            if (j > 0) sum += a.cy[k - nx] * x[k - nx];
            if (j + 1 < ny) sum += a.cy[k] * x[k + nx];
            x[k] = a.active[k] ? sum * inv_diag[k] : b[k];
        }
    }
}

/// The first red half sweep from x = 0, with the same bits as sweep(.., 0) after a fill with 0:
/// the red cells take b_i / d_i (b_i where inactive), the black ones 0.
void sweep_from_zero(const CellOperator& a, const std::vector<double>& inv_diag, const double* b,
                     double* x) {
    const int nx = a.nx, ny = a.ny;
#pragma omp parallel for schedule(static) if (parallel_grid(a.size()))
    for (int j = 0; j < ny; ++j) {
        const std::int64_t row = static_cast<std::int64_t>(j) * nx;
        for (int i = 0; i < nx; ++i) {
            const std::int64_t k = row + i;
            // A neighbour's 0 adds c * 0 = +0 to the sum, which leaves b_i as it is (a -0 b_i
            // becomes +0 there: the same value).
            const double sum = nx > 1 || ny > 1 ? b[k] + 0.0 : b[k];
            x[k] = ((i + j) & 1) == 0 ? (a.active[k] ? sum * inv_diag[k] : b[k]) : 0.0;
        }
    }
}

/// The residual b - A x of a fine level restricted to the coarse one: each coarse cell the sum
/// over its active fine cells, each coarse row gathering its two fine rows in a fixed order (the
/// same bits on any threads, and as computing the residual first and summing it after).
void restrict_residual(const CellOperator& a, const double* b, const double* x,
                       const CellOperator& c, std::vector<double>& cb) {
    const int nx = a.nx, ny = a.ny, cnx = c.nx;
#pragma omp parallel for schedule(static) if (parallel_grid(a.size()))
    for (int jc = 0; jc < c.ny; ++jc) {
        double* out = cb.data() + static_cast<std::int64_t>(jc) * cnx;
        std::fill(out, out + cnx, 0.0);
        for (int j = 2 * jc; j < std::min(ny, 2 * jc + 2); ++j)
            for (int i = 0; i < nx; ++i) {
                const std::int64_t k = static_cast<std::int64_t>(j) * nx + i;
                if (!a.active[k]) continue;
                out[i / 2] += b[k] - a.row(k, i, j, x);
            }
    }
}

/// The operator on cells of twice the side: own terms summed, crossing faces averaged. Reuses
/// c's arrays when it has the size already.
void coarsen(const CellOperator& f, CellOperator& c) {
    if (c.nx != (f.nx + 1) / 2 || c.ny != (f.ny + 1) / 2)
        c = CellOperator((f.nx + 1) / 2, (f.ny + 1) / 2);
    std::fill(c.s.begin(), c.s.end(), 0.0);
    std::fill(c.cx.begin(), c.cx.end(), 0.0);
    std::fill(c.cy.begin(), c.cy.end(), 0.0);
    std::fill(c.active.begin(), c.active.end(), std::uint8_t{0});
#pragma omp parallel for schedule(static) if (parallel_grid(f.size()))
    for (int jc = 0; jc < c.ny; ++jc)
        for (int j = 2 * jc; j < std::min(f.ny, 2 * jc + 2); ++j)
            for (int i = 0; i < f.nx; ++i) {
                const std::int64_t k = static_cast<std::int64_t>(j) * f.nx + i;
                const std::int64_t kc = static_cast<std::int64_t>(jc) * c.nx + i / 2;
                if (!f.active[k]) continue;
                c.active[kc] = 1;
                c.s[kc] += f.s[k];
                // A fine face on the aggregate's east (north) side crosses a coarse face.
                if (i % 2 == 1 && i + 1 < f.nx) c.cx[kc] += 0.5 * f.cx[k];
                if (j % 2 == 1 && j + 1 < f.ny) c.cy[kc] += 0.5 * f.cy[k];
            }
}

} // namespace

CellOperator::CellOperator(int nx_, int ny_)
    : nx(nx_), ny(ny_), s(static_cast<std::size_t>(size()), 0.0),
      cx(static_cast<std::size_t>(size()), 0.0), cy(static_cast<std::size_t>(size()), 0.0),
      active(static_cast<std::size_t>(size()), 0) {}

void CellOperator::apply(const double* x, double* y) const {
#pragma omp parallel for schedule(static) if (parallel_grid(size()))
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            const std::int64_t k = static_cast<std::int64_t>(j) * nx + i;
            y[k] = active[k] ? row(k, i, j, x) : x[k];
        }
}

std::vector<double> CellOperator::diagonal() const {
    std::vector<double> d(static_cast<std::size_t>(size()), 1.0);
    diagonal_into(d);
    return d;
}

void CellOperator::diagonal_into(std::vector<double>& d) const {
    d.resize(static_cast<std::size_t>(size()));
#pragma omp parallel for schedule(static) if (parallel_grid(size()))
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            const std::int64_t k = static_cast<std::int64_t>(j) * nx + i;
            if (!active[k]) {
                d[k] = 1.0;
                continue;
            }
            double v = s[k];
            if (i > 0) v += cx[k - 1];
            if (i + 1 < nx) v += cx[k];
            if (j > 0) v += cy[k - nx];
            if (j + 1 < ny) v += cy[k];
            d[k] = v;
        }
}

MultigridSolver::MultigridSolver(CellOperator fine) {
    set_operator(std::move(fine));
}

void MultigridSolver::set_operator(CellOperator fine) {
    const std::int64_t n = fine.size();
    if (fine.nx < 1 || fine.ny < 1 || static_cast<std::int64_t>(fine.s.size()) != n ||
        static_cast<std::int64_t>(fine.cx.size()) != n ||
        static_cast<std::int64_t>(fine.cy.size()) != n ||
        static_cast<std::int64_t>(fine.active.size()) != n)
        throw InputError("multigrid: the operator's arrays do not match its " +
                         std::to_string(fine.nx) + " x " + std::to_string(fine.ny) + " grid");
    std::int64_t bad = n; // the first cell with a negative or non-finite term
#pragma omp parallel for schedule(static) reduction(min : bad) if (parallel_grid(n))
    for (std::int64_t k = 0; k < n; ++k) {
        if (!(fine.s[k] >= 0 && fine.cx[k] >= 0 && fine.cy[k] >= 0) ||
            !std::isfinite(fine.s[k] + fine.cx[k] + fine.cy[k]))
            bad = std::min(bad, k);
        // Faces that touch an inactive cell carry nothing.
        const int i = static_cast<int>(k % fine.nx), j = static_cast<int>(k / fine.nx);
        if (!fine.active[k] || (i + 1 < fine.nx && !fine.active[k + 1])) fine.cx[k] = 0;
        if (!fine.active[k] || (j + 1 < fine.ny && !fine.active[k + fine.nx])) fine.cy[k] = 0;
    }
    if (bad < n)
        throw InputError("multigrid: a negative or non-finite term at cell " + std::to_string(bad));
    if (m_levels.empty() || m_levels.front().op.nx != fine.nx || m_levels.front().op.ny != fine.ny)
        m_levels.assign(1, Level{});
    m_levels.front().op = std::move(fine);
    for (std::size_t l = 0; m_levels[l].op.size() > kCoarsestCells; ++l) {
        if (l + 1 == m_levels.size()) m_levels.emplace_back();
        coarsen(m_levels[l].op, m_levels[l + 1].op);
    }
    for (Level& l : m_levels) {
        l.op.diagonal_into(l.inv_diag);
        const auto m = static_cast<std::size_t>(l.op.size());
        // Level 0's right-hand side is the solve's residual, read where it is.
        if (&l != &m_levels.front()) l.b.resize(m);
        l.x.resize(m);
    }
    const CellOperator& a = m_levels.front().op;
    std::vector<double>& d = m_levels.front().inv_diag; // the diagonal until inverted here
    m_weight.resize(static_cast<std::size_t>(n));
    std::int64_t singular = n;
#pragma omp parallel for schedule(static) reduction(min : singular) if (parallel_grid(n))
    for (std::int64_t k = 0; k < n; ++k) {
        if (!(d[k] > 0)) singular = std::min(singular, k);
        m_weight[k] = a.active[k] ? 1.0 / (a.s[k] > 0 ? a.s[k] : d[k]) : 0.0;
        d[k] = 1.0 / d[k];
    }
    if (singular < n)
        throw InputError("multigrid: cell " + std::to_string(singular) +
                         " has no own term and no faces (a singular row)");
    for (std::size_t i = 1; i < m_levels.size(); ++i) {
        Level& l = m_levels[i];
        for_grid_cells(l.op.size(), [&](std::int64_t k) { l.inv_diag[k] = 1.0 / l.inv_diag[k]; });
    }
    for (auto* v : {&m_r, &m_z, &m_p, &m_q}) v->resize(static_cast<std::size_t>(n));
}

void MultigridSolver::vcycle(std::size_t l, const double* b) const {
    const Level& L = m_levels[l];
    sweep_from_zero(L.op, L.inv_diag, b, L.x.data());
    if (l + 1 == m_levels.size()) {
        sweep(L.op, L.inv_diag, b, L.x.data(), 1);
        for (int k = 1; k < kCoarsestSweeps; ++k) {
            sweep(L.op, L.inv_diag, b, L.x.data(), 0);
            sweep(L.op, L.inv_diag, b, L.x.data(), 1);
        }
        for (int k = 0; k < kCoarsestSweeps; ++k) {
            sweep(L.op, L.inv_diag, b, L.x.data(), 1);
            sweep(L.op, L.inv_diag, b, L.x.data(), 0);
        }
        return;
    }
    sweep(L.op, L.inv_diag, b, L.x.data(), 1);
    const Level& C = m_levels[l + 1];
    restrict_residual(L.op, b, L.x.data(), C.op, C.b);
    vcycle(l + 1, C.b.data());
    const int nx = L.op.nx, ny = L.op.ny, cnx = C.op.nx;
#pragma omp parallel for schedule(static) if (parallel_grid(L.op.size()))
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            const std::int64_t k = static_cast<std::int64_t>(j) * nx + i;
            if (L.op.active[k]) L.x[k] += C.x[static_cast<std::int64_t>(j / 2) * cnx + i / 2];
        }
    sweep(L.op, L.inv_diag, b, L.x.data(), 1);
    sweep(L.op, L.inv_diag, b, L.x.data(), 0);
}

SolveReport MultigridSolver::solve(const std::vector<double>& b, std::vector<double>& x,
                                   double tolerance, int max_iterations) const {
    const CellOperator& a = m_levels.front().op;
    const std::int64_t n = a.size();
    if (static_cast<std::int64_t>(b.size()) != n || static_cast<std::int64_t>(x.size()) != n)
        throw InputError("multigrid: the right-hand side or the start does not match the grid");
    std::vector<double>&r = m_r, &z = m_z, &p = m_p, &q = m_q;
    a.apply(x.data(), q.data());
    for_grid_cells(n, [&](std::int64_t k) { r[k] = a.active[k] ? b[k] - q[k] : 0.0; });
    const double active_cells = std::max<double>(
        1.0, blocked_sums<1>(n, [&](std::int64_t k, auto& s) { s[0] += a.active[k]; })[0]);
    auto scaled = [&](double squares) { return std::sqrt(squares / active_cells); };
    // Each pass below does in one sweep over the cells what took two or three (the operator and
    // a dot product, the update and the residual's norm, the preconditioned residual and its dot
    // product), with the same arithmetic in the same order: the same bits as separate passes.
    const double* w = m_weight.data();
    const Level& L0 = m_levels.front();
    auto precondition_dot = [&] { // z = M r, returns r . z
        vcycle(0, r.data());
        return blocked_range_sums<1>(n, [&](std::int64_t b0, std::int64_t e0, auto& s) {
            for (std::int64_t k = b0; k < e0; ++k) {
                z[k] = a.active[k] ? L0.x[k] : 0.0;
                s[0] += r[k] * z[k];
            }
        })[0];
    };
    SolveReport rep;
    rep.residual_scaled = scaled(blocked_sums<1>(n, [&](std::int64_t k, auto& s) {
        const double e = r[k] * w[k];
        s[0] += e * e;
    })[0]);
    if (rep.residual_scaled <= tolerance) {
        rep.converged = true;
        return rep;
    }
    double rz = precondition_dot();
    std::copy(z.begin(), z.end(), p.begin());
    const int nx = a.nx;
    while (rep.iterations < max_iterations) {
        // q = A p on the active cells (0 elsewhere), and p . q.
        const double pq = blocked_range_sums<1>(n, [&](std::int64_t b0, std::int64_t e0, auto& s) {
            int i = static_cast<int>(b0 % nx), j = static_cast<int>(b0 / nx);
            for (std::int64_t k = b0; k < e0; ++k) {
                q[k] = a.active[k] ? a.row(k, i, j, p.data()) : 0.0;
                s[0] += p[k] * q[k];
                if (++i == nx) i = 0, ++j;
            }
        })[0];
        const double alpha = rz / pq;
        rep.residual_scaled =
            scaled(blocked_range_sums<1>(n, [&](std::int64_t b0, std::int64_t e0, auto& s) {
                for (std::int64_t k = b0; k < e0; ++k) {
                    x[k] += alpha * p[k];
                    r[k] -= alpha * q[k];
                    const double e = r[k] * w[k];
                    s[0] += e * e;
                }
            })[0]);
        ++rep.iterations;
        if (rep.residual_scaled <= tolerance) {
            rep.converged = true;
            break;
        }
        const double rz_new = precondition_dot();
        const double beta = rz_new / rz;
        rz = rz_new;
        for_grid_cells(n, [&](std::int64_t k) { p[k] = z[k] + beta * p[k]; });
    }
    return rep;
}

} // namespace ecoterra::hydro
