// Groundwater benchmark: cell-days/s of the implicit solver (multigrid-preconditioned conjugate
// gradients) from 128^2 to 1024^2 (2048^2 without --quick), on the terrain's 1 m cells and on
// aquifer cells of 2 and 4 m (aquifer_cell_factor; the rate counts the 1 m terrain cells), the
// CVODE reference where it is affordable, the ratio of the two at the same grid, and each run's
// budget residual. Quiet, then beside one busy process. Usage: bench_groundwater [--quick]
#include "busy.hpp"
#include "ecoterra/hydro/groundwater.hpp"
#include "ecoterra/terrain/weierstrass.hpp"
#include "ecoterra/wait_policy.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <utility>

using namespace ecoterra;
using namespace ecoterra::hydro;

namespace {

struct Figures {
    double seconds = 0, residual = 0;
    long work = 0;
};

RasterD terrain_of(int n) {
    terrain::MultifractalParams p = terrain::majhor2023_params(2.45);
    p.relief_m = 0.02 * n; // about 2 % mean relief over the grid
    return terrain::multifractal_generate(GridSpec{n, n, 1.0, 0, 0}, p, 3).z;
}

/// `days` of rain-driven recharge (30 % of days, 2 to 22 mm, half of it in the cells below the
/// mean) on 1 m cells, K 7e-6 m/s, S_y 0.2, 20 m of aquifer, the water table 3 m down.
Figures run(const RasterD& dem, GroundwaterNumerics numerics, int days) {
    const RasterF k(dem.grid(), 7e-6f);
    Groundwater gw(dem, k, 0.2, 20.0, 3.0, numerics);
    double mean = 0;
    for (std::int64_t c = 0; c < dem.size(); ++c) mean += dem.data()[c];
    mean /= static_cast<double>(dem.size());
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<double> recharge(static_cast<std::size_t>(dem.size()));
    const double s0 = gw.storage_m3();
    double added = 0, left = 0;
    const auto t0 = std::chrono::steady_clock::now();
    for (int d = 0; d < days; ++d) {
        const double mm = u(rng) < 0.3 ? 2 + 20 * u(rng) : 0.0;
        for (std::int64_t c = 0; c < dem.size(); ++c) {
            recharge[c] = mm * 1e-3 * (dem.data()[c] < mean ? 0.75 : 0.25);
            added += recharge[c];
        }
        const auto r = gw.step(86400.0, recharge);
        left += r.outflow_m3;
        for (double s : r.seepage_m3) left += s;
    }
    Figures f;
    f.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    f.residual = std::abs(gw.storage_m3() - s0 + left - added) / added;
    f.work = gw.steps_taken();
    return f;
}

} // namespace

int main(int argc, char** argv) {
    ecoterra::ensure_passive_wait(argv); // time what `ecoterra` does (it runs passive)
    const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
    std::printf("ecoterra groundwater benchmark (1 m cells, multifractal terrain D 2.45)\n");
    std::vector<int> sizes = {128, 256, 512, 1024};
    if (!quick) sizes.push_back(2048);
    for (int busy = 0; busy <= 1; ++busy) {
        const pid_t spinner = busy ? bench::start_busy() : 0;
        std::printf("\n%s\n", busy ? "beside one busy process" : "quiet");
        std::printf("%-34s %11s %5s %9s %14s %12s %10s\n", "solver (TR-BDF2 + CG)", "grid", "days",
                    "time", "rate", "work/day", "residual");
        for (int n : sizes) {
            const RasterD dem = terrain_of(n);
            const int days = n <= 512 ? 60 : 20;
            // (steps a day, aquifer cell factor): the terrain's cells, then aquifer cells of
            // 2 and 4 m under the 1 m terrain (the rate counts terrain cells).
            const std::pair<int, int> cases[] = {{2, 1}, {1, 1}, {2, 2}, {2, 4}};
            for (const auto& [sub, factor] : cases) {
                GroundwaterNumerics numerics{GroundwaterSolver::implicit, sub};
                numerics.aquifer_cell_factor = factor;
                const Figures f = run(dem, numerics, days);
                char what[64];
                std::snprintf(what, sizeof what, "implicit, %d step%s/day, %d m aquifer", sub,
                              sub > 1 ? "s" : "", factor);
                std::printf("%-34s %5d x %-5d %5d %8.2f s %9.3e c-d/s %12.1f %10.1e\n", what, n, n,
                            days, f.seconds, double(n) * n * days / f.seconds,
                            double(f.work) / days, f.residual);
            }
            if (n <= 128) {
                const Figures c = run(dem, GroundwaterNumerics{GroundwaterSolver::cvode, 1}, days);
                const Figures i = run(dem, GroundwaterNumerics{}, days);
                std::printf("%-34s %5d x %-5d %5d %8.2f s %9.3e c-d/s %12.1f %10.1e\n",
                            "cvode reference (steps)", n, n, days, c.seconds,
                            double(n) * n * days / c.seconds, double(c.work) / days, c.residual);
                std::printf("%-34s %5d x %-5d %28.1f x\n", "speed-up of implicit (2/day)", n, n,
                            c.seconds / i.seconds);
            }
        }
        if (spinner) bench::stop_busy(spinner);
    }
    return 0;
}
