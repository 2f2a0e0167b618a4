// glTF 2.0 binary writer (https://registry.khronos.org/glTF/specs/2.0/glTF-2.0.html), written
// with nlohmann-json for the JSON chunk: the file is small and regular enough that a general
// glTF library buys nothing; the Khronos validator checks the result in the tests.
//
// Axes: glTF is right-handed, +Y up, metres. A point (x east, y north, z up) of the run becomes
// (x, z, -y); a yaw t about the run's up axis becomes a rotation by t about +Y.
#include "ecoterra/export/formats.hpp"
#include "ecoterra/export/mesh.hpp"

#include "ecoterra/error.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstring>
#include <functional>
#include <limits>

namespace ecoterra::exporter {

namespace {

using nlohmann::json;

constexpr int kFloat = 5126, kUint32 = 5125;
constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;

std::array<float, 3> to_gltf(const std::array<float, 3>& p) {
    return {p[0], p[2], -p[1]};
}

class GlbBuilder {
public:
    json j = json::object();
    std::string bin;

    /// A buffer view and accessor over `count` elements of `type` ("VEC3", ...), floats.
    int accessor(const std::vector<float>& data, int count, const char* type, int target,
                 bool minmax = false) {
        const int components = static_cast<int>(data.size()) / std::max(count, 1);
        const int view = add_view(data.data(), data.size() * sizeof(float), target);
        json a = {
            {"bufferView", view}, {"componentType", kFloat}, {"count", count}, {"type", type}};
        if (minmax && count > 0) {
            std::vector<float> lo(components, std::numeric_limits<float>::max()),
                hi(components, std::numeric_limits<float>::lowest());
            for (int k = 0; k < count; ++k)
                for (int c = 0; c < components; ++c) {
                    lo[c] = std::min(lo[c], data[static_cast<std::size_t>(k * components + c)]);
                    hi[c] = std::max(hi[c], data[static_cast<std::size_t>(k * components + c)]);
                }
            a["min"] = lo;
            a["max"] = hi;
        }
        j["accessors"].push_back(a);
        return static_cast<int>(j["accessors"].size()) - 1;
    }
    int indices(const std::vector<std::uint32_t>& idx) {
        const int view =
            add_view(idx.data(), idx.size() * sizeof(std::uint32_t), kElementArrayBuffer);
        j["accessors"].push_back({{"bufferView", view},
                                  {"componentType", kUint32},
                                  {"count", idx.size()},
                                  {"type", "SCALAR"}});
        return static_cast<int>(j["accessors"].size()) - 1;
    }
    int mesh(const Mesh& m, const std::string& name, int material, const json& extras) {
        std::vector<float> pos, nor;
        for (std::size_t k = 0; k < m.positions.size(); ++k) {
            for (float v : to_gltf(m.positions[k])) pos.push_back(v);
            for (float v : to_gltf(m.normals[k])) nor.push_back(v);
        }
        const int n = static_cast<int>(m.positions.size());
        json prim = {{"attributes",
                      {{"POSITION", accessor(pos, n, "VEC3", kArrayBuffer, true)},
                       {"NORMAL", accessor(nor, n, "VEC3", kArrayBuffer)}}},
                     {"indices", indices(m.indices)},
                     {"material", material},
                     {"mode", 4}};
        j["meshes"].push_back({{"name", name}, {"primitives", {prim}}, {"extras", extras}});
        return static_cast<int>(j["meshes"].size()) - 1;
    }
    int material(const std::string& name, std::array<double, 3> rgb) {
        j["materials"].push_back({{"name", name},
                                  {"pbrMetallicRoughness",
                                   {{"baseColorFactor", {rgb[0], rgb[1], rgb[2], 1.0}},
                                    {"metallicFactor", 0.0},
                                    {"roughnessFactor", 1.0}}}});
        return static_cast<int>(j["materials"].size()) - 1;
    }
    int node(json n) {
        j["nodes"].push_back(std::move(n));
        return static_cast<int>(j["nodes"].size()) - 1;
    }

