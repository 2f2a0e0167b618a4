#pragma once
// Conjugate gradients preconditioned by an aggregation multigrid V-cycle, for the symmetric
// positive definite systems of cell-centred diffusion on a raster (the implicit groundwater step):
//   (A x)_i = s_i x_i + sum over the faces f of cell i of c_f (x_i - x_n(f))
// s_i >= 0 is a cell's own term (storage S_y A / dt, conductance to a fixed head), c_f >= 0 a face
// conductance (m2/s). Inactive cells are identity rows without faces.
//
// Coarse levels aggregate 2 x 2 cells (Braess 1995, "Towards algebraic multigrid for elliptic
// problems of second order"; Notay 2010 for aggregation as a Krylov preconditioner). A coarse
// cell's own term is the sum of its cells' (the storage of the aggregate); a coarse face's
// conductance is the mean of the fine faces that cross it, which is the rediscretised operator on
// cells twice the size (the plain Galerkin sum would be twice too stiff and slow the cycle).
// Prolongation is piecewise constant and restriction its transpose (the sum), so the cycle is
// symmetric: red-black Gauss-Seidel before the coarse correction, black-red after, a fixed number
// of symmetric sweeps on the coarsest level. That makes the V-cycle a valid preconditioner for
// conjugate gradients (Saad 2003, "Iterative methods for sparse linear systems", §9.2 and §13).
//
// Everything is deterministic: the red-black sweeps update independent cells, and the dot products
// add fixed blocks in a fixed order (blocked_sums), so the result does not depend on the thread
// count.
#include <cstdint>
#include <vector>

namespace ecoterra::hydro {

/// The grid passes of the solver do a few nanoseconds of work per cell, so a parallel region pays
/// for waking the threads only on large grids: from 16 x parallel_min_items() cells (262,144 by
/// default). Measured with bench_groundwater (2 cores, passive waits): at 128^2 one thread is 2.4 x
/// faster than two, at 256^2 1.4 x; at 512^2 two are 1.1 x and at 1024^2 1.5 x faster than one.
inline constexpr std::int64_t kGridParallelFactor = 16;
bool parallel_grid(std::int64_t cells);

/// f(k) for k in [0, n), in parallel on large grids (parallel_grid); each k's result its own.
template <class F>
void for_grid_cells(std::int64_t n, F&& f) {
#pragma omp parallel for schedule(static) if (parallel_grid(n))
    for (std::int64_t k = 0; k < n; ++k) f(k);
}

struct CellOperator {
    int nx = 0, ny = 0;
    std::vector<double> s;  ///< own term per cell, >= 0 (m2/s)
    std::vector<double> cx; ///< conductance between (i, j) and (i + 1, j) at j nx + i (m2/s)
    std::vector<double> cy; ///< conductance between (i, j) and (i, j + 1) at j nx + i (m2/s)
    std::vector<std::uint8_t> active; ///< 0: identity row, no faces

    CellOperator() = default;
    CellOperator(int nx_, int ny_);
    std::int64_t size() const { return static_cast<std::int64_t>(nx) * ny; }
    /// y = A x.
    void apply(const double* x, double* y) const;
    /// (A x)_k of the active cell k at column i, row j.
    double row(std::int64_t k, int i, int j, const double* x) const {
        double v = s[k] * x[k];
        if (i > 0) v += cx[k - 1] * (x[k] - x[k - 1]);
        if (i + 1 < nx) v += cx[k] * (x[k] - x[k + 1]);
        if (j > 0) v += cy[k - nx] * (x[k] - x[k - nx]);
        if (j + 1 < ny) v += cy[k] * (x[k] - x[k + nx]);
        return v;
    }
    /// The diagonal s_i + sum c_f (1 for inactive cells).
    std::vector<double> diagonal() const;
    void diagonal_into(std::vector<double>& d) const;
};

struct SolveReport {
    int iterations = 0;         ///< conjugate-gradient iterations
    double residual_scaled = 0; ///< root mean square of r_i / s_i at the end (units of x)
    bool converged = false;
};

class MultigridSolver {
public:
    MultigridSolver() = default;
    /// Builds the hierarchy for `fine`; throws InputError if a term is negative or not finite.
    explicit MultigridSolver(CellOperator fine);
    /// The same for a new operator, reusing the arrays of the last one when the grid is the same
    /// (an implicit time step calls it at every stage).
    void set_operator(CellOperator fine);
    /// Gives the fine operator's arrays back for the next set_operator to fill without allocating.
    CellOperator take_operator() { return std::move(m_levels.front().op); }
    /// Solves A x = b starting from x (a warm start), until the root mean square of r_i / s_i
    /// (r_i / diagonal where s_i = 0), the change of x_i the residual stands for, is at most
    /// `tolerance`, or max_iterations pass.
    SolveReport solve(const std::vector<double>& b, std::vector<double>& x, double tolerance,
                      int max_iterations) const;
    int levels() const { return static_cast<int>(m_levels.size()); }
    const CellOperator& fine() const { return m_levels.front().op; }

private:
    struct Level {
        CellOperator op;
        std::vector<double> inv_diag;
        mutable std::vector<double> b, x; ///< work arrays of the V-cycle (no b on level 0)
    };
    std::vector<Level> m_levels;
    std::vector<double> m_weight; ///< 1 / s_i (or 1 / diagonal) for the stopping test
    mutable std::vector<double> m_r, m_z, m_p, m_q; ///< conjugate-gradient work arrays
    /// One V-cycle from level l down with right-hand side b, leaving the result in level l's x.
    void vcycle(std::size_t l, const double* b) const;
};

} // namespace ecoterra::hydro
