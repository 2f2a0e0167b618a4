// Terrain benchmarks: wall time and cells/s for every generator and the main analyses.
// Usage: bench_terrain [--quick]   (--quick skips the 4096 x 4096 grids)
#include "ecoterra/terrain/analysis.hpp"
#include "ecoterra/terrain/io/dem_window.hpp"
#include "ecoterra/terrain/noise.hpp"
#include "ecoterra/terrain/spectral.hpp"
#include "ecoterra/terrain/weierstrass.hpp"
#include "ecoterra/wait_policy.hpp"

#include <omp.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <functional>
#include <string>

using namespace ecoterra;
using namespace ecoterra::terrain;

namespace {

/// Best wall time of `reps` runs, s.
double best_of(int reps, const std::function<void()>& f) {
    double best = 1e300;
    for (int r = 0; r < reps; ++r) {
        const auto t0 = std::chrono::steady_clock::now();
        f();
        best = std::min(
            best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    return best;
}

void report(const std::string& what, int n, double s) {
    const double cells = double(n) * n;
    std::printf("%-46s %5d x %-5d %9.3f s %12.3e cells/s\n", what.c_str(), n, n, s, cells / s);
}

} // namespace

int main(int argc, char** argv) {
    ecoterra::ensure_passive_wait(argv); // time what `ecoterra` does (it runs passive)
    const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
    const int threads = omp_get_max_threads();
    std::printf("ecoterra terrain benchmark: %d threads (OMP_NUM_THREADS), best of 3 runs unless "
                "noted\n\n",
                threads);
    std::printf("%-46s %13s %11s %20s\n", "what", "grid", "time", "rate");

    // The paper's multifractal: three W-M DEMs of 1009 x 1009 (M = 16/32/64, n_max = 17).
    const GridSpec paper = majhor2023_grid();
    const double mf2 =
        best_of(3, [&] { multifractal_generate(paper, majhor2023_params(2.45), 7); });
    report("majhor2023 multifractal (3 W-M DEMs)", 1009, mf2);
    omp_set_num_threads(1);
    const double mf1 =
        best_of(3, [&] { multifractal_generate(paper, majhor2023_params(2.45), 7); });
    omp_set_num_threads(threads);
    report("majhor2023 multifractal, 1 thread", 1009, mf1);
    std::printf("  -> speed-up on %d threads: %.2fx; W-M terms per second: %.3e\n", threads,
                mf1 / mf2, double(16 + 32 + 64) * 17 * 1009.0 * 1009.0 / mf2);

    std::vector<int> sizes = {1024};
    if (!quick) sizes.push_back(4096);
    for (int n : sizes) {
        const int reps = n > 2048 ? 1 : 3;
        const std::string note = reps == 1 ? " (1 run)" : "";
        const GridSpec g5{n, n, 0.05, 0, 0};
        const GridSpec g25{n, n, 0.25, 0, 0};
        report("wm M=64 D=2.45 (n_max 17, 0.05 m)" + note, n, best_of(reps, [&] {
                   wm_generate(g5, WMParams{64, 0, 1.5, 2.45, 100.9, 1e-8}, 1);
               }));
        report("multifractal (0.05 m)" + note, n,
               best_of(reps, [&] { multifractal_generate(g5, majhor2023_params(2.45), 1); }));
        report("perlin (0.25 m)" + note, n,
               best_of(reps, [&] { perlin_surface(g25, PerlinSurfaceParams{}, 1); }));
        report("gaussian (0.25 m)" + note, n,
               best_of(reps, [&] { gaussian_surface(g25, GaussianSurfaceParams{}, 1); }));
        const auto oct = variable_octave_wavelengths(g25, VariableSurfaceParams{});
        report("variable (0.25 m, " + std::to_string(oct.size()) + " octaves)" + note, n,
               best_of(reps, [&] { variable_surface(g25, VariableSurfaceParams{}, 1); }));
        report("fbm D=2.3 (0.25 m)" + note, n,
               best_of(reps, [&] { fbm_surface(g25, FbmParams::from_dimension(2.3), 1); }));
    }

    std::printf("\nanalysis of the majhor2023 terrain (1009 x 1009):\n");
    const RasterD z = multifractal_generate(paper, majhor2023_params(2.45), 7).z;
    report("gradient map + classes", 1009,
           best_of(3, [&] { classify_gradient(max_gradient_map(z)); }));
    const RasterU8 c = classify_gradient(max_gradient_map(z));
    report("closing, disk radius 0.25 m", 1009, best_of(3, [&] { close_classes(c, 0.25); }));
    report("RMS roughness (3 variants)", 1009, best_of(3, [&] { rms_roughness(z); }));
    report("radial PSD", 1009, best_of(3, [&] { radial_psd(z); }));
    report("fractal dimension (variogram)", 1009, best_of(3, [&] { fractal_dimension(z); }));
    report("full analysis", 1009, best_of(3, [&] { analyze_terrain(z); }));

    // Windows of the shipped DEMs resampled to 1 m (GDAL's warper; a scene's terrain.window):
    // 1 km2 of the 90 m UTM DEM, cubic, and of the geographic DEM reprojected to UTM 32N.
    std::printf("\nDEM windows resampled to 1 m cells (GDAL's warper):\n");
    const std::filesystem::path dem = std::filesystem::path(ECOTERRA_DATA_DIR) / "dem";
    io::DemRequest olinda;
    olinda.path = dem / "olinda_dem_utm25s.tif";
    olinda.window.centre = std::array<double, 2>{293770, 9115766};
    olinda.window.size_m = {1000, 1000};
    olinda.cell_m = 1;
    report("olinda 90 m UTM -> 1 m, cubic", 1000, best_of(3, [&] { io::read_dem(olinda); }));
    io::DemRequest lux = olinda;
    lux.path = dem / "luxembourg_elev.tif";
    lux.window.centre = std::array<double, 2>{6.13, 49.61};
    report("luxembourg degrees -> UTM 32N 1 m, cubic", 1000,
           best_of(3, [&] { io::read_dem(lux); }));
    return 0;
}