    std::string finish() {
        j["buffers"] = {{{"byteLength", bin.size()}}};
        std::string text = j.dump();
        while (text.size() % 4) text += ' ';
        std::string out;
        auto u32 = [&](std::uint32_t v) {
            char b[4];
            std::memcpy(b, &v, 4); // glTF is little-endian, as are the machines ecoterra runs on
            out.append(b, 4);
        };
        u32(0x46546C67); // "glTF"
        u32(2);
        u32(static_cast<std::uint32_t>(12 + 8 + text.size() + 8 + bin.size()));
        u32(static_cast<std::uint32_t>(text.size()));
        u32(0x4E4F534A); // "JSON"
        out += text;
        u32(static_cast<std::uint32_t>(bin.size()));
        u32(0x004E4942); // "BIN"
        out += bin;
        return out;
    }

private:
    int add_view(const void* data, std::size_t bytes, int target) {
        while (bin.size() % 4) bin += '\0';
        json v = {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", bytes}};
        if (target) v["target"] = target;
        bin.append(static_cast<const char*>(data), bytes);
        j["bufferViews"].push_back(v);
        return static_cast<int>(j["bufferViews"].size()) - 1;
    }
};

} // namespace

namespace {

std::array<float, 4> yaw_rotation(double yaw) {
    return std::array<float, 4>{0, static_cast<float>(std::sin(0.5 * yaw)), 0,
                                static_cast<float>(std::cos(0.5 * yaw))};
}
template <class T> // a Tree or a Tuft
std::array<float, 3> gltf_position(const T& t) {
    return to_gltf(
        {static_cast<float>(t.x_m), static_cast<float>(t.y_m), static_cast<float>(t.z_m)});
}
/// A scale in the run's axes (x, y, z) as glTF's (x, y up, z).
std::array<float, 3> gltf_scale(const std::array<double, 3>& e) {
    return std::array<float, 3>{static_cast<float>(e[0]), static_cast<float>(e[2]),
                                static_cast<float>(e[1])};
}

/// A mesh of a tree and how it is scaled for each tree.
struct Part {
    int mesh;
    std::function<std::array<double, 3>(const Tree&)> scale;
    std::string suffix;
};

/// The .glb of a scene, built in the order of the buffer's contents: terrain, the user's meshes,
/// the tree prototypes, the grass tufts.
class GlbScene {
public:
    GlbScene(const Scene& s, const ExportOptions& opt) : m_s(s), m_opt(opt) {}
    std::string build();

private:
    void add_terrain();
    /// Places `trees` with these parts: one node per tree (extras per tree), or per part one
    /// instanced node with per-instance attributes.
    void place(const std::vector<std::size_t>& trees, const std::vector<Part>& parts,
               const std::string& name, const json& common);
    void place_nodes(const std::vector<std::size_t>& trees, const std::vector<Part>& parts,
                     const json& common);
    void place_instanced(const std::vector<std::size_t>& trees, const std::vector<Part>& parts,
                         const std::string& name, const json& common);
    void add_user_meshes();
    void add_prototypes();
    void add_tufts(int k, const std::vector<std::size_t>& tufts);
    /// One node per piece of dead wood: the trunk mesh scaled to the piece, laid along its
    /// azimuth when it lies.
    void add_deadwood();

