// Hydrology benchmarks: cell-days/s of the daily update (soil, runoff, catchments, ET) on
// multifractal terrain, with the default soil water and with paper 002's, groundwater
// separately, and ponding cells/s.
// Usage: bench_hydro [--quick]   (--quick skips the 2048 x 2048 grid)
#include "ecoterra/hydro/catchments.hpp"
#include "ecoterra/hydro/groundwater.hpp"
#include "ecoterra/hydro/hydrology.hpp"
#include "ecoterra/terrain/spectral.hpp"
#include "ecoterra/terrain/weierstrass.hpp"
#include "ecoterra/wait_policy.hpp"

#include <chrono>
#include <cstdio>
#include <cstring>

using namespace ecoterra;
using namespace ecoterra::hydro;

namespace {
double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
RasterD terrain_of(int n) {
    terrain::MultifractalParams p = terrain::majhor2023_params(2.45);
    p.relief_m = 0.02 * n; // about 2 % mean relief over the grid
    return terrain::multifractal_generate(GridSpec{n, n, 1.0, 0, 0}, p, 3).z;
}
} // namespace

int main(int argc, char** argv) {
    ecoterra::ensure_passive_wait(argv); // time what `ecoterra` does (it runs passive)
    const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
    std::printf("ecoterra hydrology benchmark (1 m cells, humid subtropical weather)\n\n");
    std::printf("%-44s %13s %8s %10s %16s\n", "what", "grid", "days", "time", "rate");
    std::vector<int> sizes = {256, 1024};
    if (!quick) sizes.push_back(2048);
    for (int n : sizes) {
        const RasterD dem = terrain_of(n);
        RandomSoilParams rs;
        rs.mean = SoilComposition{20, 60, 20, 6.0, {}};
        const SoilMap soil = random_soil(dem.grid(), rs, 1);
        const auto t_setup = std::chrono::steady_clock::now();
        HydrologyModel m(dem, soil, RasterD(dem.grid(), 0.5), HydrologyOptions{},
                         climate_preset("humid_subtropical"));
        const double setup_s = seconds_since(t_setup);
        std::printf("%-44s %5d x %-5d %8s %9.2f s %10.3e cells/s\n",
                    "model setup (flow, depression hierarchy)", n, n, "-", setup_s,
                    double(n) * n / setup_s);
        // The default soil water (FAO-56, drainage, interception), then paper 002's.
        HydrologyOptions paper;
        paper.evapotranspiration = EvapotranspirationMethod::paper002;
        paper.drainage = DrainageMethod::none;
        paper.interception = InterceptionMethod::none;
        HydrologyModel mp(dem, soil, RasterD(dem.grid(), 0.5), paper,
                          climate_preset("humid_subtropical"));
        // The default without the critical layer (docs/hydrology.md s4, step 9): its cost.
        HydrologyOptions no_layer;
        no_layer.critical_layer_depth_m = 0;
        HydrologyModel mn(dem, soil, RasterD(dem.grid(), 0.5), no_layer,
                          climate_preset("humid_subtropical"));
        for (HydrologyModel* model : {&m, &mn, &mp}) {
            WeatherGenerator wg(climate_preset("humid_subtropical"), 5);
            const int days = 365;
            const auto t0 = std::chrono::steady_clock::now();
            for (int d = 0; d < days; ++d) model->step(wg.next());
            const double s = seconds_since(t0);
            std::printf("%-44s %5d x %-5d %8d %9.2f s %10.3e cell-days/s\n",
                        model == &m    ? "daily update, no groundwater"
                        : model == &mn ? "  the same without the critical layer"
                                       : "  the same, paper 002's soil water",
                        n, n, days, s, double(n) * n * days / s);
        }
    }
    for (int n : {32, 64, 128}) {
        const RasterD dem = terrain_of(n);
        const RasterF k(dem.grid(), 7e-6f);
        Groundwater gw(dem, k, 0.2, 20.0, 3.0, GroundwaterNumerics{GroundwaterSolver::cvode, 1});
        std::vector<double> recharge(static_cast<std::size_t>(dem.size()), 0.0);
        const int days = 30;
        const auto t0 = std::chrono::steady_clock::now();
        for (int d = 0; d < days; ++d) {
            recharge.assign(recharge.size(), d % 3 == 0 ? 0.004 : 0.0);
            gw.step(86400.0, recharge);
        }
        const double s = seconds_since(t0);
        std::printf("%-44s %5d x %-5d %8d %9.2f s %10.3e cell-days/s (%ld CVODE steps)\n",
                    "groundwater (CVODE BDF + KLU)", n, n, days, s, double(n) * n * days / s,
                    gw.steps_taken());
    }
    std::printf("\n");
    auto bench_pond = [](const char* what, const RasterD& dem) {
        const auto t0 = std::chrono::steady_clock::now();
        const Catchments c = pond(dem, 0.05, Routing::d8);
        const double s = seconds_since(t0);
        std::printf("%-44s %5d x %-5d %8s %9.3f s %10.3e cells/s (%zu catchments)\n", what,
                    dem.nx(), dem.ny(), "-", s, double(dem.size()) / s, c.catchments().size());
    };
    for (int n : {256, 1000, 2000})
        bench_pond("pond 0.05 m, d8, fBm D 2.3",
                   terrain::fbm_surface(GridSpec{n, n, 1.0, 0, 0},
                                        terrain::FbmParams::from_dimension(2.3, 2.0), 3));
    bench_pond("pond 0.05 m, d8, multifractal D 2.45", terrain_of(1024));
    return 0;
}
