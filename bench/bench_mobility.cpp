// Mobility benchmarks: SMG lines per second through a 1 ha stand of about 1000 stems and a 1 km2
// stand of about 1e5 stems (negative-exponential diameters, mean 12 cm, random positions, MRZR-4,
// 50 m lines), and traversal missions per second on a 1009 x 1009 multifractal DEM (Husky, 35 m
// missions). Figures are per-unit rates; run it alone and beside a busy neighbour.
// Usage: bench_mobility [--lines N] [--missions N]
#include "ecoterra/mobility/stand.hpp"
#include "ecoterra/mobility/traverse.hpp"
#include "ecoterra/random.hpp"
#include "ecoterra/terrain/generate.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <omp.h>

using namespace ecoterra;
using namespace ecoterra::mobility;

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::vector<StandStem> stand(double side_m, std::size_t n, std::uint64_t seed) {
    Rng rng(seed, "bench.stand");
    std::vector<StandStem> s;
    for (std::size_t k = 0; k < n; ++k) {
        const double dbh = -0.12 * std::log(1 - rng.uniform()); // mean 12 cm
        s.push_back({rng.uniform(0, side_m), rng.uniform(0, side_m), dbh, 1.3 + 60 * dbh});
    }
    return s;
}

} // namespace

int main(int argc, char** argv) {
    int lines = 400, missions = 200;
    for (int i = 1; i + 1 < argc; ++i) {
        if (std::strcmp(argv[i], "--lines") == 0) lines = std::atoi(argv[++i]);
        if (std::strcmp(argv[i], "--missions") == 0) missions = std::atoi(argv[++i]);
    }
    const std::filesystem::path data = ECOTERRA_DATA_DIR;
    const Vehicle mrzr = load_vehicle(data / "vehicles/mrzr4.json");
    const Vehicle husky = load_vehicle(data / "vehicles/husky_a200.json");
    std::printf("ecoterra mobility benchmark, %d threads\n\n", omp_get_max_threads());
    for (const auto& [side, stems] : {std::pair<double, std::size_t>{100, 1000},
                                      std::pair<double, std::size_t>{1000, 100000}}) {
        const RasterD dem(GridSpec{static_cast<int>(side), static_cast<int>(side), 1.0, 0, 0}, 0.0);
        const auto s = stand(side, stems, 1);
        StandLinesOptions opt;
        opt.lines = lines;
        const auto t0 = std::chrono::steady_clock::now();
        const auto m = analyse_stand(mrzr, s, dem, opt);
        const double sec = seconds_since(t0);
        std::printf("SMG  %6.0f m x %-6.0f m %7zu stems  BA %5.1f m2/ha  %d lines of 50 m  %7.3f s "
                    "%9.3g lines/s  (SMG mean %.2f m/s, NOGO %.1f %%)\n",
                    side, side, stems, m.basal_area_m2_per_ha, lines, sec, lines / sec,
                    m.smg_mean_m_per_s, 100 * m.nogo_fraction);
    }
    const auto t = terrain::generate_terrain({{"preset", "majhor2023"}, {"seed", 1}});
    std::vector<MissionLine> ms;
    Rng rng(2, "bench.missions");
    for (int k = 0; k < missions; ++k) {
        const double a = 2 * M_PI * rng.uniform();
        const double x = 25 + 7 * std::cos(a), y = 25 + 7 * std::sin(a);
        ms.push_back({k, x - 17.5 * std::cos(a), y - 17.5 * std::sin(a), x + 17.5 * std::cos(a),
                      y + 17.5 * std::sin(a)});
    }
    int ok = 0;
    const auto t0 = std::chrono::steady_clock::now();
    for (const auto& m : ms) ok += traverse(husky, t.z, m).success;
    const double sec = seconds_since(t0);
    std::printf("traverse 1009 x 1009 DEM (majhor2023, D_high 2.45)  %d missions of 35 m  %7.3f s "
                "%9.3g missions/s  (%d succeed)\n",
                missions, sec, missions / sec, ok);
    return 0;
}
