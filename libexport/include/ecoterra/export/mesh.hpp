#pragma once
// Triangle meshes for scene exports: the terrain surface and each species' trunk and crown, made
// by ecoterra (no downloaded models). Meshes are in the run's frame (ENU: x east, y north, z up,
// metres); writers convert axes.
//
// Tree geometry (docs/exports.md, "Plant geometry"):
//   trunk  a tapered cylinder from the ground to the tree top; its diameter falls linearly from
//          d_base at the ground to kTopDiameterFraction * d_base at the top, with d_base chosen so
//          that the diameter at breast height (1.37 m) is the tree's DBH; trees shorter than
//          breast height (DBH 0) get d_base = max(H / kSeedlingSlenderness, kMinDiameter_m)
//   crown  radius = the tree's crown radius; its base at a stage-dependent fraction of the height
//          (young 0.15, medium 0.3, adult 0.45) and its top at the tree top; shaped by the
//          species: a cone, an ellipsoid, or an umbrella (a flattened ellipsoid over the top 30 %)
// The unit prototypes have height 1, trunk base diameter 1 and crown radius 1, so an instance is
// the prototype scaled by (d_base, d_base, H) for the trunk and (r, r, H) for the crown.
#include "ecoterra/eco/species.hpp"
#include "ecoterra/export/scene.hpp"
#include "ecoterra/raster.hpp"

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace ecoterra::exporter {

struct Mesh {
    std::vector<std::array<float, 3>> positions; ///< m
    std::vector<std::array<float, 3>> normals;   ///< unit, one per position
    std::vector<std::uint32_t> indices;          ///< triangles, counter-clockwise seen from outside

    std::size_t triangles() const { return indices.size() / 3; }
    /// Appends `other` scaled by s, turned by yaw about z and moved by t.
    void append(const Mesh& other, const std::array<double, 3>& s = {1, 1, 1}, double yaw_rad = 0,
                const std::array<double, 3>& t = {0, 0, 0});
    /// Smooth per-vertex normals from the area-weighted face normals.
    void compute_normals();
};

inline constexpr double kBreastHeight_m = 1.37;
inline constexpr double kTopDiameterFraction = 0.2;
inline constexpr double kSeedlingSlenderness = 100; ///< height / base diameter below 1.37 m
inline constexpr double kMinDiameter_m = 0.005;
inline constexpr int kTrunkSegments = 8;
inline constexpr int kCrownSegments = 12, kCrownRings = 6;

/// Diameter at the ground of a trunk of this DBH and height (see the file comment), m.
double trunk_base_diameter_m(double dbh_m, double height_m);
/// Height of the crown base as a fraction of the tree's height.
double crown_base_fraction(Stage s);

/// Unit prototypes (height 1): a trunk of base diameter 1, a crown of radius 1.
Mesh unit_trunk();
Mesh unit_crown(eco::CrownShape shape, Stage stage);

/// Instance scales: the trunk's (d_base, d_base, H), the crown's (r, r, H); every factor at least
/// 1 mm so that no instance is degenerate.
std::array<double, 3> trunk_scale(const Tree& t);
std::array<double, 3> crown_scale(const Tree& t);
/// A grass tuft as unit_trunk() scaled: base diameter 2 r, height H.
std::array<double, 3> tuft_scale(const Tuft& t);

/// A size class: trees of one species and stage whose height, trunk base diameter and crown
/// radius round to the same power of kSizeClassRatio (within +-2.5 %). Formats that cannot scale
/// each instance freely (Gazebo includes, MAVS's override diameter from the height) share one
/// tree mesh per class at the class's size.
inline constexpr double kSizeClassRatio = 1.05;
struct SizeClass {
    int species = 0;
    Stage stage = Stage::young;
    int kh = 0, kd = 0, kr = 0; ///< exponents of kSizeClassRatio
    double height_m = 0, base_diameter_m = 0, crown_radius_m = 0;
    std::vector<std::size_t> trees; ///< indices into Scene::trees
    std::string name;               ///< file-safe and unique
};
/// The classes in use, ordered by species, stage and size; trees for which `skip(tree)` is true
/// (those with a user's mesh) are left out.
std::vector<SizeClass> size_classes(const Scene& s,
                                    const std::function<bool(const Tree&)>& skip = nullptr);
/// The tree's DBH (or trunk base diameter below breast height), for the override of MAVS.
double stem_diameter_m(const Tree& t);

/// The terrain surface: one vertex per `step`-th cell centre (the last row and column always
/// kept), two triangles per quad, heights in metres shifted by -z_offset_m.
Mesh terrain_mesh(const RasterD& z, int step = 1, double z_offset_m = 0);

/// The scene's dead wood as one mesh in the scene's frame (heights shifted by -z_offset_m): the
/// trunk prototype scaled to each piece's base diameter and length, standing at its base or laid
/// along its azimuth with its top at the piece's height above the ground.
Mesh deadwood_mesh(const Scene& s, double z_offset_m = 0);

/// A name safe in file names and XML ids: lower case, [a-z0-9_].
std::string file_safe(const std::string& name);

/// Wavefront OBJ text of meshes (v, vn, f with 1-based indices), each part with its material
/// from the material library `mtllib` (none if empty).
struct ObjPart {
    const Mesh* mesh;
    std::string material;
};
std::string to_obj(const std::vector<ObjPart>& parts, const std::string& header,
                   const std::string& mtllib = "");
/// A material library: name -> diffuse colour.
std::string to_mtl(const std::vector<std::pair<std::string, std::array<double, 3>>>& materials);
/// The crown colour of species k (greens; evergreens darker).
std::array<double, 3> crown_colour(const SpeciesLook& sp, int k);
inline constexpr std::array<double, 3> kBarkColour{0.33, 0.24, 0.15};
/// Dead wood: bark weathered grey.
inline constexpr std::array<double, 3> kDeadWoodColour{0.45, 0.42, 0.38};
inline constexpr std::array<double, 3> kGroundColour{0.42, 0.36, 0.26};

} // namespace ecoterra::exporter
