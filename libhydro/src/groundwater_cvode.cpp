// The reference groundwater integrator: CVODE BDF, Newton, analytic sparse Jacobian, KLU.
#include "ecoterra/error.hpp"
#include "groundwater_impl.hpp"

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_klu.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace ecoterra::hydro {

namespace {

constexpr double kRelTol = 1e-5;
constexpr double kHeadAbsTol = 1e-5;    ///< m
constexpr double kOutflowAbsTol = 1e-6; ///< m3
constexpr long kMaxSteps = 100000;
constexpr int kKluOrderingAmd = 0; ///< SUNLinSol_KLUSetOrdering: 0 AMD, 1 COLAMD, 2 natural

void check(int flag, const char* call) {
    if (flag < 0) {
        std::ostringstream s;
        s << "groundwater: SUNDIALS " << call << " failed with flag " << flag;
        throw Error(s.str());
    }
}
template <class P>
P* check_ptr(P* p, const char* call) {
    if (!p) throw Error(std::string("groundwater: SUNDIALS ") + call + " returned no object");
    return p;
}

// RAII owners for the SUNDIALS objects.
struct ContextOwner {
    SUNContext ctx = nullptr;
    ContextOwner() { check(SUNContext_Create(nullptr, &ctx), "SUNContext_Create"); }
    ~ContextOwner() {
        if (ctx) SUNContext_Free(&ctx);
    }
};
struct VectorOwner {
    N_Vector v = nullptr;
    ~VectorOwner() {
        if (v) N_VDestroy(v);
    }
};
struct MatrixOwner {
    SUNMatrix m = nullptr;
    ~MatrixOwner() {
        if (m) SUNMatDestroy(m);
    }
};
struct SolverOwner {
    SUNLinearSolver s = nullptr;
    ~SolverOwner() {
        if (s) SUNLinSolFree(s);
    }
};
struct CvodeOwner {
    void* mem = nullptr;
    ~CvodeOwner() {
        if (mem) CVodeFree(&mem);
    }
};

struct CvodeGroundwater final : Groundwater::Impl {
    // Sparse pattern (CSR) of the Jacobian, built once.
    std::vector<sunindextype> rowptr, colidx;
    // SUNDIALS objects (declaration order = reverse destruction order). yv wraps Impl::y.
    ContextOwner ctx;
    VectorOwner yv, abstol;
    MatrixOwner jac;
    SolverOwner ls;
    CvodeOwner cvode;

    CvodeGroundwater(const RasterD& surf, const RasterD& b, const RasterD& h0, const RasterF& ks,
                     double specific_yield, std::array<GroundwaterBoundary, 4> sides)
        : Impl(surf, b, h0, ks, specific_yield, sides) {
        build_pattern();
        build_solver();
    }
    GroundwaterSolver solver() const override { return GroundwaterSolver::cvode; }

    static int rhs(realtype, N_Vector yv, N_Vector ydot, void* user) {
        const auto* self = static_cast<const CvodeGroundwater*>(user);
        const double* h = N_VGetArrayPointer(yv);
        double* d = N_VGetArrayPointer(ydot);
        const std::int64_t n = self->nvar();
        double out = 0;
        for (std::int64_t v = 0; v < n; ++v) {
            const std::int64_t c = self->cell_of_var[v];
            double acc = self->rate[v];
            self->neighbours(c, [&](std::int64_t q) {
                const double hq = self->head_of(q, h);
                const double flow = self->face(c, q, h[v], hq).first * (hq - h[v]);
                acc += flow;
                if (self->var_of_cell[q] < 0) out -= flow;
            });
            d[v] = acc / (self->sy * self->area);
        }
        d[n] = out;
        return 0;
    }

    static int jacobian(realtype, N_Vector yv, N_Vector, SUNMatrix J, void* user, N_Vector,
                        N_Vector, N_Vector) {
        const auto* self = static_cast<const CvodeGroundwater*>(user);
        const double* h = N_VGetArrayPointer(yv);
        sunindextype* rp = SUNSparseMatrix_IndexPointers(J);
        sunindextype* ci = SUNSparseMatrix_IndexValues(J);
        double* val = SUNSparseMatrix_Data(J);
        std::copy(self->rowptr.begin(), self->rowptr.end(), rp);
        std::copy(self->colidx.begin(), self->colidx.end(), ci);
        std::fill(val, val + self->colidx.size(), 0.0);
        const std::int64_t n = self->nvar();
        const double s = 1.0 / (self->sy * self->area);
        auto add = [&](std::int64_t row, std::int64_t col, double x) {
            for (sunindextype p = self->rowptr[row]; p < self->rowptr[row + 1]; ++p)
                if (self->colidx[p] == col) {
                    val[p] += x;
                    return;
                }
        };
        for (std::int64_t v = 0; v < n; ++v) {
            const std::int64_t c = self->cell_of_var[v];
            self->neighbours(c, [&](std::int64_t q) {
                const double hq = self->head_of(q, h);
                const auto [t, dt] = self->face(c, q, h[v], hq);
                const double dq_dhv = -t + dt * (hq - h[v]);
                add(v, v, s * dq_dhv);
                const std::int32_t w = self->var_of_cell[q];
                if (w >= 0)
                    add(v, w, s * (t + dt * (hq - h[v])));
                else
                    add(n, v, -dq_dhv); // outflow row
            });
        }
        return 0;
    }

    /// CSR pattern: each variable row has itself and its evolving neighbours, sorted; the last
    /// row (outflow) has the variables next to fixed cells.
    void build_pattern() {
        const std::int64_t n = nvar();
        rowptr.assign(static_cast<std::size_t>(n + 2), 0);
        std::vector<sunindextype> out_cols;
        for (std::int64_t v = 0; v < n; ++v) {
            std::vector<sunindextype> cols = {static_cast<sunindextype>(v)};
            bool touches_fixed = false;
            neighbours(cell_of_var[v], [&](std::int64_t q) {
                if (var_of_cell[q] >= 0)
                    cols.push_back(var_of_cell[q]);
                else
                    touches_fixed = true;
            });
            std::sort(cols.begin(), cols.end());
            colidx.insert(colidx.end(), cols.begin(), cols.end());
            rowptr[v + 1] = static_cast<sunindextype>(colidx.size());
            if (touches_fixed) out_cols.push_back(static_cast<sunindextype>(v));
        }
        colidx.insert(colidx.end(), out_cols.begin(), out_cols.end());
        // An explicit (zero) diagonal: without it SUNMatScaleAddI rebuilds the matrix each call.
        colidx.push_back(static_cast<sunindextype>(n));
        rowptr[n + 1] = static_cast<sunindextype>(colidx.size());
    }

    void build_solver() {
        const std::int64_t n = nvar();
        yv.v = check_ptr(N_VMake_Serial(n + 1, y.data(), ctx.ctx), "N_VMake_Serial");
        abstol.v = check_ptr(N_VNew_Serial(n + 1, ctx.ctx), "N_VNew_Serial");
        double* at = N_VGetArrayPointer(abstol.v);
        std::fill(at, at + n, kHeadAbsTol);
        at[n] = kOutflowAbsTol;
        jac.m = check_ptr(SUNSparseMatrix(n + 1, n + 1, static_cast<sunindextype>(colidx.size()),
                                          CSR_MAT, ctx.ctx),
                          "SUNSparseMatrix");
        ls.s = check_ptr(SUNLinSol_KLU(yv.v, jac.m, ctx.ctx), "SUNLinSol_KLU");
        // The five-point pattern is (nearly) symmetric: AMD orders it with less fill than COLAMD.
        check(SUNLinSol_KLUSetOrdering(ls.s, kKluOrderingAmd), "SUNLinSol_KLUSetOrdering");
        cvode.mem = check_ptr(CVodeCreate(CV_BDF, ctx.ctx), "CVodeCreate");
        check(CVodeInit(cvode.mem, rhs, 0.0, yv.v), "CVodeInit");
        check(CVodeSVtolerances(cvode.mem, kRelTol, abstol.v), "CVodeSVtolerances");
        check(CVodeSetUserData(cvode.mem, this), "CVodeSetUserData");
        check(CVodeSetLinearSolver(cvode.mem, ls.s, jac.m), "CVodeSetLinearSolver");
        check(CVodeSetJacFn(cvode.mem, jacobian), "CVodeSetJacFn");
        check(CVodeSetMaxNumSteps(cvode.mem, kMaxSteps), "CVodeSetMaxNumSteps");
    }

    void advance(double dt_s) override {
        // The recharge changes at step boundaries. A multistep history that straddles the change
        // would integrate the budget invariant (storage + outflow = recharge) only approximately,
        // so the integrator restarts at every boundary, seeded with the last step size to skip
        // the slow start-up.
        check(CVodeReInit(cvode.mem, t_now, yv.v), "CVodeReInit");
        if (last_step > 0)
            check(CVodeSetInitStep(cvode.mem, std::min(last_step, dt_s)), "CVodeSetInitStep");
        const double t_end = t_now + dt_s;
        check(CVodeSetStopTime(cvode.mem, t_end), "CVodeSetStopTime");
        realtype t = t_now;
        const int flag = CVode(cvode.mem, t_end, yv.v, &t, CV_NORMAL);
        if (flag < 0) fail(flag, t, dt_s);
        t_now = t_end;
        long nst = 0;
        CVodeGetNumSteps(cvode.mem, &nst);
        steps += nst;
        realtype last = 0;
        if (CVodeGetLastStep(cvode.mem, &last) >= 0) last_step = last;
    }

    /// Names the cell with the largest weighted local error.
    [[noreturn]] void fail(int flag, double t, double dt_s) {
        VectorOwner err, wts;
        err.v = N_VClone(yv.v);
        wts.v = N_VClone(yv.v);
        std::int64_t worst = -1;
        if (CVodeGetEstLocalErrors(cvode.mem, err.v) >= 0 &&
            CVodeGetErrWeights(cvode.mem, wts.v) >= 0) {
            const double* e = N_VGetArrayPointer(err.v);
            const double* w = N_VGetArrayPointer(wts.v);
            double best = -1;
            for (std::int64_t v = 0; v < nvar(); ++v)
                if (std::abs(e[v] * w[v]) > best) best = std::abs(e[v] * w[v]), worst = v;
        }
        std::ostringstream s;
        s << "groundwater: CVODE failed with flag " << flag << " at t = " << t << " s of a " << dt_s
          << " s step";
        if (worst >= 0) {
            const std::int64_t c = cell_of_var[worst];
            s << ", largest error at cell (" << c % grid.nx << ", " << c / grid.nx << ")";
        }
        throw Error(s.str());
    }
};

} // namespace

std::unique_ptr<Groundwater::Impl>
make_cvode_groundwater(const RasterD& surf, const RasterD& b, const RasterD& h0, const RasterF& ks,
                       double sy, std::array<GroundwaterBoundary, 4> sides) {
    return std::make_unique<CvodeGroundwater>(surf, b, h0, ks, sy, sides);
}

} // namespace ecoterra::hydro
