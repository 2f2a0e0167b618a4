// The scalable groundwater integrator: TR-BDF2 steps (Bank et al. 1985, IEEE Trans. CAD 4:436;
// Hosea & Shampine 1996, Appl. Numer. Math. 20:21), second order and L-stable, each stage a
// symmetric positive definite system solved by multigrid-preconditioned conjugate gradients, and
// each stage's heads then advanced by the face fluxes of its solved heads.
//
// With M = S_y A the storage of a cell, T_f the face transmissivities (frozen over a stage: at the
// step's start for the first stage, at its end for the second), L(h)_i = sum_f T_f (h_n - h_i) and
// F(h) = R + L(h) (R the recharge rate, m3/s; heads on fixed cells do not change), a step of dt is
//   trapezoidal rule to t + g dt:  M (h_g - h0) = (g dt / 2) (F(h0) + F(h_g))
//   BDF2 to t + dt:               h1 = h_g + b (h_g - h0) + c dt F(h1) / M
// with g = 2 - sqrt 2, b = (1 - g)^2 / (g (2 - g)), c = (1 - g) / (2 - g). For the change d of a
// stage, (2 M / (g dt)) d - L(d) = 2 F(h0) and (M / (c dt)) d - L(d) = F(h_g) + b M (h_g - h0) /
// (c dt). After each solve the stage's update is recomputed from the fluxes of the solved heads,
// so every interior flux leaves one cell exactly as it enters the other and storage change plus
// fixed-head outflow equals the recharge to rounding, whatever the solver's tolerance: the
// recharge weights (1 + b) g + c = 1, and the outflow is (1 + b) (g dt / 2) (out(h0) + out(h_g)) +
// c dt out(h1).
#include "ecoterra/error.hpp"
#include "ecoterra/hydro/multigrid.hpp"
#include "ecoterra/parallel.hpp"
#include "groundwater_impl.hpp"

#include <cmath>
#include <sstream>
#include <string>
#include <utility>

namespace ecoterra::hydro {

namespace {

constexpr int kMaxIterations = 500;
const double kGamma = 2.0 - std::sqrt(2.0);
const double kB = (1 - kGamma) * (1 - kGamma) / (kGamma * (2 - kGamma));
const double kC = (1 - kGamma) / (2 - kGamma);

struct ImplicitGroundwater final : Groundwater::Impl {
    std::vector<double> h0, hg,
        trial;                    ///< heads of every cell at the step's start, the stage, a solve
    std::vector<double> flux, f0; ///< R + L(h) per cell, now and at the step's start, m3/s
    std::vector<double> d;        ///< a stage's change of the heads, m
    std::vector<double> fx, fy;   ///< transmissivity of the east and north faces, m2/s
    std::vector<double> rhs;
    CellOperator op;    ///< a stage's operator (its arrays reused from stage to stage)
    MultigridSolver mg; ///< its hierarchy (likewise)
    int substeps = 1;   ///< TR-BDF2 steps per call
    double tolerance;   ///< of a stage's solve: the root mean square change of head, m

    ImplicitGroundwater(const RasterD& surf, const RasterD& b, const RasterD& h, const RasterF& ks,
                        double specific_yield, std::array<GroundwaterBoundary, 4> sides,
                        int substeps_, double tolerance_)
        : Impl(surf, b, h, ks, specific_yield, sides), substeps(substeps_), tolerance(tolerance_) {
        if (substeps < 1)
            throw InputError("groundwater: the implicit solver needs at least 1 step per call, "
                             "got " +
                             std::to_string(substeps));
        if (!(tolerance > 0 && tolerance < 1))
            throw InputError("groundwater: the implicit solver's head tolerance must be in (0, 1) "
                             "m, got " +
                             format_number(tolerance));
        const auto n = static_cast<std::size_t>(grid.size());
        for (auto* v : {&h0, &hg, &trial, &flux, &f0, &d, &fx, &fy, &rhs}) v->assign(n, 0.0);
    }
    GroundwaterSolver solver() const override { return GroundwaterSolver::implicit; }

    bool evolving(std::int64_t c) const { return var_of_cell[c] >= 0; }

    /// f(c) for every cell, in parallel on large grids (each cell's result its own).
    template <class F>
    void for_cells(F&& f) const {
        for_grid_cells(grid.size(), f);
    }

    template <class F>
    void for_rows(F&& f) const {
#pragma omp parallel for schedule(static) if (parallel_grid(grid.size()))
        for (int j = 0; j < grid.ny; ++j) f(j);
    }

    /// Face transmissivities at heads h.
    void faces_at(const std::vector<double>& h) {
        const int nx = grid.nx, ny = grid.ny;
        for_rows([&](int j) {
            for (int i = 0; i < nx; ++i) {
                const std::int64_t c = static_cast<std::int64_t>(j) * nx + i;
                fx[c] = i + 1 < nx ? face(c, c + 1, h[c], h[c + 1]).first : 0.0;
                fy[c] = j + 1 < ny ? face(c, c + nx, h[c], h[c + nx]).first : 0.0;
            }
        });
    }

    /// Calls f(q, T) for each face of cell c (at column i, row j).
    template <class F>
    void faces_of(std::int64_t c, int i, int j, F&& f) const {
        if (i + 1 < grid.nx) f(c + 1, fx[c]);
        if (j + 1 < grid.ny) f(c + grid.nx, fy[c]);
        if (i > 0) f(c - 1, fx[c - 1]);
        if (j > 0) f(c - grid.nx, fy[c - grid.nx]);
    }

