// `ecoterra export scene` and `ecoterra export layers`: a grown forest for vehicle simulators and
// GIS (docs/exports.md).
#include "common.hpp"
#include "subcommands.hpp"

#include "ecoterra/export/formats.hpp"
#include "ecoterra/export/picture.hpp"
#include "ecoterra/io/atomic_file.hpp"

#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <memory>
#include <optional>

namespace ecoterra::app {

namespace {

namespace fs = std::filesystem;
namespace ex = ecoterra::exporter;

struct SceneArgs {
    std::string run, format, output, region, species_meshes, origin;
    int snapshot = -1, decimate = 1;
    double window_m = 10;
    bool force = false, gltf_nodes = false, no_pictures = false;
};

ex::Scene load(const SceneArgs& a) {
    std::optional<ex::Region> region;
    if (!a.region.empty()) region = ex::parse_region(a.region);
    if (a.decimate < 1)
        throw InputError("--decimate " + std::to_string(a.decimate) + ": must be 1 or more");
    return ex::load_scene(a.run, a.snapshot, region);
}

void report(const ex::Scene& s, const std::string& what, const fs::path& out, std::uint64_t bytes,
            double seconds, const std::vector<std::string>& notes) {
    std::printf("wrote %s: %s of %s snapshot %d (year %d), %zu trees, %.3g MB (%.0f bytes per "
                "tree) in %.2f s\n",
                out.string().c_str(), what.c_str(), s.run.string().c_str(), s.snapshot, s.year,
                s.trees.size(), static_cast<double>(bytes) / 1e6,
                s.trees.empty() ? 0.0 : static_cast<double>(bytes) / s.trees.size(), seconds);
    for (const auto& n : notes) std::printf("note: %s\n", n.c_str());
}

void run_scene(const SceneArgs& a) {
    const auto t0 = std::chrono::steady_clock::now();
    refuse_output_over_input("-o", a.output, {a.run});
    const auto format = ex::scene_format_from_name(a.format);
    std::optional<std::array<double, 2>> origin;
    if (!a.origin.empty()) origin = ex::parse_origin(a.origin, "--origin");
    const ex::Scene s = ex::in_local_frame(load(a), origin);
    ex::ExportOptions opt;
    opt.terrain_step = a.decimate;
    opt.gltf_nodes = a.gltf_nodes;
    ex::UserMeshes user;
    if (!a.species_meshes.empty()) {
        user = ex::UserMeshes::load(a.species_meshes, s.species);
        opt.user = &user;
    }
    auto seconds = [&] {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    };
    if (format == ex::SceneFormat::gltf && fs::path(a.output).extension() == ".glb") {
        // One file and its sidecar, each replaced atomically.
        const fs::path glb = a.output, side = a.output + ".json";
        fs::path picture = glb;
        picture.replace_extension(".picture.png");
        claim_output("-o", glb.string(), a.force);
        claim_output("-o", side.string(), a.force);
        if (!a.no_pictures) claim_output("-o", picture.string(), a.force);
        const std::string bytes = ex::glb_bytes(s, opt);
        nlohmann::json meta = {
            {"file", glb.filename().string()},
            {"format", "glTF 2.0 binary"},
            {"run", s.run.string()},
            {"snapshot", s.snapshot},
            {"year", s.year},
            {"trees", s.trees.size()},
            {"axes", "glTF: right-handed, +Y up, metres; (x, y, z) glTF = (east, up, -north) "
                     "of the local frame"},
            {"frame", s.frame.to_json()},
            {"instancing", a.gltf_nodes ? "one node per tree (extras: plant_id, species, stage, "
                                          "dbh_m, height_m, crown_radius_m)"
                                        : "EXT_mesh_gpu_instancing: per (species, stage) a "
                                          "trunks node and a crowns node; per-instance attributes "
                                          "_PLANT_ID, _DBH_M, _HEIGHT_M, _CROWN_RADIUS_M"},
            {"meshes", "terrain (every " + std::to_string(a.decimate) +
                           ". cell centre); per species and stage a unit trunk (solid) and crown "
                           "(visual only), scaled per tree to its DBH, height and crown radius"},
            {"load", "Blender: File > Import > glTF 2.0; three.js GLTFLoader; Python: pygltflib"}};
        io::write_text_atomic(glb, bytes);
        io::write_text_atomic(side, meta.dump(2) + "\n");
        if (!a.no_pictures) {
            io::AtomicOutput out(picture);
            ex::draw_export_picture(s, out.temp_path(), opt.user);
            out.commit();
            std::printf("picture: %s\n", picture.string().c_str());
        }
        report(s, "glTF", glb, bytes.size(), seconds(), {});
        return;
    }
    claim_output("-o", a.output, a.force);
    ex::OutputFolder folder(a.output, a.force);
    ex::write_scene(s, format, folder, opt);
    const auto bytes = folder.bytes(); // the scene, without its picture
    if (!a.no_pictures) ex::draw_export_picture(s, folder.staged_path("picture.png"), opt.user);
    folder.commit();
    report(s, ex::scene_format_name(format), a.output, bytes, seconds(), folder.notes());
    if (!a.no_pictures)
        std::printf("picture: %s\n", (fs::path(a.output) / "picture.png").string().c_str());
}

void run_layers(const SceneArgs& a) {
    const auto t0 = std::chrono::steady_clock::now();
    refuse_output_over_input("-o", a.output, {a.run});
    const ex::Scene s = load(a);
    claim_output("-o", a.output, a.force);
    ex::OutputFolder folder(a.output, a.force);
    ex::write_layers(s, folder, {a.window_m});
    const auto bytes = folder.bytes();
    folder.commit();
    report(s, "GeoTIFF layers", a.output, bytes,
           std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), {});
}

void common_options(CLI::App* c, SceneArgs& a) {
    c->add_option("run", a.run, "HDF5 run file")->required();
    c->add_option("-o,--output", a.output, "output folder (glTF: a .glb file or a folder)")
        ->required();
    c->add_option("--snapshot", a.snapshot, "snapshot index (negative: from the last)")
        ->capture_default_str();
    c->add_option("--region", a.region, "X0,Y0,X1,Y1: cut this rectangle (m, the run's frame)");
    c->add_flag("--force", a.force,
                "write into an existing folder (same-named files replaced, others kept)");
}

} // namespace

