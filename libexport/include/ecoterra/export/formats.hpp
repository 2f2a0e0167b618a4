#pragma once
// The scene exporters (`ecoterra export scene`, `ecoterra export layers`); docs/exports.md gives
// every file, its units and axes. Each writes into an OutputFolder (folder.hpp): a new folder
// appears whole or not at all.
#include "ecoterra/export/scene.hpp"
#include "ecoterra/export/user_meshes.hpp"
#include "ecoterra/io/staging.hpp"

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace ecoterra::exporter {

/// Exports write into an OutputFolder (io/staging.hpp).
using io::OutputFolder;

enum class SceneFormat { mavs, gazebo, unreal, gltf };
SceneFormat scene_format_from_name(const std::string& name); ///< InputError listing the names
const char* scene_format_name(SceneFormat f);

struct ExportOptions {
    int terrain_step = 1;    ///< keep every k-th terrain vertex in meshes (glTF, MAVS)
    bool gltf_nodes = false; ///< glTF: one node per tree instead of EXT_mesh_gpu_instancing
    const UserMeshes* user = nullptr; ///< the user's meshes by species and stage, if any
    /// Where the folder will be once it is moved into place (ensemble members are written in a
    /// staging folder): MAVS's PathToMeshes names it. Empty: the folder itself.
    std::filesystem::path final_dir;
};

/// The trees that take a user's mesh, grouped by mesh (in the file's order).
struct UserGroup {
    const UserMesh* mesh = nullptr;
    std::vector<std::size_t> trees; ///< indices into Scene::trees
};
std::vector<UserGroup> user_groups(const Scene& s, const UserMeshes* user);

/// Prototype (species, stage) pairs in use by trees without a user mesh, in a fixed order
/// (species, then stage).
struct Prototype {
    int species = 0;
    Stage stage = Stage::young;
    std::vector<std::size_t> trees; ///< indices into Scene::trees
    std::string name;               ///< file-safe: "<species>_<stage>"
};
std::vector<Prototype> prototypes(const Scene& s, const UserMeshes* user = nullptr);

/// The scene as glTF 2.0 binary (.glb bytes): Y-up, metres, the terrain mesh and per (species,
/// stage) a trunk and a crown mesh with their instances.
std::string glb_bytes(const Scene& s, const ExportOptions& opt);
/// Writes the scene in `format` into the folder (glTF: scene.glb and a short README).
void write_scene(const Scene& s, SceneFormat format, OutputFolder& folder,
                 const ExportOptions& opt);
void write_mavs(const Scene& s, OutputFolder& folder, const ExportOptions& opt);
void write_gazebo(const Scene& s, OutputFolder& folder, const ExportOptions& opt);
void write_unreal(const Scene& s, OutputFolder& folder, const ExportOptions& opt);

/// GeoTIFF layers of a snapshot on the terrain's grid; `window_radius_m` is the radius of the
/// circular window of the stems-per-ha and basal-area layers.
struct LayerOptions {
    double window_radius_m = 10;
};
void write_layers(const Scene& s, OutputFolder& folder, const LayerOptions& opt);

/// The vegetation layers on the terrain's grid (exposed for tests).
struct VegetationLayers {
    RasterD canopy_height_m, stems_per_ha, basal_area_m2_per_ha, dominant_species, leaf_area_m2;
};
VegetationLayers vegetation_layers(const Scene& s, const LayerOptions& opt);

} // namespace ecoterra::exporter
