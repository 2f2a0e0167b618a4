#pragma once
// What a scene export carries out of a run: the terrain of one snapshot (cut to a region), its
// trees with a life stage and a yaw, and each species' look. Every exporter writes this one
// structure, so all formats hold the same stems (docs/exports.md).
//
// Frame: the run's, east-north-up (ENU), metres; x east, y north, z up. Formats that use other
// axes (glTF Y-up, Unreal left-handed centimetres) convert on writing, and say so in their README.
#include "ecoterra/eco/species.hpp"
#include "ecoterra/raster.hpp"

#include <nlohmann/json.hpp>

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace ecoterra::exporter {

/// Life stage of a tree, by its height relative to the species' maximum: young below a third,
/// medium below two thirds, adult above (paper 002 s5.1 gives each species three meshes).
enum class Stage { young, medium, adult };
inline constexpr Stage kStages[] = {Stage::young, Stage::medium, Stage::adult};
const char* stage_name(Stage s);
Stage stage_of(double height_m, double max_height_m);

/// A rectangle in the run's coordinates, m.
struct Region {
    double x0_m = 0, y0_m = 0, x1_m = 0, y1_m = 0;
};
/// "X0,Y0,X1,Y1" (m); InputError naming `option` and the text otherwise.
Region parse_region(const std::string& text, const std::string& option = "--region");

struct Tree {
    std::int64_t id = 0;
    int species = 0;
    Stage stage = Stage::young;
    double x_m = 0, y_m = 0;
    double z_m = 0; ///< the terrain under the stem (bilinear on the DEM), m
    double height_m = 0, dbh_m = 0, crown_radius_m = 0;
    /// A shrub's stem diameter at the ground, or an object's diameter (0 for trees: their trunk
    /// base follows from the DBH), m.
    double base_diameter_m = 0;
    eco::LifeForm life_form = eco::LifeForm::tree;
    double yaw_rad = 0; ///< heading of the mesh, counter-clockwise from east, [0, 2 pi)
};

/// The ground layer (grasses and herbs, a cover per cell in the run) drawn as tufts: per cell and
/// grass species Poisson(cover x cell area / kTuftAreaM2) tufts at uniform positions in the cell,
/// each a tapered column with a base of kTuftAreaM2 and the species' Max Height tall. The draws
/// come from the run's seed in stream "export.grass" indexed by cell and species, so a region cut
/// holds the same tufts as the whole scene there.
inline constexpr double kTuftAreaM2 = 0.25;
/// A tuft's stem diameter for MAVS's vegetation override, m: MAVS's own oat grass entry.
inline constexpr double kTuftStemDiameterM = 0.01;
struct Tuft {
    int species = 0;
    double x_m = 0, y_m = 0, z_m = 0;
    double height_m = 0, radius_m = 0; ///< the tuft's base radius, m
    double yaw_rad = 0;
};

/// A piece of dead wood (docs/ecosystem.md s11, s12): a snag or stump standing at its base, or a
/// log or piece of slash lying from its base along its azimuth. Its diameter is at the base; the
/// meshes taper it as the trunks (unit_trunk).
struct DeadPiece {
    std::int64_t id = 0; ///< the tree's plant id
    int species = 0;
    int piece = 0; ///< eco::PieceKind: 0 stem, 1 stump, 2 top (slash), 3 snapped, 4 root plate
    bool standing = true;
    int decay_class = 1;
    double x_m = 0, y_m = 0, z_m = 0; ///< the base, on the terrain
    double azimuth_rad = 0;           ///< lying: base -> end, counter-clockwise from east
    double length_m = 0;              ///< standing height or lying length
    double diameter_m = 0;            ///< at the base
    double top_height_m = 0;          ///< lying: the top above the ground at the base
};

/// A piece's kind as node and link names give it: stem, stump, top, snapped, root_plate.
const char* dead_piece_name(int piece);

struct SpeciesLook {
    std::string name;
    eco::CrownShape crown_shape = eco::CrownShape::ellipsoid;
    double max_height_m = 20;
    bool evergreen = false;
    double leaf_area_per_crown_area = 4; ///< m2 of leaf per m2 of crown projection
};

/// Where a scene export's coordinates start: scene exports are written about a local origin so
/// that float32 formats (glTF) and engines keep millimetres at a DEM's map coordinates; x_run =
/// x_local + origin_x_m, y_run = y_local + origin_y_m, z unchanged.
struct LocalFrame {
    double origin_x_m = 0, origin_y_m = 0;
    std::string crs_wkt; ///< the run's coordinate system (empty: local metres)
    /// The frame as JSON for a sidecar (frame.json, the .glb's .json): origin, CRS and meaning.
    nlohmann::json to_json() const;
};

struct Scene {
    std::filesystem::path run;
    std::string source; ///< how the files name the run (default: the run's path)
    int snapshot = 0, year = 0;
    std::uint64_t seed = 0;       ///< the run's seed (the yaw stream derives from it)
    RasterD terrain;              ///< elevation, m, cut to the region
    std::optional<Region> region; ///< as asked (the terrain covers it to whole cells)
    int cut_i0 = 0, cut_j0 = 0;   ///< the terrain's first column and row in the run's grid
    std::vector<SpeciesLook> species;
    std::vector<Tree> trees;         ///< sorted by plant id
    std::vector<Tuft> tufts;         ///< the ground layer, by species, then cell, then draw
    std::vector<DeadPiece> deadwood; ///< pieces whose base lies on the (cut) terrain
    /// The frame of the coordinates above: load_scene gives the run's own (origin 0, 0);
    /// in_local_frame() moves a scene to a local one.
    LocalFrame frame;
    /// The run terrain's south-west corner (the whole terrain's, not a region's), run frame, m.
    double run_corner_x_m = 0, run_corner_y_m = 0;
};

/// A copy of `s` about a local origin given in the run's frame (default: the run terrain's
/// south-west corner, so that region cuts of one run share a frame): the terrain's grid origin,
/// the trees and the tufts are shifted; the frame records the origin and the CRS.
Scene in_local_frame(const Scene& s, const std::optional<std::array<double, 2>>& origin = {});
/// "X,Y" (m, the run's frame); InputError naming `option` and the text otherwise.
std::array<double, 2> parse_origin(const std::string& text, const std::string& option);

/// The tufts of each grass species that has any: (species index, indices into Scene::tufts).
std::vector<std::pair<int, std::vector<std::size_t>>> tuft_groups(const Scene& s);
/// The name of species k's tuft mesh in every format: "<file-safe species name>_grass".
std::string tuft_mesh_name(const Scene& s, int k);

/// The trees' yaw: uniform in [0, 2 pi), drawn from the run's seed in stream "export.yaw" indexed
/// by the plant id, so a tree keeps its heading from snapshot to snapshot and across formats.
double tree_yaw_rad(std::uint64_t seed, std::int64_t id);

/// Reads snapshot `snapshot` (negative: from the last) of `run`. With a region, the terrain is cut
/// to the cells that meet it and only stems inside it are kept; InputError if it lies outside the
/// terrain or is empty.
Scene load_scene(const std::filesystem::path& run, int snapshot,
                 const std::optional<Region>& region = std::nullopt);

/// The window of cells that meet `r`: first column, first row, columns, rows (InputError naming
/// `what` if it lies outside the grid or covers fewer than 2 x 2 cells).
std::array<int, 4> region_window(const GridSpec& g, const Region& r, const std::string& what);

} // namespace ecoterra::exporter
