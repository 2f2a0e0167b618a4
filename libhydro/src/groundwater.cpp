#include "ecoterra/hydro/groundwater.hpp"

#include "ecoterra/error.hpp"

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

constexpr double kMinSaturatedThickness = 1e-3; ///< t_min, m
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

} // namespace

struct Groundwater::Impl {
    GridSpec grid;
    std::vector<double> surface, base, head_fixed, k;
    double sy = 0.2, area = 1.0;
    std::vector<std::int64_t> cell_of_var; ///< evolving cells
    std::vector<std::int32_t> var_of_cell; ///< -1 for fixed-head cells
    std::vector<double> rate;              ///< recharge per variable, m3/s
    // Sparse pattern (CSR) of the Jacobian, built once.
    std::vector<sunindextype> rowptr, colidx;
    long steps = 0;
    double t_now = 0;      ///< integrator time, s
    double last_step = 0;  ///< the last internal step size, s
    bool modified = false; ///< heads changed outside the integrator (seepage): re-initialise
    // SUNDIALS objects (declaration order = reverse destruction order).
    ContextOwner ctx;
    VectorOwner y, abstol;
    MatrixOwner jac;
    SolverOwner ls;
    CvodeOwner cvode;

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
    /// Face transmissivity and its derivative with respect to either head.
    std::pair<double, double> face(std::int64_t a, std::int64_t b, double ha, double hb) const {
        const double kf = (k[a] > 0 && k[b] > 0) ? 2.0 * k[a] * k[b] / (k[a] + k[b]) : 0.0;
        const double sat = 0.5 * (ha + hb) - 0.5 * (base[a] + base[b]);
        if (sat <= kMinSaturatedThickness) return {kf * kMinSaturatedThickness, 0.0};
        return {kf * sat, 0.5 * kf};
    }