    const Scene& m_s;
    const ExportOptions& m_opt;
    GlbBuilder m_b;
    std::vector<int> m_roots;
    int m_bark = 0;
    bool m_instancing = false;
};

void GlbScene::add_terrain() {
    const int ground = m_b.material("ground", kGroundColour);
    m_bark = m_b.material("bark", kBarkColour);
    m_roots.push_back(m_b.node({{"name", "terrain"},
                                {"mesh", m_b.mesh(terrain_mesh(m_s.terrain, m_opt.terrain_step),
                                                  "terrain", ground, {{"role", "ground"}})}}));
}

void GlbScene::place(const std::vector<std::size_t>& trees, const std::vector<Part>& parts,
                     const std::string& name, const json& common) {
    if (m_opt.gltf_nodes)
        place_nodes(trees, parts, common);
    else
        place_instanced(trees, parts, name, common);
}

void GlbScene::place_nodes(const std::vector<std::size_t>& trees, const std::vector<Part>& parts,
                           const json& common) {
    for (const auto i : trees) {
        const Tree& t = m_s.trees[i];
        json children = json::array();
        for (const auto& p : parts)
            children.push_back(m_b.node({{"mesh", p.mesh}, {"scale", gltf_scale(p.scale(t))}}));
        json extras = common;
        extras.update({{"plant_id", t.id},
                       {"species", m_s.species[static_cast<std::size_t>(t.species)].name},
                       {"stage", stage_name(t.stage)},
                       {"dbh_m", t.dbh_m},
                       {"height_m", t.height_m},
                       {"crown_radius_m", t.crown_radius_m}});
        m_roots.push_back(m_b.node({{"name", "plant_" + std::to_string(t.id)},
                                    {"translation", gltf_position(t)},
                                    {"rotation", yaw_rotation(t.yaw_rad)},
                                    {"children", children},
                                    {"extras", extras}}));
    }
}

void GlbScene::place_instanced(const std::vector<std::size_t>& trees,
                               const std::vector<Part>& parts, const std::string& name,
                               const json& common) {
    m_instancing = true;
    std::vector<float> tr, ro, id, dbh, height, crown;
    for (const auto i : trees) {
        const Tree& t = m_s.trees[i];
        for (float v : gltf_position(t)) tr.push_back(v);
        for (float v : yaw_rotation(t.yaw_rad)) ro.push_back(v);
        id.push_back(static_cast<float>(t.id));
        dbh.push_back(static_cast<float>(t.dbh_m));
        height.push_back(static_cast<float>(t.height_m));
        crown.push_back(static_cast<float>(t.crown_radius_m));
    }
    const int n = static_cast<int>(trees.size());
    const int a_tr = m_b.accessor(tr, n, "VEC3", 0), a_ro = m_b.accessor(ro, n, "VEC4", 0);
    const json meta = {{"_PLANT_ID", m_b.accessor(id, n, "SCALAR", 0)},
                       {"_DBH_M", m_b.accessor(dbh, n, "SCALAR", 0)},
                       {"_HEIGHT_M", m_b.accessor(height, n, "SCALAR", 0)},
                       {"_CROWN_RADIUS_M", m_b.accessor(crown, n, "SCALAR", 0)}};
    for (const auto& p : parts) {
        std::vector<float> sc;
        for (const auto i : trees)
            for (float v : gltf_scale(p.scale(m_s.trees[i]))) sc.push_back(v);
        json attrs = meta;
        attrs["TRANSLATION"] = a_tr;
        attrs["ROTATION"] = a_ro;
        attrs["SCALE"] = m_b.accessor(sc, n, "VEC3", 0);
        json extras = common;
        extras["instances"] = n;
        extras["per_instance"] = "_PLANT_ID, _DBH_M (m), _HEIGHT_M (m), _CROWN_RADIUS_M (m)";
        m_roots.push_back(
            m_b.node({{"name", name + p.suffix},
                      {"mesh", p.mesh},
                      {"extensions", {{"EXT_mesh_gpu_instancing", {{"attributes", attrs}}}}},
                      {"extras", extras}}));
    }
}

void GlbScene::add_user_meshes() {
    for (const auto& g : user_groups(m_s, m_opt.user)) {
        const UserMesh& u = *g.mesh;
        const int k = m_s.trees[g.trees[0]].species;
        const SpeciesLook& sp = m_s.species[static_cast<std::size_t>(k)];
        const int mat = m_b.material(u.name, crown_colour(sp, k));
        const json extras = {{"role", "user mesh " + u.obj.filename().string() +
                                          ", scaled uniformly by height / " +
                                          std::to_string(u.height_m) + " m"}};
        const int mesh = m_b.mesh(u.mesh, u.name, mat, extras);
        const double h = u.height_m;
        place(g.trees,
              {{mesh,
                [h](const Tree& t) {
                    const double s = std::max(t.height_m, 1e-3) / h;
                    return std::array<double, 3>{s, s, s};
                },
                "_trees"}},
              u.name, extras);
    }
}

void GlbScene::add_prototypes() {
    const Mesh trunk = unit_trunk();
    for (const auto& proto : prototypes(m_s, m_opt.user)) {
        const SpeciesLook& sp = m_s.species[static_cast<std::size_t>(proto.species)];
        const int leaves =
            m_b.material(file_safe(sp.name) + "_crown", crown_colour(sp, proto.species));
        const json common = {{"species", sp.name}, {"stage", stage_name(proto.stage)}};
        json te = common, ce = common;
        te["role"] = "trunk: solid (collision, override)";
        ce["role"] = "crown: visual only (seen by cameras and lidar, passable)";
        const int trunk_mesh = m_b.mesh(trunk, proto.name + "_trunk", m_bark, te);
        const int crown_mesh =
            m_b.mesh(unit_crown(sp.crown_shape, proto.stage), proto.name + "_crown", leaves, ce);
        place(proto.trees,
              {{trunk_mesh, [](const Tree& t) { return trunk_scale(t); }, "_trunks"},
               {crown_mesh, [](const Tree& t) { return crown_scale(t); }, "_crowns"}},
              proto.name, common);
    }
}

void GlbScene::add_tufts(int k, const std::vector<std::size_t>& tufts) {
    // One tuft mesh per grass species, instanced (or a node per tuft).
    const SpeciesLook& sp = m_s.species[static_cast<std::size_t>(k)];
    const std::string name = tuft_mesh_name(m_s, k);
    const json extras = {{"species", sp.name},
                         {"role", "grass tufts: visual only (the ground layer's cover, passable)"},
                         {"tufts", tufts.size()}};
    const int mesh = m_b.mesh(unit_trunk(), name, m_b.material(name, crown_colour(sp, k)), extras);
    if (m_opt.gltf_nodes) {
        for (const auto i : tufts)
            m_roots.push_back(m_b.node({{"mesh", mesh},
                                        {"translation", gltf_position(m_s.tufts[i])},
                                        {"rotation", yaw_rotation(m_s.tufts[i].yaw_rad)},
                                        {"scale", gltf_scale(tuft_scale(m_s.tufts[i]))}}));
        return;
    }
    m_instancing = true;
    std::vector<float> tr, ro, sc;
    for (const auto i : tufts) {
        const Tuft& t = m_s.tufts[i];
        for (float v : gltf_position(t)) tr.push_back(v);
        for (float v : yaw_rotation(t.yaw_rad)) ro.push_back(v);
        for (float v : gltf_scale(tuft_scale(t))) sc.push_back(v);
    }
    const int n = static_cast<int>(tufts.size());
    const json attrs = {{"TRANSLATION", m_b.accessor(tr, n, "VEC3", 0)},
                        {"ROTATION", m_b.accessor(ro, n, "VEC4", 0)},
                        {"SCALE", m_b.accessor(sc, n, "VEC3", 0)}};
    m_roots.push_back(
        m_b.node({{"name", name},
                  {"mesh", mesh},
                  {"extensions", {{"EXT_mesh_gpu_instancing", {{"attributes", attrs}}}}},
                  {"extras", extras}}));
}

void GlbScene::add_deadwood() {
    if (m_s.deadwood.empty()) return;
    const json role = {{"role", "dead wood: solid (collision); a trunk mesh scaled to the piece"}};
    const int mesh =
        m_b.mesh(unit_trunk(), "deadwood", m_b.material("deadwood", kDeadWoodColour), role);
    const float s = static_cast<float>(std::sqrt(0.5));
    for (const auto& d : m_s.deadwood) {
        const double dia = std::max(d.diameter_m, 1e-3), len = std::max(d.length_m, 1e-3);
        json n = {{"name", "deadwood_" + std::to_string(d.id) + "_" + dead_piece_name(d.piece)},
                  {"mesh", mesh},
                  {"scale", gltf_scale({dia, dia, len})}};
        if (d.standing) {
            n["translation"] = to_gltf(
                {static_cast<float>(d.x_m), static_cast<float>(d.y_m), static_cast<float>(d.z_m)});
        } else {
            // The trunk's axis (glTF +Y) turned onto the azimuth: 90 degrees about the
            // horizontal axis (-sin a, 0, -cos a); its top at the piece's top height.
            const double a = d.azimuth_rad;
            n["rotation"] = std::array<float, 4>{static_cast<float>(-std::sin(a)) * s, 0,
                                                 static_cast<float>(-std::cos(a)) * s, s};
            n["translation"] = to_gltf({static_cast<float>(d.x_m), static_cast<float>(d.y_m),
                                        static_cast<float>(d.z_m + d.top_height_m - 0.5 * dia)});
        }
        n["extras"] = {{"plant_id", d.id},
                       {"species", m_s.species[static_cast<std::size_t>(d.species)].name},
                       {"piece", dead_piece_name(d.piece)},
                       {"standing", d.standing},
                       {"decay_class", d.decay_class},
                       {"diameter_m", d.diameter_m},
                       {"length_m", d.length_m}};
        m_roots.push_back(m_b.node(std::move(n)));
    }
}

std::string GlbScene::build() {
    m_b.j["asset"] = {
        {"version", "2.0"},
        {"generator", "ecoterra export scene"},
        {"extras",
         {{"run", m_s.source},
          {"snapshot", m_s.snapshot},
          {"year", m_s.year},
          {"frame", "glTF Y-up, metres: (x_gltf, y_gltf, z_gltf) = (east, up, -north)"},
          {"trees", m_s.trees.size()},
          {"grass_tufts", m_s.tufts.size()},
          {"deadwood_pieces", m_s.deadwood.size()}}}};
    add_terrain();
    add_user_meshes();
    add_prototypes();
    for (const auto& [k, tufts] : tuft_groups(m_s)) add_tufts(k, tufts);
    add_deadwood();
    if (m_instancing) {
        m_b.j["extensionsUsed"] = {"EXT_mesh_gpu_instancing"};
        m_b.j["extensionsRequired"] = {"EXT_mesh_gpu_instancing"};
    }
    m_b.j["scenes"] = {{{"name", "ecoterra"}, {"nodes", m_roots}}};
    m_b.j["scene"] = 0;
    return m_b.finish();
}

} // namespace

std::string glb_bytes(const Scene& s, const ExportOptions& opt) {
    return GlbScene(s, opt).build();
}

} // namespace ecoterra::exporter
