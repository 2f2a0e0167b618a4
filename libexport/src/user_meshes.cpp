#include "ecoterra/export/user_meshes.hpp"

#include "ecoterra/error.hpp"
#include "ecoterra/io/atomic_file.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

namespace ecoterra::exporter {

namespace fs = std::filesystem;
using nlohmann::json;

Mesh read_obj_mesh(const fs::path& path, std::vector<std::string>* mtllibs) {
    std::istringstream in(io::read_text(path));
    Mesh m;
    std::string line;
    int lineno = 0;
    auto fail = [&](const std::string& why) {
        throw InputError(path.string() + ":" + std::to_string(lineno) + ": " + why);
    };
    while (std::getline(in, line)) {
        ++lineno;
        std::istringstream ls(line);
        std::string tag;
        ls >> tag;
        if (tag == "v") {
            double x = 0, y = 0, z = 0;
            if (!(ls >> x >> y >> z) || !std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
                fail("a vertex needs three finite numbers: '" + line + "'");
            m.positions.push_back(
                {static_cast<float>(x), static_cast<float>(y), static_cast<float>(z)});
        } else if (tag == "f") {
            std::vector<std::uint32_t> poly;
            std::string item;
            while (ls >> item) {
                long k = 0;
                try {
                    k = std::stol(item.substr(0, item.find('/')));
                } catch (const std::exception&) {
                    fail("face index '" + item + "' is not a number");
                }
                const long n = static_cast<long>(m.positions.size());
                const long idx = k < 0 ? n + k : k - 1;
                if (k == 0 || idx < 0 || idx >= n)
                    fail("face index " + item + " names no vertex (there are " + std::to_string(n) +
                         " so far)");
                poly.push_back(static_cast<std::uint32_t>(idx));
            }
            if (poly.size() < 3) fail("a face needs at least three vertices");
            for (std::size_t k = 1; k + 1 < poly.size(); ++k)
                m.indices.insert(m.indices.end(), {poly[0], poly[k], poly[k + 1]});
        } else if (tag == "mtllib" && mtllibs) {
            for (std::string name; ls >> name;) {
                checked_mtllib(path, lineno, name);
                mtllibs->push_back(name);
            }
        }
    }
    if (m.indices.empty()) throw InputError(path.string() + ": no faces (not a mesh OBJ?)");
    m.compute_normals();
    return m;
}

fs::path checked_mtllib(const fs::path& obj, int line, const std::string& name) {
    const std::string at = obj.string() + ":" + std::to_string(line) + ": mtllib '" + name + "'";
    const fs::path rel(name);
    if (rel.is_absolute())
        throw InputError(at + ": an absolute path; a material library must lie in the OBJ's "
                              "folder (name it relative to it)");
    for (const auto& part : rel)
        if (part == "..")
            throw InputError(at + ": leads out of the OBJ's folder ('..'); a material library "
                                  "must lie in it");
    std::error_code ec;
    const fs::path folder = fs::canonical(fs::absolute(obj).parent_path(), ec);
    const fs::path file = fs::weakly_canonical(fs::absolute(obj).parent_path() / rel, ec);
    if (!fs::is_regular_file(file, ec))
        throw InputError(at + ": no such file (" + file.string() + ")");
    // A link inside the folder may still lead out of it.
    const auto [f, e] = std::mismatch(folder.begin(), folder.end(), file.begin(), file.end());
    if (f != folder.end())
        throw InputError(at + ": leads out of the OBJ's folder (to " + file.string() +
                         "); a material library must lie in it");
    return file;
}

namespace {

/// A text entry of a mesh's object ("" when absent and not required).
std::string entry_text(const json& m, const char* key, bool required, const std::string& at) {
    if (!m.contains(key)) {
        if (required) throw InputError(at + ": " + key + " is missing");
        return "";
    }
    if (!m[key].is_string()) throw InputError(at + "." + key + ": not a string");
    return m[key].get<std::string>();
}

/// The index of the run's species a mesh names.
int entry_species(const std::string& species, const std::vector<SpeciesLook>& sp,
                  const std::string& at) {
    int k = -1;
    std::string known;
    for (std::size_t s = 0; s < sp.size(); ++s) {
        if (sp[s].name == species) k = static_cast<int>(s);
        known += (s ? ", " : "") + sp[s].name;
    }
    if (k < 0)
        throw InputError(at + ".species = '" + species + "': the run has no such species (" +
                         known + ")");
    return k;
}

/// The life stages a mesh stands for: the one it names, or all.
std::vector<Stage> entry_stages(const std::string& stage, const std::string& at) {
    std::vector<Stage> stages;
    for (const Stage st : kStages)
        if (stage.empty() || stage == stage_name(st)) stages.push_back(st);
    if (stages.empty())
        throw InputError(at + ".stage = '" + stage + "': use young, medium or adult");
    return stages;
}

/// The mesh of an entry: its OBJ (beside the JSON unless absolute), height and orientation.
UserMesh entry_mesh(const json& m, const fs::path& base, const std::string& at) {
    UserMesh u;
    const std::string obj = entry_text(m, "obj", true, at);
    u.obj = fs::path(obj).is_absolute() ? fs::path(obj) : base / obj;
    std::error_code ec;
    if (!fs::is_regular_file(u.obj, ec))
        throw InputError(at + ".obj = '" + obj + "': no such file (" + u.obj.string() + ")");
    if (!m.contains("height_m") || !m["height_m"].is_number() || !(m["height_m"].get<double>() > 0))
        throw InputError(at + ".height_m: give the mesh's height in metres (above 0)");
    u.height_m = m["height_m"].get<double>();
    if (m.contains("rotate_y_to_z")) {
        if (!m["rotate_y_to_z"].is_boolean())
            throw InputError(at + ".rotate_y_to_z: true or false");
        u.rotate_y_to_z = m["rotate_y_to_z"].get<bool>();
    }
    std::vector<std::string> libs;
    u.mesh = read_obj_mesh(u.obj, &libs);
    if (u.rotate_y_to_z) {
        for (auto& p : u.mesh.positions) p = {p[0], -p[2], p[1]};
        u.mesh.compute_normals();
    }
    u.mtl = libs; // each checked by read_obj_mesh
    return u;
}

} // namespace

UserMeshes UserMeshes::load(const fs::path& file, const std::vector<SpeciesLook>& sp) {
    const std::string where = "--species-meshes " + file.string();
    json j;
    try {
        j = json::parse(io::read_text(file));
    } catch (const json::exception& e) {
        throw InputError(where + ": not JSON (" + e.what() + ")");
    }
    if (!j.is_object() || !j.contains("meshes") || !j["meshes"].is_array())
        throw InputError(where + ": needs {\"meshes\": [...]}");
    for (const auto& [k, v] : j.items())
        if (k != "meshes") throw InputError(where + ": unknown key '" + k + "'");
    UserMeshes out;
    std::set<std::string> names;
    const fs::path base = fs::absolute(file).parent_path();
    for (std::size_t e = 0; e < j["meshes"].size(); ++e) {
        const json& m = j["meshes"][e];
        const std::string at = where + ": meshes[" + std::to_string(e) + "]";
        if (!m.is_object()) throw InputError(at + ": not an object");
        for (const auto& [k, v] : m.items())
            if (k != "species" && k != "stage" && k != "obj" && k != "height_m" &&
                k != "rotate_y_to_z")
                throw InputError(at + ": unknown key '" + k +
                                 "' (species, stage, obj, height_m, rotate_y_to_z)");
        const std::string species = entry_text(m, "species", true, at);
        const int k = entry_species(species, sp, at);
        const std::vector<Stage> stages = entry_stages(entry_text(m, "stage", false, at), at);
        UserMesh u = entry_mesh(m, base, at);
        u.name = "user_" + file_safe(u.obj.stem().string());
        while (!names.insert(u.name).second) u.name += "_";
        const std::size_t idx = out.m_meshes.size();
        out.m_meshes.push_back(std::move(u));
        for (const Stage st : stages) {
            if (!out.m_by.emplace(std::pair{k, static_cast<int>(st)}, idx).second)
                throw InputError(at + ": species '" + species + "', stage " + stage_name(st) +
                                 " has a mesh already");
        }
    }
    return out;
}

const UserMesh* UserMeshes::find(int species, Stage stage) const {
    const auto it = m_by.find({species, static_cast<int>(stage)});
    return it == m_by.end() ? nullptr : &m_meshes[it->second];
}

} // namespace ecoterra::exporter