    static int rhs(realtype, N_Vector yv, N_Vector ydot, void* user) {
        const auto* self = static_cast<const Impl*>(user);
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
        const auto* self = static_cast<const Impl*>(user);
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

    void build(const RasterD& surf, const RasterD& b, const RasterD& h0, const RasterF& ks,
               double specific_yield, std::array<GroundwaterBoundary, 4> sides) {
        grid = surf.grid();
        if (!(b.grid() == grid) || !(h0.grid() == grid) || !(ks.grid() == grid))
            throw InputError("groundwater: base, head and conductivity rasters must share the "
                             "terrain's grid");
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
                const bool fixed =
                    (i == 0 && sides[0] == GroundwaterBoundary::fixed_head) ||
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
        // CSR pattern: each variable row has itself and its evolving neighbours, sorted; the last
        // row (outflow) has the variables next to fixed cells.
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

        y.v = check_ptr(N_VNew_Serial(n + 1, ctx.ctx), "N_VNew_Serial");
        abstol.v = check_ptr(N_VNew_Serial(n + 1, ctx.ctx), "N_VNew_Serial");
        double* yy = N_VGetArrayPointer(y.v);
        double* at = N_VGetArrayPointer(abstol.v);
        for (std::int64_t v = 0; v < n; ++v) {
            yy[v] = head_fixed[cell_of_var[v]];
            at[v] = kHeadAbsTol;
        }
        yy[n] = 0.0;
        at[n] = kOutflowAbsTol;
        jac.m = check_ptr(SUNSparseMatrix(n + 1, n + 1, static_cast<sunindextype>(colidx.size()),
                                          CSR_MAT, ctx.ctx),
                          "SUNSparseMatrix");
        ls.s = check_ptr(SUNLinSol_KLU(y.v, jac.m, ctx.ctx), "SUNLinSol_KLU");
        // The five-point pattern is (nearly) symmetric: AMD orders it with less fill than COLAMD.
        check(SUNLinSol_KLUSetOrdering(ls.s, kKluOrderingAmd), "SUNLinSol_KLUSetOrdering");
        cvode.mem = check_ptr(CVodeCreate(CV_BDF, ctx.ctx), "CVodeCreate");
        check(CVodeInit(cvode.mem, rhs, 0.0, y.v), "CVodeInit");
        check(CVodeSVtolerances(cvode.mem, kRelTol, abstol.v), "CVodeSVtolerances");
        check(CVodeSetUserData(cvode.mem, this), "CVodeSetUserData");
        check(CVodeSetLinearSolver(cvode.mem, ls.s, jac.m), "CVodeSetLinearSolver");
        check(CVodeSetJacFn(cvode.mem, jacobian), "CVodeSetJacFn");
        check(CVodeSetMaxNumSteps(cvode.mem, kMaxSteps), "CVodeSetMaxNumSteps");
    }
};

Groundwater::Groundwater(const RasterD& surface, const RasterF& ksat, double specific_yield,
                         double thickness_m, double initial_depth_m)
    : m(std::make_unique<Impl>()) {
    RasterD b = surface, h0 = surface;
    b.array() -= thickness_m;
    h0.array() -= initial_depth_m;
    using GB = GroundwaterBoundary;
    m->build(surface, b, h0, ksat, specific_yield,
             {GB::fixed_head, GB::fixed_head, GB::fixed_head, GB::fixed_head});
}

Groundwater::Groundwater(const RasterD& surface, const RasterD& base, const RasterD& initial_head,
                         const RasterF& ksat, double specific_yield,
                         std::array<GroundwaterBoundary, 4> sides)
    : m(std::make_unique<Impl>()) {
    m->build(surface, base, initial_head, ksat, specific_yield, sides);
}

Groundwater::~Groundwater() = default;

GroundwaterResult Groundwater::step(double dt_s, const std::vector<double>& recharge_m3) {
    if (!(dt_s > 0)) throw InputError("groundwater: the time step must be > 0 s");
    const std::int64_t n = m->nvar();
    for (std::int64_t v = 0; v < n; ++v) m->rate[v] = recharge_m3[m->cell_of_var[v]] / dt_s;
    double* yy = N_VGetArrayPointer(m->y.v);
    const double out0 = yy[n];
    // The recharge changes at step boundaries. A multistep history that straddles the change would
    // integrate the budget invariant (storage + outflow = recharge) only approximately, so the
    // integrator restarts at every boundary, seeded with the last step size to skip the slow
    // start-up.
    check(CVodeReInit(m->cvode.mem, m->t_now, m->y.v), "CVodeReInit");
    if (m->last_step > 0)
        check(CVodeSetInitStep(m->cvode.mem, std::min(m->last_step, dt_s)), "CVodeSetInitStep");
    m->modified = false;
    const double t_end = m->t_now + dt_s;
    check(CVodeSetStopTime(m->cvode.mem, t_end), "CVodeSetStopTime");
    realtype t = m->t_now;
    const int flag = CVode(m->cvode.mem, t_end, m->y.v, &t, CV_NORMAL);
    if (flag < 0) {
        // Name the cell with the largest weighted local error.
        VectorOwner err, wts;
        err.v = N_VClone(m->y.v);
        wts.v = N_VClone(m->y.v);
        std::int64_t worst = -1;
        if (CVodeGetEstLocalErrors(m->cvode.mem, err.v) >= 0 &&
            CVodeGetErrWeights(m->cvode.mem, wts.v) >= 0) {
            const double* e = N_VGetArrayPointer(err.v);
            const double* w = N_VGetArrayPointer(wts.v);
            double best = -1;
            for (std::int64_t v = 0; v < n; ++v)
                if (std::abs(e[v] * w[v]) > best) best = std::abs(e[v] * w[v]), worst = v;
        }
        std::ostringstream s;
        s << "groundwater: CVODE failed with flag " << flag << " at t = " << t << " s of a " << dt_s
          << " s step";
        if (worst >= 0) {
            const std::int64_t c = m->cell_of_var[worst];
            s << ", largest error at cell (" << c % m->grid.nx << ", " << c / m->grid.nx << ")";
        }
        throw Error(s.str());
    }
    m->t_now = t_end;
    long nst = 0;
    CVodeGetNumSteps(m->cvode.mem, &nst);
    m->steps += nst;
    realtype last = 0;
    if (CVodeGetLastStep(m->cvode.mem, &last) >= 0) m->last_step = last;
    GroundwaterResult r;
    r.outflow_m3 = yy[n] - out0;
    // Recharge onto a fixed-head cell leaves through that boundary at once.
    for (std::int64_t c = 0; c < m->grid.size(); ++c)
        if (m->var_of_cell[c] < 0) r.outflow_m3 += recharge_m3[c];
    r.seepage_m3.assign(static_cast<std::size_t>(m->grid.size()), 0.0);
    for (std::int64_t v = 0; v < n; ++v) {
        const std::int64_t c = m->cell_of_var[v];
        if (yy[v] > m->surface[c]) {
            r.seepage_m3[c] = m->sy * (yy[v] - m->surface[c]) * m->area;
            yy[v] = m->surface[c];
            m->modified = true;
        }
    }
    return r;
}

RasterD Groundwater::head() const {
    RasterD h(m->grid);
    const double* yy = N_VGetArrayPointer(m->y.v);
    for (std::int64_t c = 0; c < m->grid.size(); ++c) {
        const std::int32_t v = m->var_of_cell[c];
        h.data()[c] = v >= 0 ? yy[v] : m->head_fixed[c];
    }
    return h;
}

double Groundwater::storage_m3() const {
    const double* yy = N_VGetArrayPointer(m->y.v);
    double s = 0;
    for (std::int64_t v = 0; v < m->nvar(); ++v)
        s += m->sy * (yy[v] - m->base[m->cell_of_var[v]]) * m->area;
    return s;
}

long Groundwater::steps_taken() const {
    return m->steps;
}

} // namespace ecoterra::hydro

namespace ecoterra::hydro {

void Groundwater::save_state(ArchiveWriter& a) const {
    const double* yy = N_VGetArrayPointer(m->y.v);
    a.put_vector(std::vector<double>(yy, yy + m->nvar() + 1));
    a.put(m->t_now);
    a.put(m->last_step);
    a.put(m->steps);
}

void Groundwater::load_state(ArchiveReader& a) {
    const auto y = a.get_vector<double>();
    if (static_cast<std::int64_t>(y.size()) != m->nvar() + 1)
        throw CheckpointError("groundwater checkpoint: " + std::to_string(y.size()) +
                              " values for " + std::to_string(m->nvar() + 1) +
                              " unknowns (another terrain?)");
    std::copy(y.begin(), y.end(), N_VGetArrayPointer(m->y.v));
    m->t_now = a.get<double>();
    m->last_step = a.get<double>();
    m->steps = a.get<long>();
}

} // namespace ecoterra::hydro