    /// flux = R + L(h) on the evolving cells; returns the flow into the fixed heads, m3/s.
    double fluxes(const std::vector<double>& h) {
        const int nx = grid.nx;
        std::vector<double> out_rows(static_cast<std::size_t>(grid.ny), 0.0);
        for_rows([&](int j) {
            double out = 0;
            for (int i = 0; i < nx; ++i) {
                const std::int64_t c = static_cast<std::int64_t>(j) * nx + i;
                if (!evolving(c)) continue;
                double in = rate[var_of_cell[c]];
                faces_of(c, i, j, [&](std::int64_t q, double t) {
                    const double f = t * (h[q] - h[c]);
                    in += f;
                    if (!evolving(q)) out -= f;
                });
                flux[c] = in;
            }
            out_rows[static_cast<std::size_t>(j)] = out;
        });
        double out = 0;
        for (double o : out_rows) out += o;
        return out;
    }

    /// The stage operator own x - L(x): faces between evolving cells couple, a face to a fixed
    /// head adds its transmissivity to the own term.
    void stage_operator(double own) {
        const int nx = grid.nx;
        if (op.nx != nx || op.ny != grid.ny) op = CellOperator(nx, grid.ny);
        for_rows([&](int j) {
            for (int i = 0; i < nx; ++i) {
                const std::int64_t c = static_cast<std::int64_t>(j) * nx + i;
                op.s[c] = op.cx[c] = op.cy[c] = 0;
                op.active[c] = 0;
                if (!evolving(c)) continue;
                op.active[c] = 1;
                double s = own;
                faces_of(c, i, j, [&](std::int64_t q, double t) {
                    if (!evolving(q)) s += t;
                });
                if (i + 1 < nx && evolving(c + 1)) op.cx[c] = fx[c];
                if (j + 1 < grid.ny && evolving(c + nx)) op.cy[c] = fy[c];
                op.s[c] = s;
            }
        });
    }

    /// Solves the stage for d, from d = 0, and leaves h + d in `trial`. (Starting from the last
    /// stage's change saves nothing measurable, as rain changes it from day to day, and would put
    /// solver history into the state a checkpoint must carry.)
    void solve_stage(double own, const std::vector<double>& h, double dt_s) {
        stage_operator(own);
        mg.set_operator(std::move(op));
        std::fill(d.begin(), d.end(), 0.0);
        const SolveReport rep = mg.solve(rhs, d, tolerance, kMaxIterations);
        op = mg.take_operator();
        steps += rep.iterations;
        if (!rep.converged) {
            std::ostringstream s;
            s << "groundwater: the implicit step did not converge in " << kMaxIterations
              << " iterations (the residual stands for " << rep.residual_scaled
              << " m of head at the end of a " << dt_s << " s step)";
            throw Error(s.str());
        }
        for_cells([&](std::int64_t c) { trial[c] = h[c] + (evolving(c) ? d[c] : 0); });
    }

    void advance(double dt_s) override {
        for (int q = 0; q < substeps; ++q) tr_bdf2(dt_s / substeps);
    }

    void tr_bdf2(double dt) {
        const double m = sy * area;
        for_cells([&](std::int64_t c) { h0[c] = head_of(c, y.data()); });
        // Trapezoidal stage.
        faces_at(h0);
        const double out0 = fluxes(h0);
        for_cells([&](std::int64_t c) { rhs[c] = evolving(c) ? 2 * flux[c] : 0.0; });
        // F(h0) moves to f0; fluxes() writes every evolving cell of `flux` anew, and no other
        // cell's entry is read.
        std::swap(f0, flux);
        solve_stage(2 * m / (kGamma * dt), h0, dt);
        const double outg = fluxes(trial);
        for_cells([&](std::int64_t c) {
            hg[c] = evolving(c) ? h0[c] + kGamma * dt / 2 * (f0[c] + flux[c]) / m : h0[c];
        });
        // BDF2 stage, with the transmissivities of the stage's heads.
        faces_at(hg);
        fluxes(hg);
        const double own = m / (kC * dt);
        for_cells([&](std::int64_t c) {
            rhs[c] = evolving(c) ? flux[c] + kB * own * (hg[c] - h0[c]) : 0.0;
        });
        solve_stage(own, hg, dt);
        const double out1 = fluxes(trial);
        const auto n = nvar();
#pragma omp parallel for schedule(static) if (parallel_grid(n))
        for (std::int64_t v = 0; v < n; ++v) {
            const std::int64_t c = cell_of_var[v];
            y[v] = hg[c] + kB * (hg[c] - h0[c]) + kC * dt * flux[c] / m;
        }
        y[static_cast<std::size_t>(nvar())] +=
            (1 + kB) * kGamma * dt / 2 * (out0 + outg) + kC * dt * out1;
        t_now += dt;
    }
};

} // namespace

std::unique_ptr<Groundwater::Impl>
make_implicit_groundwater(const RasterD& surf, const RasterD& b, const RasterD& h0,
                          const RasterF& ks, double sy, std::array<GroundwaterBoundary, 4> sides,
                          int substeps, double head_tolerance_m) {
    return std::make_unique<ImplicitGroundwater>(surf, b, h0, ks, sy, sides, substeps,
                                                 head_tolerance_m);
}

} // namespace ecoterra::hydro
