// Landscape-scale benchmark (issue 26): each case runs in a child process, so that its peak
// resident memory and its CPU time are its own (wait4's rusage), quiet and then beside one busy
// process. Prints wall time, plant-years/s, cell-days/s, CPU use (user + system over wall: 100 %
// is one core busy, 200 % both), the peak memory and the run's own estimate of it
// (eco::memory_estimate, which refuses scenes that would not fit).
//   1 ha quickstart, coupled, 100 years (50^2 terrain cells of 2 m, 1 m plant grid)
//   1 km2 at 1 m (terrain, hydrology and plant grids), coupled, 300 stems/ha to start, N years
//   the same with groundwater (the implicit solver), N years, on the terrain's 1 m cells and on
//   aquifer cells of 4 m (hydrology.aquifer_cell_factor 4)
//   1 km2 at 1 m planted with 2000 stems/ha (2e5 plants, the density the century reaches from
//   year 70), 1 year, with the plants in stem-cell order (the default) and in birth order
//   (vegetation.plant_order = birth, the layout before 2026-11-28)
// Usage: bench_landscape [--years-1km N] (default 3) [--quiet-only]
#include "busy.hpp"
#include "ecoterra/eco/ecosystem.hpp"
#include "ecoterra/io/atomic_file.hpp"
#include "ecoterra/wait_policy.hpp"

#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

using namespace ecoterra;
using nlohmann::json;

namespace {

struct Figures {
    double seconds = 0, plant_years = 0, cell_days = 0, estimate_bytes = 0;
    double plants_end = 0;
};

Figures grow(const json& scene, int years) {
    const eco::EcoScene sc =
        eco::load_eco_scene(scene, std::filesystem::path(ECOTERRA_DATA_DIR) / "scenes");
    Figures f;
    f.estimate_bytes = eco::memory_estimate(sc).bytes();
    const auto t0 = std::chrono::steady_clock::now();
    eco::Ecosystem e(sc);
    for (int y = 0; y < years; ++y) {
        e.run_year();
        f.plant_years += static_cast<double>(e.plants().size());
    }
    f.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    f.cell_days = static_cast<double>(sc.hydro.dem.size()) * 365.0 * years;
    f.plants_end = static_cast<double>(e.plants().size());
    return f;
}

/// Runs grow() in a child (which also builds the scene: a child forked from a process whose
/// OpenMP threads have started would hang in libgomp); prints its figures, CPU use and peak
/// resident memory.
void measure(const char* name, const json& sc, int years) {
    int fd[2];
    if (pipe(fd) != 0) return;
    std::fflush(stdout);
    const pid_t pid = fork();
    if (pid == 0) {
        close(fd[0]);
        const Figures f = grow(sc, years);
        const ssize_t w = write(fd[1], &f, sizeof f);
        _exit(w == static_cast<ssize_t>(sizeof f) ? 0 : 1);
    }
    close(fd[1]);
    Figures f;
    const ssize_t got = read(fd[0], &f, sizeof f);
    close(fd[0]);
    int status = 0;
    rusage ru{};
    wait4(pid, &status, 0, &ru);
    if (got != static_cast<ssize_t>(sizeof f) || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        std::printf("%-44s failed\n", name);
        return;
    }
    const double cpu = static_cast<double>(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) +
                       1e-6 * static_cast<double>(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
    const double peak = static_cast<double>(ru.ru_maxrss) * 1024.0;
    std::printf("%-44s %3d yr %8.1f s %9.3g pl-yr/s %9.3g c-d/s %5.0f %% %7.0f MB (est. %5.0f) "
                "%8.0f plants\n",
                name, years, f.seconds, f.plant_years / f.seconds, f.cell_days / f.seconds,
                100.0 * cpu / f.seconds, peak / 1e6, f.estimate_bytes / 1e6, f.plants_end);
}

} // namespace

int main(int argc, char** argv) {
    ecoterra::ensure_passive_wait(argv); // time what `ecoterra` does (it runs passive)
    int years_1km = 3;
    bool quiet_only = false;
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--years-1km") == 0 && i + 1 < argc)
            years_1km = std::atoi(argv[++i]);
        if (std::strcmp(argv[i], "--quiet-only") == 0) quiet_only = true;
    }
    const std::filesystem::path data = ECOTERRA_DATA_DIR;
    json q = json::parse(io::read_text(data / "scenes/quickstart.json"));
    json k = q;
    k["terrain"]["generate"]["size"] = 1000;
    k["terrain"]["generate"]["cell_size_m"] = 1.0;
    k["vegetation"]["initial"] = {{"random", {{"stems_per_ha", 300}}}};
    json g = k;
    g["hydrology"]["groundwater"] = true;
    json g4 = g;
    g4["hydrology"]["aquifer_cell_factor"] = 4;
    json dense = k;
    dense["vegetation"]["initial"] = {{"random", {{"stems_per_ha", 2000}}}};
    json dense_birth = dense;
    dense_birth["vegetation"]["plant_order"] = "birth";
    std::printf("ecoterra landscape benchmark (humid subtropical broadleaf, coupled, daily steps; "
                "CPU: 100 %% = one core)\n");
    for (int busy = 0; busy <= (quiet_only ? 0 : 1); ++busy) {
        const pid_t spinner = busy ? bench::start_busy() : 0;
        std::printf("\n%s\n", busy ? "beside one busy process" : "quiet");
        measure("1 ha quickstart (2500 cells, 1 m plants)", q, 100);
        measure("1 km2 at 1 m, 300 stems/ha to start", k, years_1km);
        measure("1 km2 at 1 m, 300 stems/ha, groundwater", g, years_1km);
        measure("the same, 4 m aquifer cells", g4, years_1km);
        measure("1 km2 at 1 m, 2000 stems/ha", dense, 1);
        measure("the same, plants in birth order", dense_birth, 1);
        if (spinner) bench::stop_busy(spinner);
    }
    return 0;
}
