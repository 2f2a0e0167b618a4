// Scene export benchmark: seconds and bytes for each format on a 1 ha stand of about 600 stems
// (the quickstart's density at year 25) on a 50 x 50 terrain of 2 m cells, and on a 1 km2 stand
// of 1e5 stems on a 1009 x 1009 terrain of 0.99 m cells (the broadleaf species, negative-
// exponential DBH of mean 12 cm, random positions, fBm terrain). Bytes per stem are the export's
// bytes less those of the same export without trees, over the stems: what the trees cost.
// Figures are per-unit rates; run it alone and beside a busy neighbour.
// Usage: bench_export [--small-only]
#include "ecoterra/eco/plant.hpp"
#include "ecoterra/eco/species.hpp"
#include "ecoterra/export/formats.hpp"
#include "ecoterra/random.hpp"
#include "ecoterra/terrain/spectral.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <unistd.h>

using namespace ecoterra;
using namespace ecoterra::exporter;
namespace fs = std::filesystem;

namespace {

Scene forest(int cells, double cell_m, std::size_t n, std::uint64_t seed) {
    const auto eco = eco::load_ecosystem(fs::path(ECOTERRA_DATA_DIR) /
                                         "ecosystems/humid_subtropical_broadleaf.json");
    Scene s;
    s.run = "bench";
    s.terrain = terrain::fbm_surface(GridSpec{cells, cells, cell_m, 0, 0},
                                     terrain::FbmParams::from_dimension(2.3, 1.0), seed);
    for (const auto& sp : eco.species)
        s.species.push_back(
            {sp.name, sp.crown_shape, sp.max_height_m, sp.evergreen, sp.leaf_area_per_crown_area});
    Rng rng(seed, "bench.export");
    const double side = cells * cell_m;
    for (std::size_t k = 0; k < n; ++k) {
        Tree t;
        t.id = static_cast<std::int64_t>(k);
        t.species = static_cast<int>(rng.below(eco.species.size()));
        const auto& sp = eco.species[static_cast<std::size_t>(t.species)];
        t.dbh_m = -0.12 * std::log(1 - rng.uniform());
        t.height_m = eco::allometry::height_m(sp, t.dbh_m);
        t.crown_radius_m = eco::allometry::crown_radius_m(sp, t.dbh_m);
        t.x_m = rng.uniform(0, side);
        t.y_m = rng.uniform(0, side);
        t.z_m = s.terrain.sample_bilinear(t.x_m, t.y_m);
        t.stage = stage_of(t.height_m, sp.max_height_m);
        t.yaw_rad = tree_yaw_rad(seed, t.id);
        s.trees.push_back(t);
    }
    return s;
}

struct Figure {
    double seconds = 0;
    std::uint64_t bytes = 0;
};

Figure run(const Scene& s, SceneFormat f, const fs::path& dir) {
    const auto t0 = std::chrono::steady_clock::now();
    Figure fig;
    {
        OutputFolder folder(dir, false);
        write_scene(s, f, folder, ExportOptions{});
        fig.bytes = folder.bytes();
        folder.commit();
    }
    fig.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    fs::remove_all(dir);
    return fig;
}

} // namespace

int main(int argc, char** argv) {
    const bool small_only = argc > 1 && std::strcmp(argv[1], "--small-only") == 0;
    const fs::path tmp =
        fs::temp_directory_path() / ("ecoterra-bench-export-" + std::to_string(::getpid()));
    std::printf("ecoterra scene export benchmark (one thread)\n\n");
    std::printf("%-28s %-7s %9s %12s %10s %14s\n", "scene", "format", "seconds", "s per 1e5", "MB",
                "bytes per stem");
    struct Case {
        const char* name;
        int cells;
        double cell_m;
        std::size_t stems;
    };
    for (const Case c : {Case{"1 ha, 600 stems, 50^2", 50, 2.0, 600},
                         Case{"1 km2, 1e5 stems, 1009^2", 1009, 1000.0 / 1009, 100000}}) {
        if (small_only && c.stems > 1000) break;
        const Scene s = forest(c.cells, c.cell_m, c.stems, 7);
        Scene bare = s;
        bare.trees.clear();
        for (const auto f :
             {SceneFormat::gltf, SceneFormat::mavs, SceneFormat::gazebo, SceneFormat::unreal}) {
            const Figure full = run(s, f, tmp / "full");
            const Figure base = run(bare, f, tmp / "bare");
            std::printf("%-28s %-7s %9.3f %12.3f %10.2f %14.0f\n", c.name, scene_format_name(f),
                        full.seconds, full.seconds / static_cast<double>(c.stems) * 1e5,
                        static_cast<double>(full.bytes) / 1e6,
                        static_cast<double>(full.bytes - base.bytes) /
                            static_cast<double>(c.stems));
        }
    }
    fs::remove_all(tmp);
    return 0;
}