void add_export_scene_commands(CLI::App& exp) {
    auto a = std::make_shared<SceneArgs>();
    CLI::App* sc = exp.add_subcommand("scene", "the forest and terrain for a vehicle simulator");
    common_options(sc, *a);
    sc->add_option("--format", a->format, "mavs, gazebo, unreal or gltf")->required();
    sc->add_option("--decimate", a->decimate, "keep every k-th terrain vertex in meshes")
        ->capture_default_str();
    sc->add_option("--origin", a->origin,
                   "X,Y: the local origin of the scene's coordinates, m in the run's frame "
                   "(default: the run terrain's south-west corner); frame.json records it");
    sc->add_flag("--gltf-nodes", a->gltf_nodes,
                 "glTF: one node per tree (extras per tree) instead of GPU instancing");
    sc->add_option("--species-meshes", a->species_meshes,
                   "JSON mapping species and life stage to your own OBJ meshes (docs/exports.md)");
    sc->add_flag("--no-pictures", a->no_pictures,
                 "skip the picture (the stems beside a top view of the exported geometry)");
    sc->callback([a] { run_scene(*a); });

    auto b = std::make_shared<SceneArgs>();
    CLI::App* ly = exp.add_subcommand("layers", "GeoTIFF rasters of a snapshot for GIS");
    common_options(ly, *b);
    ly->add_option("--window", b->window_m, "radius of the stems and basal-area window, m")
        ->capture_default_str();
    ly->callback([b] { run_layers(*b); });
}

} // namespace ecoterra::app
