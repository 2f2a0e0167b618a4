// Ecosystem benchmarks: plant-years/s and simulated years per wall second, coupled and light-only,
// for the 1 ha quickstart scene and its undergrowth variant (shrubs and a ground layer; 100
// years each, and the ratio of their times), the quickstart with dead wood, windthrow and two
// thinnings against the living stand alone (the ratio of their times), and a 1 km x 1 km scene (1 m
// plant grid, 8 m hydrology grid, 300 stems/ha to start; --years N, default 10, and the 100-year
// time it implies). Usage: bench_eco [--years-1km N] [--skip-1km] [--mode coupled|light_only]
#include "ecoterra/eco/ecosystem.hpp"
#include "ecoterra/io/atomic_file.hpp"
#include "ecoterra/wait_policy.hpp"

#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>

using namespace ecoterra;
using nlohmann::json;

namespace {

struct Result {
    double seconds = 0, plant_years = 0;
    std::size_t plants = 0;
    double ba = 0;
};

Result grow(const eco::EcoScene& sc, int years) {
    const auto t0 = std::chrono::steady_clock::now();
    eco::Ecosystem e(sc);
    Result r;
    for (int y = 0; y < years; ++y) {
        e.run_year();
        r.plant_years += static_cast<double>(e.plants().size());
    }
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    r.plants = e.plants().size();
    r.ba = e.stand().basal_area_m2_per_ha;
    return r;
}

void report(const char* name, const char* mode, int years, const Result& r) {
    std::printf("%-34s %-10s %4d yr %8.2f s %10.3g plant-years/s %8.3g sim-yr/s  %7zu plants  "
                "BA %5.1f m2/ha  (100 yr: %.1f s)\n",
                name, mode, years, r.seconds, r.plant_years / r.seconds, years / r.seconds,
                r.plants, r.ba, 100.0 * r.seconds / years);
}

} // namespace

int main(int argc, char** argv) {
    ecoterra::ensure_passive_wait(argv); // time what `ecoterra` does (it runs passive)
    int years_1km = 10;
    bool skip_1km = false;
    std::string only; // --mode coupled | light_only: run that mode alone
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--years-1km") == 0 && i + 1 < argc)
            years_1km = std::atoi(argv[++i]);
        if (std::strcmp(argv[i], "--skip-1km") == 0) skip_1km = true;
        if (std::strcmp(argv[i], "--mode") == 0 && i + 1 < argc) only = argv[++i];
    }
    const std::filesystem::path data = ECOTERRA_DATA_DIR;
    std::printf("ecoterra ecosystem benchmark (humid subtropical broadleaf, daily steps)\n\n");
    json q = json::parse(io::read_text(data / "scenes/quickstart.json"));
    json u = json::parse(io::read_text(data / "scenes/quickstart_undergrowth.json"));
    for (const char* mode : {"coupled", "light_only"}) {
        if (!only.empty() && only != mode) continue;
        q["vegetation"]["competition"] = mode;
        u["vegetation"]["competition"] = mode;
        const Result trees = grow(eco::load_eco_scene(q, data / "scenes"), 100);
        report("1 ha quickstart (50^2 x 2 m terrain)", mode, 100, trees);
        // The same trees over a shrub layer and a ground layer of two grass species.
        const Result under = grow(eco::load_eco_scene(u, data / "scenes"), 100);
        report("1 ha quickstart with undergrowth", mode, 100, under);
        std::printf("%-34s %-10s undergrowth / trees alone: %.2f x the time\n", "", mode,
                    under.seconds / trees.seconds);
        // Issue 29's budget: dead wood, windthrow (a windy climate, a = 5 m/s) and two thinnings
        // against the living stand alone (no dead wood, no storms).
        json bare = q, busy = q;
        bare["vegetation"]["deadwood"]["enabled"] = false;
        bare["vegetation"]["windthrow"]["enabled"] = false;
        busy["vegetation"]["windthrow"]["weibull_scale_m_per_s"] = 5.0;
        busy["simulation"]["years"] = 100; // the operations' years must lie in the run
        busy["vegetation"]["management"] = {
            {"operations",
             {{{"year", 40}, {"type", "thin_from_below"}, {"target_basal_area_m2_per_ha", 15}},
              {{"year", 70}, {"type", "thin_from_above"}, {"target_basal_area_m2_per_ha", 18}}}}};
        const Result b = grow(eco::load_eco_scene(bare, data / "scenes"), 100);
        report("1 ha, no dead wood, no storms", mode, 100, b);
        const Result d = grow(eco::load_eco_scene(busy, data / "scenes"), 100);
        report("1 ha, dead wood, storms, 2 thinnings", mode, 100, d);
        std::printf("%-34s %-10s dead wood, storms and thinnings / neither: %.2f x the time, "
                    "%.2f x per plant-year\n",
                    "", mode, d.seconds / b.seconds,
                    (d.seconds / d.plant_years) / (b.seconds / b.plant_years));
    }
    if (skip_1km) return 0;
    json k = q;
    k["terrain"]["generate"] = {{"method", "fbm"},
                                {"size", 125},
                                {"cell_size_m", 8.0},
                                {"seed", 2},
                                {"params", {{"D", 2.3}, {"rms_m", 6.0}}}};
    k["vegetation"]["initial"] = {{"random", {{"stems_per_ha", 300}, {"max_dbh_m", 0.4}}}};
    for (const char* mode : {"coupled", "light_only"}) {
        if (!only.empty() && only != mode) continue;
        k["vegetation"]["competition"] = mode;
        const auto sc = eco::load_eco_scene(k, data / "scenes");
        report("1 km2 (125^2 x 8 m terrain, 1 m plants)", mode, years_1km, grow(sc, years_1km));
    }
    return 0;
}
