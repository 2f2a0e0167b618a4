#pragma once
// A user's own tree meshes (`--species-meshes FILE.json`, docs/exports.md):
//
//   {"meshes": [{"species": "Birch", "stage": "adult", "obj": "birch.obj", "height_m": 18,
//                "rotate_y_to_z": false}, ...]}
//
// `species` names a species of the run; `stage` is young, medium or adult, or absent for every
// stage; `obj` is a Wavefront OBJ (relative to the JSON file), base at the origin, metres, z up
// (or y up with rotate_y_to_z); `height_m` is the mesh's height: each tree gets the mesh scaled
// uniformly by its height / height_m. A user mesh replaces ecoterra's trunk and crown for those
// trees in every format.
#include "ecoterra/export/mesh.hpp"

#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace ecoterra::exporter {

struct UserMesh {
    std::filesystem::path obj; ///< absolute
    /// The material libraries it names, as named (relative paths inside the OBJ's folder: no
    /// absolute path, no "..", no link leading out of it), each an existing file.
    std::vector<std::string> mtl;
    double height_m = 1;
    bool rotate_y_to_z = false;
    Mesh mesh;        ///< read from the OBJ, z up (turned if rotate_y_to_z)
    std::string name; ///< file-safe, unique
};

class UserMeshes {
public:
    /// Reads and checks the file; InputError naming the file, the entry, the key and the value.
    static UserMeshes load(const std::filesystem::path& json, const std::vector<SpeciesLook>& sp);
    /// The mesh for this species and stage, or nullptr.
    const UserMesh* find(int species, Stage stage) const;
    const std::vector<UserMesh>& meshes() const { return m_meshes; }
    bool empty() const { return m_meshes.empty(); }

private:
    std::vector<UserMesh> m_meshes;
    std::map<std::pair<int, int>, std::size_t> m_by;
};

/// Reads a Wavefront OBJ's vertices and faces (v; f with v, v/t, v//n or v/t/n, negative indices
/// allowed; polygons fanned into triangles); InputError naming the file and line. With `mtllibs`,
/// the material libraries its mtllib lines name, checked by checked_mtllib().
Mesh read_obj_mesh(const std::filesystem::path& path, std::vector<std::string>* mtllibs = nullptr);

/// A material library `name` that the OBJ `obj` names on line `line`: it must be a relative path
/// that stays inside the OBJ's folder (no absolute path, no "..", no link leading out) and an
/// existing file; InputError naming the OBJ, the line and the name otherwise. An export copies
/// only such files (an `mtllib /etc/shadow` once copied that file into the export).
std::filesystem::path checked_mtllib(const std::filesystem::path& obj, int line,
                                     const std::string& name);

} // namespace ecoterra::exporter
