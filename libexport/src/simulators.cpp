// MAVS, Gazebo and Unreal exports (docs/exports.md; formats from reference mobility.md s3 and
// mavs.md s3.5).
#include "ecoterra/csv.hpp"
#include "ecoterra/export/formats.hpp"
#include "ecoterra/export/mesh.hpp"

#include "ecoterra/error.hpp"
#include "ecoterra/io/atomic_file.hpp"
#include "ecoterra/terrain/io/raster_io.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <map>
#include <numbers>

namespace ecoterra::exporter {

namespace {

using nlohmann::json;
namespace fs = std::filesystem;

constexpr double kCmPerM = 100;
constexpr double kUnrealZCountsPerPercent = 128; ///< UE: 1/128 cm per count at Z scale 100 %
constexpr double kUnrealZeroCount = 32768;       ///< UE puts this count at the actor's Z

std::string num(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.9g", v);
    return buf;
}

double rad_to_deg(double r) {
    return r * 180 / std::numbers::pi;
}

/// Materials of the trees: bark and each species' crown.
std::vector<std::pair<std::string, std::array<double, 3>>> tree_materials(const Scene& s) {
    std::vector<std::pair<std::string, std::array<double, 3>>> m{{"bark", kBarkColour}};
    for (std::size_t k = 0; k < s.species.size(); ++k)
        m.emplace_back(file_safe(s.species[k].name) + "_crown",
                       crown_colour(s.species[k], static_cast<int>(k)));
    return m;
}

/// The OBJ of a tuft of one grass species: the tapered column of its size in the species' colour.
std::string tuft_obj(const Scene& s, const Tuft& t, const std::string& mtllib) {
    Mesh m;
    m.append(unit_trunk(), tuft_scale(t));
    return to_obj({{&m, file_safe(s.species[static_cast<std::size_t>(t.species)].name) + "_crown"}},
                  "ecoterra grass tuft of " + s.species[static_cast<std::size_t>(t.species)].name +
                      ": ENU (x east, y north, z up), metres, base at the origin",
                  mtllib);
}

/// OBJ of a size class: trunk with bark, crown with the species' colour.
std::string tree_obj(const Scene& s, const SizeClass& c, const std::string& mtllib) {
    const SpeciesLook& look = s.species[static_cast<std::size_t>(c.species)];
    Mesh trunk, crown;
    trunk.append(unit_trunk(), {c.base_diameter_m, c.base_diameter_m, c.height_m});
    crown.append(unit_crown(look.crown_shape, c.stage),
                 {c.crown_radius_m, c.crown_radius_m, c.height_m});
    return to_obj({{&trunk, "bark"}, {&crown, file_safe(look.name) + "_crown"}},
                  "ecoterra tree: " + look.name + ", " + stage_name(c.stage) + ", height " +
                      num(c.height_m) + " m, trunk base diameter " + num(c.base_diameter_m) +
                      " m, crown radius " + num(c.crown_radius_m) +
                      " m; ENU (x east, y north, z up), metres, base at the origin",
                  mtllib);
}

std::string header_lines(const Scene& s) {
    return "Run: " + s.source + ", snapshot " + std::to_string(s.snapshot) + " (year " +
           std::to_string(s.year) + "), " + std::to_string(s.trees.size()) + " trees, terrain " +
           std::to_string(s.terrain.nx()) + " x " + std::to_string(s.terrain.ny()) + " cells of " +
           num(s.terrain.cell_size()) + " m from (" + num(s.terrain.grid().origin_x_m) + ", " +
           num(s.terrain.grid().origin_y_m) + ") m.\n\nFrame: positions are local, about (" +
           num(s.frame.origin_x_m) + ", " + num(s.frame.origin_y_m) +
           ") m of the run's frame (add it back for the run's or the map's coordinates; "
           "frame.json holds it with the coordinate system" +
           (s.frame.crs_wkt.empty() ? ": none, a generated terrain" : "") + ").\n";
}

std::string notes_text(const OutputFolder& folder) {
    std::string t;
    for (const auto& n : folder.notes()) t += "- " + n + "\n";
    return t.empty() ? "" : "\n## Notes\n\n" + t;
}

/// A square raster of side `side` cells over the same extent as z (first and last samples on its
/// outermost cell centres), bilinear.
RasterD resample_square(const RasterD& z, int side) {
    const double span = (z.nx() - 1) * z.cell_size();
    const double h = span / (side - 1);
    GridSpec g{side, side, h, z.grid().x_of(0) - 0.5 * h, z.grid().y_of(0) - 0.5 * h};
    RasterD out(g, 0.0);
    for (int j = 0; j < side; ++j)
        for (int i = 0; i < side; ++i) out(i, j) = z.sample_bilinear(g.x_of(i), g.y_of(j));
    return out;
}

void require_square(const RasterD& z, const std::string& format) {
    if (z.nx() != z.ny())
        throw InputError("--format " + format + ": the terrain is " + std::to_string(z.nx()) +
                         " x " + std::to_string(z.ny()) + " cells; " + format +
                         " landscapes are square: cut a square with --region X0,Y0,X1,Y1");
}

/// Leaves out of the size classes the trees that take a user's mesh.
std::function<bool(const Tree&)> has_user_mesh(const ExportOptions& opt) {
    if (!opt.user) return nullptr;
    const UserMeshes* u = opt.user;
    return [u](const Tree& t) { return u->find(t.species, t.stage) != nullptr; };
}

/// Copies a user's OBJ (as NAME.obj) and its material libraries into `dir` of the folder.
void copy_user_mesh(OutputFolder& folder, const std::string& dir, const UserMesh& m) {
    folder.write(dir + m.name + ".obj", io::read_text(m.obj));
    // Checked again as they are read: the file may have changed since it was loaded.
    for (const auto& l : m.mtl) folder.write(dir + l, io::read_text(checked_mtllib(m.obj, 0, l)));
}

double user_scale(const Tree& t, const UserMesh& m) {
    return std::max(t.height_m, 1e-3) / m.height_m;
}

json read_json_file(const fs::path& p) {
    std::ifstream in(p);
    return json::parse(in);
}

} // namespace

SceneFormat scene_format_from_name(const std::string& name) {
    for (auto f : {SceneFormat::mavs, SceneFormat::gazebo, SceneFormat::unreal, SceneFormat::gltf})
        if (name == scene_format_name(f)) return f;
    throw InputError("--format " + name + ": unknown; use mavs, gazebo, unreal or gltf");
}

const char* scene_format_name(SceneFormat f) {
    switch (f) {
    case SceneFormat::mavs:
        return "mavs";
    case SceneFormat::gazebo:
        return "gazebo";
    case SceneFormat::unreal:
        return "unreal";
    case SceneFormat::gltf:
        return "gltf";
    }
    return "gltf";
}

std::vector<UserGroup> user_groups(const Scene& s, const UserMeshes* user) {
    std::vector<UserGroup> out;
    if (!user) return out;
    for (const auto& m : user->meshes()) out.push_back({&m, {}});
    for (std::size_t i = 0; i < s.trees.size(); ++i)
        if (const UserMesh* m = user->find(s.trees[i].species, s.trees[i].stage))
            out[static_cast<std::size_t>(m - user->meshes().data())].trees.push_back(i);
    std::erase_if(out, [](const UserGroup& g) { return g.trees.empty(); });
    return out;
}

std::vector<Prototype> prototypes(const Scene& s, const UserMeshes* user) {
    std::map<std::pair<int, int>, Prototype> by;
    for (std::size_t i = 0; i < s.trees.size(); ++i) {
        const Tree& t = s.trees[i];
        if (user && user->find(t.species, t.stage)) continue;
        auto& p = by[{t.species, static_cast<int>(t.stage)}];
        p.species = t.species;
        p.stage = t.stage;
        p.trees.push_back(i);
    }
    std::vector<Prototype> out;
    for (auto& [k, p] : by) {
        p.name = file_safe(s.species[static_cast<std::size_t>(p.species)].name) + "_" +
                 stage_name(p.stage);
        out.push_back(std::move(p));
    }
    return out;
}

namespace {

/// MAVS derives an instance's stem diameter from the sum of its world z-bounds (mavs.md s1.2
/// item 5): the scene is shifted so that the stems stand near z = 0. Returns the shift, m, and
/// notes how large MAVS's inflation of the override diameter remains.
double mavs_height_offset(const Scene& s, OutputFolder& folder) {
    double offset = 0;
    if (!s.trees.empty()) {
        for (const auto& t : s.trees) offset += t.z_m;
        offset /= static_cast<double>(s.trees.size());
    } else {
        offset = s.terrain.array().mean();
    }
    double worst = 1; // over the stems with a DBH (seedlings push with next to no force)
    for (const auto& t : s.trees)
        if (t.dbh_m > 0)
            worst = std::max(worst, std::abs(2 * (t.z_m - offset) + t.height_m) / t.height_m);
    folder.note("heights are shifted by " + num(-offset) +
                " m so that stems stand near z = 0 (MAVS inflates a stem's override diameter by "
                "(2 z0 + H) / H for a base at z0); the largest such factor among stems with a DBH "
                "here is " +
                num(worst) + (worst > 1.05 ? " (hilly: MAVS will overstate override forces)" : ""));
    return offset;
}

/// The `Objects` of a MAVS scene, its vegetation override entries and its truth file.
struct MavsObjects {
    json objects = json::array(), veg = json::array();
    std::string truth;
};

void add_mavs_user_meshes(const Scene& s, OutputFolder& folder, const ExportOptions& opt,
                          double offset, MavsObjects& o) {
    for (const auto& g : user_groups(s, opt.user)) {
        const UserMesh& u = *g.mesh;
        copy_user_mesh(folder, "meshes/", u);
        const std::string mesh = "meshes/" + u.name + ".obj";
        json inst = json::array();
        double ratio = 0;
        for (const auto i : g.trees) {
            const Tree& t = s.trees[i];
            const double k = user_scale(t, u);
            inst.push_back({{"YawPitchRoll", {t.yaw_rad, 0.0, 0.0}},
                            {"Position", {t.x_m, t.y_m, t.z_m - offset}},
                            {"Scale", {k, k, k}}});
            ratio += stem_diameter_m(t) / std::max(t.height_m, 1e-3);
            o.truth += num(t.x_m) + " " + num(t.y_m) + " " + num(t.height_m) + " " +
                       std::to_string(t.species + 1) + " " + mesh + "\n";
        }
        ratio /= static_cast<double>(g.trees.size());
        o.objects.push_back(
            {{"Mesh", mesh}, {"Rotate Y to Z", u.rotate_y_to_z}, {"Instances", inst}});
        o.veg.push_back({{"mesh", mesh}, {"height", u.height_m}, {"diameter", ratio * u.height_m}});
    }
}

void add_mavs_size_classes(const Scene& s, OutputFolder& folder, const ExportOptions& opt,
                           double offset, MavsObjects& o) {
    for (const auto& c : size_classes(s, has_user_mesh(opt))) {
        const std::string mesh = "meshes/" + c.name + ".obj";
        folder.write(mesh, tree_obj(s, c, "trees.mtl"));
        json inst = json::array();
        double ratio = 0; // mean stem diameter / height of the class's trees
        for (const auto i : c.trees) {
            const Tree& t = s.trees[i];
            inst.push_back({{"YawPitchRoll", {t.yaw_rad, 0.0, 0.0}},
                            {"Position", {t.x_m, t.y_m, t.z_m - offset}},
                            {"Scale", {1.0, 1.0, std::max(t.height_m, 1e-3) / c.height_m}}});
            ratio += stem_diameter_m(t) / std::max(t.height_m, 1e-3);
            o.truth += num(t.x_m) + " " + num(t.y_m) + " " + num(t.height_m) + " " +
                       std::to_string(c.species + 1) + " " + mesh + "\n";
        }
        ratio /= static_cast<double>(c.trees.size());
        o.objects.push_back({{"Mesh", mesh}, {"Rotate Y to Z", false}, {"Instances", inst}});
        // MAVS: d = diameter * (instance height) / height, so d follows each tree's height.
        o.veg.push_back({{"mesh", mesh}, {"height", c.height_m}, {"diameter", ratio * c.height_m}});
    }
}

/// The ground layer's tufts: one mesh per grass species; MAVS's own oat grass has a 1 cm stem in
/// its override file (reference mobility.md s1.2), and so do these.
void add_mavs_tufts(const Scene& s, OutputFolder& folder, double offset, MavsObjects& o) {
    for (const auto& [k, tufts] : tuft_groups(s)) {
        const std::string mesh = "meshes/" + tuft_mesh_name(s, k) + ".obj";
        folder.write(mesh, tuft_obj(s, s.tufts[tufts[0]], "trees.mtl"));
        json inst = json::array();
        for (const auto i : tufts) {
            const Tuft& t = s.tufts[i];
            inst.push_back({{"YawPitchRoll", {t.yaw_rad, 0.0, 0.0}},
                            {"Position", {t.x_m, t.y_m, t.z_m - offset}},
                            {"Scale", {1.0, 1.0, 1.0}}});
        }
        o.objects.push_back({{"Mesh", mesh}, {"Rotate Y to Z", false}, {"Instances", inst}});
        o.veg.push_back({{"mesh", mesh},
                         {"height", s.tufts[tufts[0]].height_m},
                         {"diameter", kTuftStemDiameterM}});
    }
}

void write_mavs_readme(const Scene& s, OutputFolder& folder, double offset) {
    folder.write(
        "README.md",
        "# MAVS scene from ecoterra\n\n" + header_lines(s) +
            "\nFrame: ENU (x east, y north, z up), metres, as MAVS uses; heights shifted by " +
            num(-offset) +
            " m (add it back for the run's elevations).\n\n"
            "| file | what |\n|---|---|\n"
            "| scene.json | MAVS scene: `Surface Mesh` (the terrain), `Objects` (one entry per "
            "tree "
            "mesh with its instances: `YawPitchRoll` in radians as MAVS's loader reads them, "
            "`Position` m, `Scale` [1, 1, H / mesh height]), `VegOverrideFile` |\n"
            "| terrain.obj, terrain.mtl | the terrain mesh, metres |\n"
            "| meshes/*.obj, meshes/trees.mtl | one tree mesh per species, life stage and 5 % size "
            "class (trunk and crown; ecoterra's own geometry) |\n"
            "| veg_override.json | MAVS vegetation override: per mesh its `height` (m) and "
            "`diameter` (m), so that MAVS's stem diameter, diameter x instance height / height, "
            "is each tree's DBH to within its class |\n"
            "| truth.txt | one tree per line: x y height speciesNum meshPath (MAVS's truth "
            "format) |\n" +
            (s.deadwood.empty()
                 ? std::string()
                 : "| meshes/deadwood.obj | the dead wood: " + std::to_string(s.deadwood.size()) +
                       " snags, logs, stumps and pieces of slash in one mesh in the scene's frame "
                       "(one instance at the origin), solid: not in veg_override.json |\n") +
            (s.tufts.empty()
                 ? std::string()
                 : "| meshes/*_grass.obj | the ground layer: " + std::to_string(s.tufts.size()) +
                       " grass tufts in `Objects` (one mesh per grass species, scale 1), with a "
                       "1 cm stem in veg_override.json (MAVS's own oat grass); not in truth.txt "
                       "|\n") +
            "\nLoad: `scene.json` as a MAVS scene (`PathToMeshes` is this folder's absolute path; "
            "edit it if you move the folder). Enable the override with `\"Using Veg Forces\": "
            "true` in the vehicle file.\n" +
            notes_text(folder));
}

} // namespace

void write_mavs(const Scene& s, OutputFolder& folder, const ExportOptions& opt) {
    const double offset = mavs_height_offset(s, folder);
    const Mesh ground = terrain_mesh(s.terrain, opt.terrain_step, offset);
    folder.write("terrain.mtl", to_mtl({{"ground", kGroundColour}}));
    folder.write("terrain.obj",
                 to_obj({{&ground, "ground"}},
                        "ecoterra terrain: ENU (x east, y north, z up), metres, z shifted by " +
                            num(-offset) + " m",
                        "terrain.mtl"));
    folder.write("meshes/trees.mtl", to_mtl(tree_materials(s)));
    MavsObjects o;
    add_mavs_user_meshes(s, folder, opt, offset, o);
    add_mavs_size_classes(s, folder, opt, offset, o);
    add_mavs_tufts(s, folder, offset, o);
    if (!s.deadwood.empty()) {
        // Dead wood: one mesh in the scene's frame, one instance at the origin (solid: not in the
        // vegetation override).
        const Mesh dead = deadwood_mesh(s, offset);
        folder.write("meshes/deadwood.mtl", to_mtl({{"deadwood", kDeadWoodColour}}));
        folder.write("meshes/deadwood.obj",
                     to_obj({{&dead, "deadwood"}},
                            "ecoterra dead wood: " + std::to_string(s.deadwood.size()) +
                                " snags, logs, stumps and slash; ENU metres, z shifted by " +
                                num(-offset) + " m",
                            "deadwood.mtl"));
        o.objects.push_back({{"Mesh", "meshes/deadwood.obj"},
                             {"Rotate Y to Z", false},
                             {"Instances", json::array({json{{"YawPitchRoll", {0.0, 0.0, 0.0}},
                                                             {"Position", {0.0, 0.0, 0.0}},
                                                             {"Scale", {1.0, 1.0, 1.0}}}})}});
    }
    // One separator between the folder and the names MAVS appends ("out/" given as -o must not
    // become "out//").
    const fs::path abs =
        fs::absolute(opt.final_dir.empty() ? folder.dir() : opt.final_dir).lexically_normal() / "";
    json scene = {{"PathToMeshes", abs.string()},
                  {"UseFullPaths", false},
                  {"Surface Mesh",
                   {{{"Mesh", "terrain.obj"},
                     {"Rotate Y to Z", false},
                     {"YawPitchRoll", {0.0, 0.0, 0.0}},
                     {"Position", {0.0, 0.0, 0.0}},
                     {"Scale", {1.0, 1.0, 1.0}},
                     {"Material", "dry"},
                     {"Cone Index", 250.0}}}},
                  {"Objects", o.objects},
                  {"VegOverrideFile", (abs / "veg_override.json").string()}};
    folder.write("scene.json", scene.dump(1) + "\n");
    folder.write("veg_override.json", json({{"veg_models", o.veg}}).dump(1) + "\n");
    folder.write("truth.txt", o.truth);
    write_mavs_readme(s, folder, offset);
}

namespace {

/// A Gazebo world being written: the SDF text, the models and their includes.
class GazeboWorld {
public:
    GazeboWorld(const Scene& s, OutputFolder& folder) : m_s(s), m_folder(folder) {}
    /// The heightmap PNG and the world's terrain model; notes a resampling and left-out tufts.
    void add_terrain();
    /// A user's mesh: one model per 5 % height class (an include cannot scale its model).
    void add_user_meshes(const ExportOptions& opt);
    void add_size_classes(const ExportOptions& opt);
    /// The dead wood as one static model of the world, a link per piece with a cylinder for
    /// collision and sight.
    void add_deadwood();
    void finish();

private:
    void include(const std::string& model, const Tree& t) {
        m_world += "    <include><uri>model://" + model + "</uri><name>plant_" +
                   std::to_string(t.id) + "</name><pose>" + num(t.x_m) + " " + num(t.y_m) + " " +
                   num(t.z_m) + " 0 0 " + num(t.yaw_rad) +
                   "</pose><static>true</static></include>\n";
    }
    void model_files(const std::string& name, const std::string& description,
                     const std::string& collision, const std::string& visual);
    const Scene& m_s;
    OutputFolder& m_folder;
    std::string m_world;
};

void GazeboWorld::add_terrain() {
    std::vector<std::string> warnings;
    terrain::io::WriteOptions wo;
    wo.warnings = &warnings;
    const fs::path png = m_folder.staged_path("terrain.png");
    m_folder.staged_path("terrain.png.json");
    terrain::io::write_gazebo_png(m_s.terrain, png, wo);
    for (const auto& w : warnings)
        if (w.find("resampled") != std::string::npos) m_folder.note(w.substr(w.find(": ") + 2));
    if (!m_s.tufts.empty())
        m_folder.note("the ground layer's " + std::to_string(m_s.tufts.size()) +
                      " grass tufts are left out: a Gazebo world includes a model per object, "
                      "and thousands of includes make the world slow to load (glTF, MAVS and "
                      "Unreal exports hold them)");
    const json side = read_json_file(terrain::io::png_sidecar_path(png));
    const auto& gz = side.at("gazebo");
    auto v3 = [&](const json& a) {
        return num(a[0].get<double>()) + " " + num(a[1].get<double>()) + " " +
               num(a[2].get<double>());
    };
    const std::string heightmap = "<heightmap><uri>terrain.png</uri><size>" + v3(gz.at("size_m")) +
                                  "</size><pos>" + v3(gz.at("pos_m")) + "</pos></heightmap>";
    m_world = "<?xml version=\"1.0\"?>\n<sdf version=\"1.9\">\n  <world name=\"ecoterra\">\n"
              "    <light type=\"directional\" name=\"sun\">\n"
              "      <direction>-0.5 0.1 -0.9</direction>\n    </light>\n"
              "    <model name=\"terrain\">\n      <static>true</static>\n"
              "      <link name=\"link\">\n        <collision name=\"collision\">"
              "<geometry>" +
              heightmap + "</geometry></collision>\n        <visual name=\"visual\"><geometry>" +
              heightmap + "</geometry></visual>\n      </link>\n    </model>\n";
}

void GazeboWorld::model_files(const std::string& name, const std::string& description,
                              const std::string& collision, const std::string& visual) {
    const std::string dir = "models/" + name + "/";
    m_folder.write(dir + "model.config",
                   "<?xml version=\"1.0\"?>\n<model>\n  <name>" + name +
                       "</name>\n  <version>1.0</version>\n  <sdf version=\"1.9\">model.sdf</sdf>"
                       "\n  <description>" +
                       description + "</description>\n</model>\n");
    m_folder.write(dir + "model.sdf",
                   "<?xml version=\"1.0\"?>\n<sdf version=\"1.9\">\n  <model name=\"" + name +
                       "\">\n    <static>true</static>\n    <link name=\"link\">\n" + collision +
                       visual + "    </link>\n  </model>\n</sdf>\n");
}

void GazeboWorld::add_user_meshes(const ExportOptions& opt) {
    const double lq = std::log(kSizeClassRatio);
    for (const auto& g : user_groups(m_s, opt.user)) {
        const UserMesh& u = *g.mesh;
        std::map<int, std::vector<std::size_t>> by_height;
        for (const auto i : g.trees)
            by_height[static_cast<int>(
                          std::lround(std::log(std::max(m_s.trees[i].height_m, 1e-3)) / lq))]
                .push_back(i);
        for (const auto& [kh, trees] : by_height) {
            const std::string name =
                u.name + "_h" + (kh < 0 ? "m" : "") + std::to_string(std::abs(kh));
            const double k = std::pow(kSizeClassRatio, kh) / u.height_m;
            copy_user_mesh(m_folder, "models/" + name + "/meshes/", u);
            model_files(name, "user mesh " + u.obj.filename().string() + ", scaled " + num(k), "",
                        "      <visual name=\"tree\">\n        <pose>0 0 0 " +
                            std::string(u.rotate_y_to_z ? "1.5707963267948966" : "0") +
                            " 0 0</pose>\n        <geometry><mesh><uri>model://" + name +
                            "/meshes/" + u.name + ".obj</uri><scale>" + num(k) + " " + num(k) +
                            " " + num(k) + "</scale></mesh></geometry>\n      </visual>\n");
            for (const auto i : trees) include(name, m_s.trees[i]);
        }
    }
}

void GazeboWorld::add_size_classes(const ExportOptions& opt) {
    const std::string mtl = to_mtl(tree_materials(m_s));
    for (const auto& c : size_classes(m_s, has_user_mesh(opt))) {
        const std::string dir = "models/" + c.name + "/";
        m_folder.write(dir + "meshes/tree.mtl", mtl);
        m_folder.write(dir + "meshes/tree.obj", tree_obj(m_s, c, "tree.mtl"));
        // Collision: the trunk only, a cylinder of the trunk's mean diameter; the crown is visual
        // (cameras and lidar see it, vehicles pass through).
        const double r = 0.5 * c.base_diameter_m * (1 + kTopDiameterFraction) / 2;
        model_files(c.name,
                    "ecoterra tree: " + m_s.species[static_cast<std::size_t>(c.species)].name +
                        ", " + stage_name(c.stage),
                    "      <collision name=\"trunk\">\n        <pose>0 0 " + num(0.5 * c.height_m) +
                        " 0 0 0</pose>\n        <geometry><cylinder><radius>" + num(r) +
                        "</radius><length>" + num(c.height_m) +
                        "</length></cylinder></geometry>\n      </collision>\n",
                    "      <visual name=\"tree\">\n        <geometry><mesh><uri>model://" + c.name +
                        "/meshes/tree.obj</uri></mesh></geometry>\n      </visual>\n");
        for (const auto i : c.trees) include(c.name, m_s.trees[i]);
    }
}

void GazeboWorld::add_deadwood() {
    if (m_s.deadwood.empty()) return;
    m_world += "    <model name=\"deadwood\">\n      <static>true</static>\n";
    for (const auto& d : m_s.deadwood) {
        const double len = std::max(d.length_m, 1e-3);
        // A stump or root plate at its diameter; a stem or top at its mean diameter, as a
        // trunk's collision.
        const bool whole = d.piece == 1 || d.piece == 4;
        const double r =
            0.5 * std::max(d.diameter_m, 1e-3) * (whole ? 1.0 : (1 + kTopDiameterFraction) / 2);
        std::string pose;
        if (d.standing) {
            pose = num(d.x_m) + " " + num(d.y_m) + " " + num(d.z_m + 0.5 * len) + " 0 0 0";
        } else {
            // The cylinder's axis (z) pitched onto x, then turned to the azimuth; its top at the
            // piece's height above the ground.
            const double c = std::cos(d.azimuth_rad), s = std::sin(d.azimuth_rad);
            pose = num(d.x_m + 0.5 * len * c) + " " + num(d.y_m + 0.5 * len * s) + " " +
                   num(d.z_m + d.top_height_m - std::max(d.diameter_m, 1e-3) / 2) +
                   " 0 1.5707963267948966 " + num(d.azimuth_rad);
        }
        const std::string geometry = "<geometry><cylinder><radius>" + num(r) + "</radius><length>" +
                                     num(len) + "</length></cylinder></geometry>";
        m_world += "      <link name=\"piece_" + std::to_string(d.id) + "_" +
                   dead_piece_name(d.piece) + "\">\n        <pose>" + pose +
                   "</pose>\n        <collision name=\"collision\">" + geometry +
                   "</collision>\n        <visual name=\"visual\">" + geometry +
                   "</visual>\n      </link>\n";
    }
    m_world += "    </model>\n";
}

void GazeboWorld::finish() {
    const Scene& s = m_s;
    OutputFolder& folder = m_folder;
    m_world += "  </world>\n</sdf>\n";
    folder.write("world.sdf", m_world);
    folder.write(
        "README.md",
        "# Gazebo world from ecoterra\n\n" + header_lines(s) +
            "\nFrame: ENU (x east, y north, z up), metres, as Gazebo uses; elevations as in the "
            "run.\n\n| file | what |\n|---|---|\n"
            "| world.sdf | SDF 1.9 world: the terrain as a `<heightmap>` (collision and visual) "
            "and "
            "one static `<include>` per tree (`<name>plant_ID</name>`, pose x y z 0 0 yaw) |\n"
            "| terrain.png, terrain.png.json | 16-bit heightmap, square of side 2^n + 1 (its size "
            "and height range are in world.sdf and the sidecar) |\n"
            "| models/NAME/ | one model per species, life stage and 5 % size class: model.config, "
            "model.sdf (collision: the trunk as a cylinder; visual: trunk and crown mesh), "
            "meshes/tree.obj |\n\n"
            "Load: `GZ_SIM_RESOURCE_PATH=$PWD/models gz sim world.sdf` (Gazebo Sim), or "
            "`GAZEBO_MODEL_PATH=$PWD/models gazebo world.sdf` (Gazebo Classic), from this "
            "folder.\n" +
            notes_text(folder));
}

/// The Unreal landscape: the terrain resampled to a size Unreal accepts, as a 16-bit PNG, and
/// where its import puts it.
struct UnrealLandscape {
    RasterD land;
    double scale_m = 0, offset_m = 0; ///< elevation = offset + scale x count
    double z_scale = 0, xy_scale = 0, loc_x = 0, loc_y = 0, loc_z = 0;
};

UnrealLandscape write_unreal_landscape(const Scene& s, OutputFolder& folder) {
    UnrealLandscape l;
    l.land = s.terrain;
    if (!terrain::io::is_unreal_landscape_size(l.land.nx())) {
        int side = l.land.nx();
        while (!terrain::io::is_unreal_landscape_size(side)) ++side;
        l.land = resample_square(s.terrain, side);
        folder.note("the terrain (" + std::to_string(s.terrain.nx()) + " x " +
                    std::to_string(s.terrain.ny()) + ") was resampled to " + std::to_string(side) +
                    " x " + std::to_string(side) +
                    ", the next size Unreal Engine accepts, over the same extent");
    }
    const fs::path png = folder.staged_path("landscape.png");
    folder.staged_path("landscape.png.json");
    terrain::io::write_png16(l.land, png, {});
    const json side = read_json_file(terrain::io::png_sidecar_path(png));
    l.scale_m = side.at("vertical_scale_m").get<double>();
    l.offset_m = side.at("vertical_offset_m").get<double>();
    l.z_scale = l.scale_m * kCmPerM * kUnrealZCountsPerPercent;
    l.xy_scale = l.land.cell_size() * kCmPerM;
    // The PNG's first pixel is the north-west cell centre; Unreal's Y points south.
    l.loc_x = l.land.grid().x_of(0) * kCmPerM;
    l.loc_y = -l.land.grid().y_of(l.land.ny() - 1) * kCmPerM;
    l.loc_z = (l.offset_m + l.scale_m * kUnrealZeroCount) * kCmPerM;
    return l;
}

/// trees.csv (a DataTable for PCG) and the tree meshes.
void write_unreal_trees(const Scene& s, OutputFolder& folder, const ExportOptions& opt) {
    std::string csv = "Name,species,stage,mesh,x_cm,y_cm,z_cm,yaw_deg,scale_x,scale_y,scale_z,"
                      "dbh_cm,height_m,crown_radius_m,collision_radius_cm\n";
    auto row = [&](const Tree& t, const std::string& mesh, std::array<double, 3> scale) {
        csv += "plant_" + std::to_string(t.id) + "," +
               csv_field(s.species[static_cast<std::size_t>(t.species)].name) + "," +
               stage_name(t.stage) + "," + mesh + "," + num(t.x_m * kCmPerM) + "," +
               num(-t.y_m * kCmPerM) + "," + num(t.z_m * kCmPerM) + "," +
               num(-rad_to_deg(t.yaw_rad)) + "," + num(scale[0]) + "," + num(scale[1]) + "," +
               num(scale[2]) + "," + num(t.dbh_m * kCmPerM) + "," + num(t.height_m) + "," +
               num(t.crown_radius_m) + "," + num(0.5 * stem_diameter_m(t) * kCmPerM) + "\n";
    };
    for (const auto& g : user_groups(s, opt.user)) {
        copy_user_mesh(folder, "meshes/", *g.mesh);
        for (const auto i : g.trees) {
            const double k = user_scale(s.trees[i], *g.mesh);
            row(s.trees[i], g.mesh->name, {k, k, k});
        }
    }
    for (const auto& c : size_classes(s, has_user_mesh(opt))) {
        folder.write("meshes/" + c.name + ".obj", tree_obj(s, c, "trees.mtl"));
        for (const auto i : c.trees)
            row(s.trees[i], c.name, {1, 1, std::max(s.trees[i].height_m, 1e-3) / c.height_m});
    }
    folder.write("trees.csv", csv);
}

/// grass.csv and the tuft meshes of the ground layer (nothing without one).
void write_unreal_grass(const Scene& s, OutputFolder& folder) {
    std::string grass = "Name,species,mesh,x_cm,y_cm,z_cm,yaw_deg,height_m,base_radius_m\n";
    for (const auto& [k, tufts] : tuft_groups(s)) {
        folder.write("meshes/" + tuft_mesh_name(s, k) + ".obj",
                     tuft_obj(s, s.tufts[tufts[0]], "trees.mtl"));
        for (const auto i : tufts) {
            const Tuft& t = s.tufts[i];
            grass += "tuft_" + std::to_string(i) + "," +
                     csv_field(s.species[static_cast<std::size_t>(k)].name) + "," +
                     tuft_mesh_name(s, k) + "," + num(t.x_m * kCmPerM) + "," +
                     num(-t.y_m * kCmPerM) + "," + num(t.z_m * kCmPerM) + "," +
                     num(-rad_to_deg(t.yaw_rad)) + "," + num(t.height_m) + "," + num(t.radius_m) +
                     "\n";
        }
    }
    if (!s.tufts.empty()) folder.write("grass.csv", grass);
}

/// deadwood.csv and the unit trunk mesh (nothing without dead wood): one row per piece, the trunk
/// (base at the origin, axis +Z, 1 m long and 1 m across at the base) scaled to the piece, standing
/// at its base or pitched -90 degrees (its axis onto +X) and yawed onto its azimuth, its axis at
/// the piece's top height less half its diameter.
void write_unreal_deadwood(const Scene& s, OutputFolder& folder) {
    if (s.deadwood.empty()) return;
    std::string csv = "Name,species,piece,decay_class,mesh,x_cm,y_cm,z_cm,pitch_deg,yaw_deg,"
                      "scale_x,scale_y,scale_z,diameter_m,length_m,top_height_m\n";
    for (const auto& d : s.deadwood) {
        const double dia = std::max(d.diameter_m, 1e-3), len = std::max(d.length_m, 1e-3);
        const double z = d.z_m + (d.standing ? 0.0 : d.top_height_m - 0.5 * dia);
        csv += "deadwood_" + std::to_string(d.id) + "_" + dead_piece_name(d.piece) + "," +
               csv_field(s.species[static_cast<std::size_t>(d.species)].name) + "," +
               dead_piece_name(d.piece) + "," + std::to_string(d.decay_class) + ",deadwood," +
               num(d.x_m * kCmPerM) + "," + num(-d.y_m * kCmPerM) + "," + num(z * kCmPerM) + "," +
               (d.standing ? "0" : "-90") + "," +
               num(d.standing ? 0.0 : -rad_to_deg(d.azimuth_rad)) + "," + num(dia) + "," +
               num(dia) + "," + num(len) + "," + num(d.diameter_m) + "," + num(d.length_m) + "," +
               num(d.standing ? d.length_m : d.top_height_m) + "\n";
    }
    folder.write("deadwood.csv", csv);
    const Mesh unit = unit_trunk();
    folder.write("meshes/deadwood.mtl", to_mtl({{"deadwood", kDeadWoodColour}}));
    folder.write("meshes/deadwood.obj",
                 to_obj({{&unit, "deadwood"}},
                        "ecoterra dead wood: the unit trunk (base at the origin, axis +Z, 1 m)",
                        "deadwood.mtl"));
}

void write_unreal_readme(const Scene& s, OutputFolder& folder, const UnrealLandscape& l) {
    const RasterD& land = l.land;
    const double offset_m = l.offset_m, scale_m = l.scale_m, loc_x = l.loc_x, loc_y = l.loc_y,
                 loc_z = l.loc_z, xy_scale = l.xy_scale, z_scale = l.z_scale;
    folder.write(
        "README.md",
        "# Unreal Engine scene from ecoterra\n\n" + header_lines(s) +
            "\nUnreal axes: left-handed, Z up, centimetres. A run point (x east, y north, z up, "
            "m) is (100 x, -100 y, 100 z) cm in Unreal; a yaw t counter-clockwise from east is "
            "-t degrees in Unreal.\n\n| file | what |\n|---|---|\n"
            "| landscape.png | 16-bit landscape heightmap, " +
            std::to_string(land.nx()) + " x " + std::to_string(land.ny()) +
            " (an Unreal landscape size), first row north |\n"
            "| landscape.png.json | its encoding: elevation_m = " +
            num(offset_m) + " + " + num(scale_m) +
            " x pixel |\n"
            "| trees.csv | a DataTable (row name first) for PCG's Load Data Table: species, "
            "stage, mesh, position (cm, Unreal axes), yaw_deg, scale (z scale = height / mesh "
            "height), DBH (cm), height (m), crown radius (m), collision radius (cm, the trunk) |\n"
            "| meshes/*.obj, trees.mtl | tree meshes per species, stage and 5 % size class, "
            "metres, Z up: import with a uniform scale of 100 |\n" +
            (s.tufts.empty()
                 ? std::string()
                 : "| grass.csv, meshes/*_grass.obj | the ground layer as " +
                       std::to_string(s.tufts.size()) +
                       " grass tufts (visual only, passable), a table like trees.csv |\n") +
            (s.deadwood.empty()
                 ? std::string()
                 : "| deadwood.csv, meshes/deadwood.obj | the dead wood as " +
                       std::to_string(s.deadwood.size()) +
                       " pieces (solid): the unit trunk (axis +Z, 1 m) scaled by scale_x/y/z "
                       "(m), a lying piece rotated by Pitch pitch_deg then Yaw yaw_deg "
                       "(FRotator), its axis at z_cm |\n") +
            "\n"
            "Landscape import: Location X " +
            num(loc_x) + ", Y " + num(loc_y) + ", Z " + num(loc_z) + " cm; Scale X " +
            num(xy_scale) + ", Y " + num(xy_scale) + ", Z " + num(z_scale) +
            " (Unreal puts count 32768 at the actor's Z, 1/128 cm per count at Z scale 100).\n" +
            notes_text(folder));
}

} // namespace

void write_gazebo(const Scene& s, OutputFolder& folder, const ExportOptions& opt) {
    require_square(s.terrain, "gazebo");
    GazeboWorld w(s, folder);
    w.add_terrain();
    w.add_user_meshes(opt);
    w.add_size_classes(opt);
    w.add_deadwood();
    w.finish();
}

void write_unreal(const Scene& s, OutputFolder& folder, const ExportOptions& opt) {
    require_square(s.terrain, "unreal");
    const UnrealLandscape l = write_unreal_landscape(s, folder);
    folder.write("meshes/trees.mtl", to_mtl(tree_materials(s)));
    write_unreal_trees(s, folder, opt);
    write_unreal_grass(s, folder);
    write_unreal_deadwood(s, folder);
    write_unreal_readme(s, folder, l);
}

void write_scene(const Scene& s, SceneFormat format, OutputFolder& folder,
                 const ExportOptions& opt) {
    folder.write("frame.json", s.frame.to_json().dump(2) + "\n");
    switch (format) {
    case SceneFormat::mavs:
        write_mavs(s, folder, opt);
        break;
    case SceneFormat::gazebo:
        write_gazebo(s, folder, opt);
        break;
    case SceneFormat::unreal:
        write_unreal(s, folder, opt);
        break;
    case SceneFormat::gltf:
        folder.write("scene.glb", glb_bytes(s, opt));
        folder.write("README.md", "# glTF scene from ecoterra\n\n" + header_lines(s) +
                                      "\nscene.glb: glTF 2.0 binary, +Y up, metres; see "
                                      "docs/exports.md.\n");
        break;
    }
}

} // namespace ecoterra::exporter
