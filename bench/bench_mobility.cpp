// Mobility benchmarks: SMG lines per second through a 1 ha stand of about 1000 stems and a 1 km2
// stand of about 1e5 stems (negative-exponential diameters, mean 12 cm, random positions, MRZR-4,
// 50 m lines), mobility maps of the same stands over fBm terrain with soft soil (8 headings, the
// terrain's 1 m cells; the 1 km2 map is the 1e6 cells with 1e5 stems), and traversal
// missions per second on a 1009 x 1009 multifractal DEM (Husky, 35 m missions). Figures are
// per-unit rates; run it alone and beside a busy neighbour.
// Usage: bench_mobility [--lines N] [--missions N] [--only-map]
#include "ecoterra/mobility/map.hpp"
#include "ecoterra/mobility/route.hpp"
#include "ecoterra/mobility/stand.hpp"
#include "ecoterra/mobility/traverse.hpp"
#include "ecoterra/random.hpp"
#include "ecoterra/terrain/generate.hpp"
#include "ecoterra/terrain/spectral.hpp"
#include "ecoterra/wait_policy.hpp"

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

/// The mobility map of a stand of `stems` on a side_m x side_m fBm terrain at 1 m, with logs and
/// a soil of random strength (60-2000 kPa: some cells soft, a few below the MRZR's VCI1).
void bench_map(const Vehicle& v, double side_m, std::size_t stems) {
    const int n = static_cast<int>(side_m);
    const RasterD dem = terrain::fbm_surface(GridSpec{n, n, 1.0, 0, 0},
                                             terrain::FbmParams::from_dimension(2.3, 1.0), 3);
    Rng rng(4, "bench.map");
    RasterD rci(dem.grid(), 0.0);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) rci(i, j) = rng.uniform(60, 2000);
    std::vector<Log> logs;
    for (std::size_t k = 0; k < stems / 50; ++k) {
        const double x = rng.uniform(0, side_m), y = rng.uniform(0, side_m);
        const double a = 2 * M_PI * rng.uniform(), len = rng.uniform(3, 15);
        const double h = rng.uniform(0.1, 0.5);
        logs.push_back({{x, y}, {x + len * std::cos(a), y + len * std::sin(a)}, h, h, h});
    }
    GroundMaps g;
    g.rci_kpa = &rci;
    const auto s = stand(side_m, stems, 1);
    const auto t0 = std::chrono::steady_clock::now();
    const MobilityMap m = mobility_map(v, dem, s, logs, g, MapOptions{});
    const double sec = seconds_since(t0);
    const double cells = static_cast<double>(m.grid.size());
    std::printf("map  %6.0f m x %-6.0f m %7zu stems %6zu logs  %zu headings  %7.3f s  %9.3g "
                "cells/s  %9.3g cell-headings/s  (mean %.2f m/s, GO %.1f %%)\n",
                side_m, side_m, stems, logs.size(), m.headings_deg.size(), sec, cells / sec,
                cells * m.headings_deg.size() / sec, m.mean_speed_m_per_s, 100 * m.go_share);
    // A season's day: the plan (slopes and lanes) once, then the map of each day's ground.
    const auto tp = std::chrono::steady_clock::now();
    const MapPlan plan(v, dem, s, logs, MapOptions{});
    const double plan_s = seconds_since(tp);
    const int days = 5;
    const auto td = std::chrono::steady_clock::now();
    double mean = 0;
    for (int d = 0; d < days; ++d) {
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) rci(i, j) = rng.uniform(60, 2000);
        mean += plan.map(g, false).mean_speed_m_per_s / days;
    }
    const double day_s = seconds_since(td) / days;
    std::printf("season: plan %7.3f s, then %7.3f s a day (%9.3g cells/s): 365 days in %.0f s "
                "(mean %.2f m/s)\n",
                plan_s, day_s, cells / day_s, plan_s + 365 * day_s, mean);
    const auto t1 = std::chrono::steady_clock::now();
    const Route r = fastest_route(m.speed_m_per_s, m.headings_deg, {0.1 * side_m, 0.1 * side_m},
                                  {0.9 * side_m, 0.9 * side_m});
    const double rs = seconds_since(t1);
    std::printf("route across it (0.1 to 0.9)    %7.3f s  %9.3g cells/s  (%s, %.1f s, SMG %.2f "
                "m/s)\n",
                rs, cells / rs, r.found ? "found" : "none", r.time_s, r.smg_m_per_s());
}

} // namespace

int main(int argc, char** argv) {
    ecoterra::ensure_passive_wait(argv); // time what `ecoterra` does (it runs passive)
    int lines = 400, missions = 200;
    bool only_map = false;
    for (int i = 1; i < argc; ++i)
        if (std::strcmp(argv[i], "--only-map") == 0) only_map = true;
    for (int i = 1; i + 1 < argc; ++i) {
        if (std::strcmp(argv[i], "--lines") == 0) lines = std::atoi(argv[++i]);
        if (std::strcmp(argv[i], "--missions") == 0) missions = std::atoi(argv[++i]);
    }
    const std::filesystem::path data = ECOTERRA_DATA_DIR;
    const Vehicle mrzr = load_vehicle(data / "vehicles/mrzr4.json");
    const Vehicle husky = load_vehicle(data / "vehicles/husky_a200.json");
    std::printf("ecoterra mobility benchmark, %d threads\n\n", omp_get_max_threads());
    bench_map(mrzr, 100, 1000);
    bench_map(mrzr, 1000, 100000);
    if (only_map) return 0;
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
