#pragma once
// The picture every scene export writes (docs/exports.md): the snapshot's stems beside a top
// view rendered from the exported geometry.
#include "ecoterra/export/scene.hpp"
#include "ecoterra/export/user_meshes.hpp"

#include <filesystem>

namespace ecoterra::exporter {

/// Writes `png`: left the run's stems (crown circles over the hillshade), right the terrain mesh
/// and every tree's trunk and crown triangles (or the user's mesh) seen from above, species
/// coloured alike.
void draw_export_picture(const Scene& s, const std::filesystem::path& png,
                         const UserMeshes* user = nullptr);

} // namespace ecoterra::exporter
