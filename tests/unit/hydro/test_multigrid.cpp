// The multigrid-preconditioned conjugate gradients against Eigen's sparse Cholesky factorisation
// (an independent direct solver) on many random cell operators, and its contracts.
#include "ecoterra/error.hpp"
#include "ecoterra/hydro/multigrid.hpp"
#include "ecoterra/parallel.hpp"

#include <Eigen/Sparse>
#include <catch2/catch.hpp>

#include <cmath>
#include <omp.h>
#include <random>

using namespace ecoterra;
using namespace ecoterra::hydro;

namespace {

/// A random operator: own terms spanning `own_scale`, conductances log-uniform over two decades,
/// a share of inactive cells.
CellOperator random_operator(int nx, int ny, double own_scale, double inactive,
                             std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    CellOperator op(nx, ny);
    for (std::int64_t k = 0; k < op.size(); ++k) {
        op.active[k] = u(rng) >= inactive;
        op.s[k] = own_scale * (0.5 + u(rng));
        op.cx[k] = std::pow(10.0, 2 * u(rng) - 1);
        op.cy[k] = std::pow(10.0, 2 * u(rng) - 1);
    }
    return op;
}

/// The same operator as an Eigen sparse matrix (faces to inactive cells carry nothing).
Eigen::SparseMatrix<double> to_eigen(const CellOperator& op) {
    std::vector<Eigen::Triplet<double>> t;
    auto on = [&](std::int64_t k) { return op.active[k] != 0; };
    for (int j = 0; j < op.ny; ++j)
        for (int i = 0; i < op.nx; ++i) {
            const std::int64_t k = static_cast<std::int64_t>(j) * op.nx + i;
            if (!on(k)) {
                t.emplace_back(k, k, 1.0);
                continue;
            }
            double diag = op.s[k];
            auto face = [&](std::int64_t q, double c) {
                if (!on(q)) return;
                diag += c;
                t.emplace_back(k, q, -c);
            };
            if (i > 0) face(k - 1, op.cx[k - 1]);
            if (i + 1 < op.nx) face(k + 1, op.cx[k]);
            if (j > 0) face(k - op.nx, op.cy[k - op.nx]);
            if (j + 1 < op.ny) face(k + op.nx, op.cy[k]);
            t.emplace_back(k, k, diag);
        }
    Eigen::SparseMatrix<double> a(op.size(), op.size());
    a.setFromTriplets(t.begin(), t.end());
    return a;
}

} // namespace

TEST_CASE("Multigrid conjugate gradients solve what a sparse Cholesky factorisation solves",
          "[multigrid][hydro]") {
    struct Case {
        int nx, ny;
        double own, inactive;
    };
    // Square and odd shapes, one row, weak and strong own terms (a groundwater stage has
    // S_y A / dt ~ 1e-6 to 1e-4 against conductances ~1e-5 to 1e-3), with and without holes.
    const std::vector<Case> cases = {{64, 64, 1e-3, 0.0}, {63, 37, 1e-2, 0.1},
                                     {1, 50, 1e-3, 0.0},  {129, 5, 1e-1, 0.05},
                                     {17, 17, 1e-4, 0.2}, {200, 150, 1e-3, 0.02}};
    std::uint64_t seed = 1;
    for (const Case& c : cases) {
        ++seed;
        INFO(c.nx << " x " << c.ny << ", own " << c.own << ", inactive " << c.inactive);
        const CellOperator op = random_operator(c.nx, c.ny, c.own, c.inactive, seed);
        std::mt19937_64 rng(seed + 100);
        std::normal_distribution<double> n(0, 1);
        std::vector<double> b(static_cast<std::size_t>(op.size()));
        for (std::int64_t k = 0; k < op.size(); ++k) b[k] = op.active[k] ? n(rng) : 0.0;
        const Eigen::SparseMatrix<double> a = to_eigen(op);
        Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> direct(a);
        REQUIRE(direct.info() == Eigen::Success);
        const Eigen::VectorXd exact =
            direct.solve(Eigen::Map<const Eigen::VectorXd>(b.data(), op.size()));
        const MultigridSolver mg(op);
        std::vector<double> x(b.size(), 0.0);
        const SolveReport rep = mg.solve(b, x, 1e-10, 200);
        CHECK(rep.converged);
        CHECK(rep.iterations < 100); // 51-62 to ~1e-13 of x on cell-by-cell random conductances
        double worst = 0, scale = 0;
        for (std::int64_t k = 0; k < op.size(); ++k) {
            worst = std::max(worst, std::abs(x[k] - exact[k]));
            scale = std::max(scale, std::abs(exact[k]));
        }
        CHECK(worst <= 1e-6 * scale);
        // apply() is the matrix.
        std::vector<double> ax(b.size());
        mg.fine().apply(x.data(), ax.data()); // faces to inactive cells dropped
        const Eigen::VectorXd ex = a * Eigen::Map<const Eigen::VectorXd>(x.data(), op.size());
        for (std::int64_t k = 0; k < op.size(); k += 7)
            if (op.active[k]) CHECK(ax[k] == Approx(ex[k]).margin(1e-12 * scale));
    }
}

TEST_CASE("Multigrid solves give the same bits on any thread count", "[multigrid][hydro]") {
    const CellOperator op = random_operator(150, 130, 1e-3, 0.05, 9);
    std::vector<double> b(static_cast<std::size_t>(op.size()));
    for (std::int64_t k = 0; k < op.size(); ++k) b[k] = std::sin(0.01 * static_cast<double>(k));
    const int saved = omp_get_max_threads();
    set_parallel_min_items(1);
    std::vector<std::vector<double>> x;
    for (int threads : {1, 2, 3}) {
        omp_set_num_threads(threads);
        const MultigridSolver mg(op);
        x.emplace_back(b.size(), 0.0);
        mg.solve(b, x.back(), 1e-9, 200);
    }
    omp_set_num_threads(saved);
    set_parallel_min_items(kMinParallelItems);
    CHECK(x[0] == x[1]);
    CHECK(x[0] == x[2]);
}

TEST_CASE("Multigrid refuses operators it cannot solve, naming the cell", "[multigrid][hydro]") {
    CellOperator op(4, 4);
    std::fill(op.active.begin(), op.active.end(), 1);
    std::fill(op.s.begin(), op.s.end(), 1.0);
    op.cx[5] = -1;
    CHECK_THROWS_WITH(MultigridSolver(op), "multigrid: a negative or non-finite term at cell 5");
    op.cx[5] = 0;
    op.s[6] = 0; // a cell with no own term and no faces: singular
    CHECK_THROWS_WITH(MultigridSolver(op),
                      Catch::Contains("cell 6") && Catch::Contains("singular"));
    op.s.pop_back();
    CHECK_THROWS_AS(MultigridSolver(op), InputError);
}
