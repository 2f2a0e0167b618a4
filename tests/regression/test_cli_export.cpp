// `ecoterra export scene` and `export layers` as a user runs them, checked by the formats' own
// consumers (the Khronos glTF validator, libsdformat, GDAL) and against the snapshot's stems.
#include "support/run_cli.hpp"
#include "support/scenes.hpp"

#include "ecoterra/export/formats.hpp"
#include "ecoterra/export/mesh.hpp"
#include "ecoterra/export/scene.hpp"
#include "ecoterra/io/atomic_file.hpp"
#include "ecoterra/random.hpp"
#include "ecoterra/run/run_reader.hpp"
#include "ecoterra/terrain/io/raster_io.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <numbers>
#include <set>
#include <sstream>

using namespace ecoterra;
using namespace ecoterra::exporter;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

json read_json(const fs::path& p) {
    return json::parse(io::read_text(p));
}

/// The JSON chunk and binary chunk of a .glb.
std::pair<json, std::string> read_glb(const fs::path& p) {
    const std::string b = io::read_text(p);
    REQUIRE(b.size() >= 28);
    std::uint32_t magic = 0, len = 0, jlen = 0;
    std::memcpy(&magic, b.data(), 4);
    std::memcpy(&len, b.data() + 8, 4);
    std::memcpy(&jlen, b.data() + 12, 4);
    CHECK(magic == 0x46546C67);
    CHECK(len == b.size());
    const json j = json::parse(b.substr(20, jlen));
    return {j, b.substr(20 + jlen + 8)};
}

std::vector<float> accessor_floats(const json& j, const std::string& bin, int a) {
    const auto& acc = j["accessors"][a];
    const auto& view = j["bufferViews"][acc["bufferView"].get<int>()];
    const int comps = acc["type"] == "SCALAR" ? 1 : acc["type"] == "VEC3" ? 3 : 4;
    std::vector<float> v(acc["count"].get<std::size_t>() * comps);
    std::memcpy(v.data(), bin.data() + view["byteOffset"].get<std::size_t>(),
                v.size() * sizeof(float));
    return v;
}

/// Calls f(node, its EXT_mesh_gpu_instancing attributes) for every instanced trunks node.
template <class F>
void each_trunks_node(const json& j, F&& f) {
    for (const auto& node : j["nodes"])
        if (node.contains("extensions") && node["name"].get<std::string>().ends_with("_trunks"))
            f(node, node["extensions"]["EXT_mesh_gpu_instancing"]["attributes"]);
}

/// The trees of a run's last snapshot by plant id.
std::map<std::int64_t, Tree> trees_by_id(const Scene& s) {
    std::map<std::int64_t, Tree> m;
    for (const auto& t : s.trees) m[t.id] = t;
    return m;
}

using test::shell;

/// Runs ecoterra with `args` in `dir`; the test case stops unless it succeeds. Its output.
std::string succeeds(const test::TempDir& dir, const std::string& args) {
    const auto r = test::run(dir, args);
    INFO(r.out);
    REQUIRE(r.code == 0);
    return r.out;
}

/// The Khronos glTF validator on `glb`: passes with zero errors.
void check_gltf_validator(const test::TempDir& dir, const std::string& glb) {
    const auto r = shell(dir, "NODE_PATH='" ECOTERRA_TOOLS_DIR
                              "/node_modules' node '" ECOTERRA_VALIDATE_GLTF "' " +
                                  glb);
    INFO(r.out);
    CHECK(r.code == 0);
    CHECK_THAT(r.out, Catch::Contains("errors 0"));
}

/// libsdformat on FOLDER/world.sdf with its models: no errors. Its output ("models N").
std::string check_sdformat(const test::TempDir& dir, const std::string& folder) {
    const auto r = shell(dir, "ASAN_OPTIONS=detect_leaks=0 '" ECOTERRA_SDF_CHECK "' " + folder +
                                  "/world.sdf " + folder + "/models");
    INFO(r.out);
    CHECK(r.code == 0);
    return r.out;
}

} // namespace

TEST_CASE("export: plant geometry matches the tree's DBH, height and crown", "[export]") {
    // The trunk's diameter at breast height is the DBH, for any height above it.
    for (const double h : {1.5, 3.0, 10.0, 35.0})
        for (const double d : {0.02, 0.1, 0.6}) {
            const double base = trunk_base_diameter_m(d, h);
            CHECK(base * (1 - (1 - kTopDiameterFraction) * kBreastHeight_m / h) == Approx(d));
        }
    // Unit prototypes: height 1, trunk radius 0.5 at the ground, crown radius 1, unit normals.
    for (const auto shape :
         {eco::CrownShape::cone, eco::CrownShape::ellipsoid, eco::CrownShape::umbrella})
        for (const Stage st : kStages) {
            const Mesh c = unit_crown(shape, st);
            float zmin = 9, zmax = -9, rmax = 0;
            for (const auto& p : c.positions) {
                zmin = std::min(zmin, p[2]);
                zmax = std::max(zmax, p[2]);
                rmax = std::max(rmax, std::hypot(p[0], p[1]));
            }
            CHECK(zmax == Approx(1));
            CHECK(zmin >= crown_base_fraction(st) - 1e-6);
            CHECK(rmax == Approx(1).epsilon(1e-6));
            for (const auto& n : c.normals)
                CHECK(std::hypot(n[0], n[1], n[2]) == Approx(1).epsilon(1e-5));
            CHECK(c.triangles() > 0);
        }
    // Size classes hold every tree within 2.5 % of its height, trunk and crown.
    Scene s;
    s.species = {{"A", eco::CrownShape::cone, 30, true, 3},
                 {"B", eco::CrownShape::umbrella, 10, false, 4}};
    s.terrain = RasterD(GridSpec{10, 10, 1.0, 0, 0}, 0.0);
    Rng rng(1, "test");
    for (int k = 0; k < 500; ++k) {
        Tree t;
        t.id = k;
        t.species = k % 2;
        t.height_m = rng.uniform(0.2, 30);
        t.dbh_m = t.height_m > kBreastHeight_m ? rng.uniform(0.01, 0.8) : 0;
        t.crown_radius_m = rng.uniform(0.1, 8);
        t.stage = stage_of(t.height_m, s.species[static_cast<std::size_t>(t.species)].max_height_m);
        s.trees.push_back(t);
    }
    std::size_t n = 0;
    for (const auto& c : size_classes(s))
        for (const auto i : c.trees) {
            const Tree& t = s.trees[i];
            CHECK(c.species == t.species);
            CHECK(std::abs(c.height_m / t.height_m - 1) <= 0.0251);
            CHECK(std::abs(c.base_diameter_m / trunk_scale(t)[0] - 1) <= 0.0251);
            CHECK(std::abs(c.crown_radius_m / t.crown_radius_m - 1) <= 0.0251);
            ++n;
        }
    CHECK(n == s.trees.size());
}

TEST_CASE("export layers: basal area and stems are conserved, canopy height is the tallest crown",
          "[export][layers]") {
    Scene s;
    s.species = {{"A", eco::CrownShape::ellipsoid, 30, false, 4},
                 {"B", eco::CrownShape::cone, 30, true, 3}};
    s.terrain = RasterD(GridSpec{100, 100, 1.0, 0, 0}, 0.0);
    Rng rng(2, "test");
    double ba = 0;
    for (int k = 0; k < 40; ++k) {
        Tree t;
        t.id = k;
        t.species = k % 2;
        // At cell centres, so that the window around the tree holds as many cells as the window
        // around any interior cell (off-centre, the sum is within about 1 %).
        t.x_m = std::floor(rng.uniform(20, 80)) + 0.5;
        t.y_m = std::floor(rng.uniform(20, 80)) + 0.5;
        t.height_m = rng.uniform(2, 25);
        t.dbh_m = rng.uniform(0.05, 0.5);
        t.crown_radius_m = rng.uniform(1, 4);
        ba += std::numbers::pi / 4 * t.dbh_m * t.dbh_m;
        s.trees.push_back(t);
    }
    const auto v = vegetation_layers(s, {10});
    // Trees 10 m or more from the edges: every cell's window is whole, so the layers integrate to
    // the stand's totals.
    double ba_sum = 0, stems_sum = 0;
    for (int j = 0; j < 100; ++j)
        for (int i = 0; i < 100; ++i) {
            ba_sum += v.basal_area_m2_per_ha(i, j) * 1e-4;
            stems_sum += v.stems_per_ha(i, j) * 1e-4;
        }
    CHECK(ba_sum == Approx(ba).epsilon(1e-9));
    CHECK(stems_sum == Approx(40).epsilon(1e-9));
    // Canopy height: at each tree's own cell, at least its height.
    for (const auto& t : s.trees) {
        const int i = static_cast<int>(t.x_m), j = static_cast<int>(t.y_m);
        CHECK(v.canopy_height_m(i, j) >= t.height_m);
        CHECK(!std::isnan(v.dominant_species(i, j)));
    }
    CHECK(v.canopy_height_m(0, 0) == 0);
    CHECK(std::isnan(v.dominant_species(0, 0)));
}

TEST_CASE("export layers: the dead-wood volume integrates to the pieces inside the terrain, "
          "read back by GDAL",
          "[export][layers][deadwood]") {
    test::TempDir dir;
    // 15 years: snags, logs, a thinning's stumps and slash at year 10, and a storm's snapped
    // stems, tops, stems and root plates at year 13.
    json scene = test::small_scene(15);
    scene["vegetation"]["management"] = {
        {"operations",
         json::array({json{
             {"year", 10}, {"type", "thin_from_below"}, {"target_basal_area_m2_per_ha", 5}}})}};
    scene["vegetation"]["windthrow"] = {
        {"storms", {{{"year", 13}, {"wind_m_per_s", 26}, {"from_deg", 200}}}}};
    // Birch of weak wood (MOR 15 MPa), so that some stems break rather than uproot.
    json eco = read_json(test::data_dir() / "ecosystems/humid_subtropical_broadleaf.json");
    for (auto& sp : eco["Species"])
        if (sp["Species Name"] == "Birch") sp["physiology"]["wind"]["mor_pa"] = 15e6;
    std::ofstream(dir / "eco.json") << eco.dump(1);
    scene["vegetation"]["ecosystem"] = (dir / "eco.json").string();
    std::ofstream(dir / "scene.json") << scene.dump(2);
    succeeds(dir, "run scene.json -o run.h5 --no-pictures");
    succeeds(dir, "export layers run.h5 -o layers");
    const auto pieces = run::read_snapshot_deadwood(dir / "run.h5", -1).pieces;
    REQUIRE(pieces.size() > 10);
    const GridSpec g = run::read_run_terrain(dir / "run.h5").grid();
    // Bounds: the pieces wholly on the terrain, and all of them (a log may reach past the edge).
    double inside = 0, all = 0, top = 0;
    bool stumps = false;
    for (const auto& p : pieces) {
        all += p.volume_m3;
        stumps = stumps || p.piece == 1;
        if (g.contains_point(p.x_m, p.y_m) && g.contains_point(p.end_x_m, p.end_y_m)) {
            inside += p.volume_m3;
            if (!p.standing || p.piece == 1) top = std::max({top, p.height_m, p.end_height_m});
        }
    }
    CHECK(stumps);
    const auto gdal = shell(dir, "gdalinfo layers/deadwood_volume_m3_per_ha.tif");
    CHECK(gdal.code == 0);
    CHECK_THAT(gdal.out, Catch::Contains("Size is"));
    const RasterD v = terrain::io::read_raster(dir / "layers/deadwood_volume_m3_per_ha.tif");
    const RasterD h = terrain::io::read_raster(dir / "layers/deadwood_top_height_m.tif");
    double sum = 0, highest = 0;
    for (std::int64_t k = 0; k < v.size(); ++k) sum += v.data()[k];
    for (std::int64_t k = 0; k < h.size(); ++k) highest = std::max(highest, h.data()[k]);
    sum *= g.cell_size_m * g.cell_size_m / 1e4; // float32 in the file
    CHECK(sum >= inside * (1 - 1e-6));
    CHECK(sum <= all * (1 + 1e-6));
    // The highest top: at most the highest end (tops are linear along a piece), and within a
    // quarter cell's taper of the highest end of the pieces wholly inside.
    double any_top = 0;
    for (const auto& p : pieces)
        if (!p.standing || p.piece == 1) any_top = std::max({any_top, p.height_m, p.end_height_m});
    CHECK(highest <= any_top * (1 + 1e-6));
    CHECK(highest >= 0.8 * top);
    // The pits of the root plates: each pit's centre cell (a plate thickness and radius upwind of
    // the stem base) is as deep as half the plate is thick, and every cell with a pit lies
    // within a plate radius of some pit's centre.
    const RasterD pit = terrain::io::read_raster(dir / "layers/windthrow_pit_depth_m.tif");
    std::vector<std::array<double, 3>> pits; // centre x, y and radius
    std::size_t centres = 0;
    for (const auto& p : pieces) {
        if (p.piece != 4) continue;
        const double r = 0.5 * p.height_m, t = p.length_m;
        const double cx = p.x_m + (t + r) * std::cos(p.azimuth_rad);
        const double cy = p.y_m + (t + r) * std::sin(p.azimuth_rad);
        pits.push_back({cx, cy, r});
        if (!g.contains_point(cx, cy)) continue;
        const int i = std::clamp(static_cast<int>(std::lround(g.col_of(cx))), 0, g.nx - 1);
        const int j = std::clamp(static_cast<int>(std::lround(g.row_of(cy))), 0, g.ny - 1);
        if (std::hypot(g.x_of(i) - cx, g.y_of(j) - cy) > r) continue;
        CHECK(pit(i, j) >= 0.5 * t - 1e-6);
        ++centres;
    }
    CHECK(centres > 0);
    for (int j = 0; j < g.ny; ++j)
        for (int i = 0; i < g.nx; ++i) {
            if (pit(i, j) <= 0) continue;
            bool near = false;
            for (const auto& c : pits)
                near = near || std::hypot(g.x_of(i) - c[0], g.y_of(j) - c[1]) <= c[2] + 1e-9;
            CHECK(near);
        }

    // glTF: one node per piece whose base is on the terrain, valid for the Khronos validator; a
    // lying piece's node carries the trunk's axis from its base to its end point.
    succeeds(dir, "export scene run.h5 --format gltf -o s.glb --no-pictures");
    check_gltf_validator(dir, "s.glb");
    const json frame = read_json(dir / "s.glb.json")["frame"];
    const double ox = frame["origin_x_m"].get<double>(), oy = frame["origin_y_m"].get<double>();
    const auto glb = read_glb(dir / "s.glb");
    std::map<std::string, json> nodes;
    for (const auto& n : glb.first["nodes"])
        if (n.contains("name") && n["name"].get<std::string>().starts_with("deadwood_"))
            nodes[n["name"].get<std::string>()] = n;
    std::size_t on_terrain = 0, lying_checked = 0;
    const char* kinds[] = {"stem", "stump", "top", "snapped", "root_plate"};
    for (const auto& p : pieces) {
        if (!g.contains_point(p.x_m, p.y_m)) continue;
        ++on_terrain;
        const auto it = nodes.find("deadwood_" + std::to_string(p.id) + "_" + kinds[p.piece]);
        REQUIRE(it != nodes.end());
        const json& n = it->second;
        CHECK(n["extras"]["decay_class"] == p.decay_class);
        if (p.standing) continue;
        // v' = v + 2 w (q x v) + 2 q x (q x v), v = (0, length, 0) in glTF axes.
        const auto q = n["rotation"].get<std::array<double, 4>>();
        const auto t = n["translation"].get<std::array<double, 3>>();
        const double L = n["scale"][1].get<double>();
        const std::array<double, 3> axis{0, L, 0};
        auto cross = [](const std::array<double, 3>& a, const std::array<double, 3>& b) {
            return std::array<double, 3>{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                                         a[0] * b[1] - a[1] * b[0]};
        };
        const std::array<double, 3> qv{q[0], q[1], q[2]};
        const auto c1 = cross(qv, axis);
        const auto c2 = cross(qv, c1);
        const double ex = t[0] + axis[0] + 2 * q[3] * c1[0] + 2 * c2[0];
        const double ey = t[1] + axis[1] + 2 * q[3] * c1[1] + 2 * c2[1];
        const double ez = t[2] + axis[2] + 2 * q[3] * c1[2] + 2 * c2[2];
        CHECK(ex + ox == Approx(p.end_x_m).margin(1e-3));
        CHECK(-ez + oy == Approx(p.end_y_m).margin(1e-3));
        CHECK(ey == Approx(t[1]).margin(1e-4)); // lying level
        ++lying_checked;
    }
    CHECK(nodes.size() == on_terrain);
    CHECK(lying_checked > 0);

    // Gazebo: libsdformat parses the world with its dead-wood model, a link per piece.
    succeeds(dir, "export scene run.h5 --format gazebo -o gz --no-pictures");
    const Scene sc = load_scene(dir / "run.h5", -1);
    CHECK_THAT(check_sdformat(dir, "gz"),
               Catch::Contains("models " + std::to_string(sc.trees.size() + 2)));
    const std::string world = io::read_text(dir / "gz/world.sdf");
    std::size_t links = 0;
    for (std::size_t at = 0; (at = world.find("<link name=\"piece_", at)) != std::string::npos;
         ++at)
        ++links;
    CHECK(links == on_terrain);

    // MAVS: one dead-wood mesh in the scene's frame; each piece's block of vertices is the trunk
    // prototype, and a lying piece's far ring is centred on its end point.
    succeeds(dir, "export scene run.h5 --format mavs -o mavs --no-pictures");
    const json mavs = read_json(dir / "mavs/scene.json");
    bool listed = false;
    for (const auto& o : mavs["Objects"]) listed = listed || o["Mesh"] == "meshes/deadwood.obj";
    CHECK(listed);
    std::vector<std::array<double, 3>> verts;
    std::ifstream obj(dir / "mavs/meshes/deadwood.obj");
    for (std::string line; std::getline(obj, line);)
        if (line.starts_with("v ")) {
            std::istringstream in(line.substr(2));
            std::array<double, 3> vert{};
            in >> vert[0] >> vert[1] >> vert[2];
            verts.push_back(vert);
        }
    const Mesh unit = unit_trunk();
    REQUIRE(verts.size() == sc.deadwood.size() * unit.positions.size());
    CHECK(sc.deadwood.size() == on_terrain);
    std::size_t ends_checked = 0;
    for (std::size_t k = 0; k < sc.deadwood.size(); ++k) {
        const DeadPiece& d = sc.deadwood[k];
        double cx = 0, cy = 0, n = 0;
        for (std::size_t i = 0; i < unit.positions.size(); ++i)
            if (unit.positions[i][2] == 1.0f) {
                cx += verts[k * unit.positions.size() + i][0];
                cy += verts[k * unit.positions.size() + i][1];
                n += 1;
            }
        const double ex = d.standing ? d.x_m : d.x_m + d.length_m * std::cos(d.azimuth_rad);
        const double ey = d.standing ? d.y_m : d.y_m + d.length_m * std::sin(d.azimuth_rad);
        CHECK(cx / n == Approx(ex).margin(1e-3));
        CHECK(cy / n == Approx(ey).margin(1e-3));
        ends_checked += !d.standing;
    }
    CHECK(ends_checked > 0);

    // Unreal: a row per piece; the unit trunk's axis end, turned by Unreal's rotation matrix
    // (FRotationMatrix: for Roll 0 the local Z axis goes to (-sin P cos Y, -sin P sin Y, cos P))
    // and scaled, lands on the piece's end in Unreal's axes (100 x, -100 y cm).
    succeeds(dir, "export scene run.h5 --format unreal -o ue --no-pictures");
    std::ifstream ue(dir / "ue/deadwood.csv");
    std::string line;
    std::getline(ue, line);
    CHECK(line.starts_with("Name,species,piece,decay_class,mesh,x_cm,y_cm,z_cm,pitch_deg,yaw_deg"));
    std::size_t rows = 0;
    std::set<std::string> kinds_seen;
    const double deg = std::numbers::pi / 180;
    for (; std::getline(ue, line); ++rows) {
        std::vector<std::string> f;
        std::stringstream ss(line);
        for (std::string c; std::getline(ss, c, ',');) f.push_back(c);
        REQUIRE(f.size() == 16);
        REQUIRE(rows < sc.deadwood.size());
        const DeadPiece& d = sc.deadwood[rows];
        CHECK(f[0] == "deadwood_" + std::to_string(d.id) + "_" + dead_piece_name(d.piece));
        kinds_seen.insert(f[2]);
        const double p = std::stod(f[8]) * deg, y = std::stod(f[9]) * deg;
        const double len_cm = 100 * std::stod(f[12]);
        const double ex = std::stod(f[5]) - std::sin(p) * std::cos(y) * len_cm;
        const double ey = std::stod(f[6]) - std::sin(p) * std::sin(y) * len_cm;
        const double end_x = d.standing ? d.x_m : d.x_m + d.length_m * std::cos(d.azimuth_rad);
        const double end_y = d.standing ? d.y_m : d.y_m + d.length_m * std::sin(d.azimuth_rad);
        CHECK(ex == Approx(100 * end_x).margin(0.2));
        CHECK(ey == Approx(-100 * end_y).margin(0.2));
        if (d.standing) CHECK(std::stod(f[7]) == Approx(100 * d.z_m).margin(0.2));
    }
    CHECK(rows == sc.deadwood.size());
    for (const char* k : {"stem", "top", "snapped", "root_plate", "stump"}) {
        CAPTURE(k);
        CHECK(kinds_seen.count(k) == 1);
    }
    CHECK(std::filesystem::file_size(dir / "ue/meshes/deadwood.obj") > 100);
}

TEST_CASE("export scene: every format holds the snapshot's stems, checked by its own consumer",
          "[export][cli][slow]") {
    test::TempDir dir;
    std::ofstream(dir / "scene.json") << test::small_scene(2).dump(2);
    REQUIRE(test::run(dir, "run scene.json -o run.h5 --no-pictures").code == 0);
    const Scene s = load_scene(dir / "run.h5", -1);
    REQUIRE(s.trees.size() > 20);
    const auto by_id = trees_by_id(s);
    const RasterD dem = run::read_run_terrain(dir / "run.h5");

    SECTION("glTF: the Khronos validator accepts it; instances and nodes hold the stems") {
        for (const std::string mode : {"", " --gltf-nodes"}) {
            succeeds(dir, "export scene run.h5 --format gltf -o scene.glb --force" + mode);
            check_gltf_validator(dir, "scene.glb");
            const auto [j, bin] = read_glb(dir / "scene.glb");
            std::size_t seen = 0;
            for (const auto& node : j["nodes"]) {
                if (mode.empty() && node.contains("extensions") &&
                    node["name"].get<std::string>().ends_with("_trunks")) {
                    const auto& at = node["extensions"]["EXT_mesh_gpu_instancing"]["attributes"];
                    const auto pos = accessor_floats(j, bin, at["TRANSLATION"]);
                    const auto ids = accessor_floats(j, bin, at["_PLANT_ID"]);
                    const auto dbh = accessor_floats(j, bin, at["_DBH_M"]);
                    for (std::size_t k = 0; k < ids.size(); ++k) {
                        const Tree& t = by_id.at(static_cast<std::int64_t>(ids[k]));
                        // glTF Y-up: (east, up, -north).
                        CHECK(pos[3 * k] == Approx(t.x_m).margin(1e-4));
                        CHECK(pos[3 * k + 1] ==
                              Approx(dem.sample_bilinear(t.x_m, t.y_m)).margin(1e-4));
                        CHECK(pos[3 * k + 2] == Approx(-t.y_m).margin(1e-4));
                        CHECK(dbh[k] == Approx(t.dbh_m).margin(1e-6));
                        CHECK(node["extras"]["species"] ==
                              s.species[static_cast<std::size_t>(t.species)].name);
                        ++seen;
                    }
                }
                if (!mode.empty() && node.contains("extras") &&
                    node["extras"].contains("plant_id") &&
                    !node["name"].get<std::string>().starts_with("deadwood_")) {
                    const Tree& t = by_id.at(node["extras"]["plant_id"].get<std::int64_t>());
                    CHECK(node["translation"][0].get<double>() == Approx(t.x_m).margin(1e-4));
                    CHECK(node["translation"][2].get<double>() == Approx(-t.y_m).margin(1e-4));
                    CHECK(node["extras"]["height_m"].get<double>() == Approx(t.height_m));
                    ++seen;
                }
            }
            CHECK(seen == s.trees.size());
        }
    }

    SECTION("Gazebo: libsdformat parses the world; one include per tree at its pose") {
        CHECK_THAT(succeeds(dir, "export scene run.h5 --format gazebo -o gz"),
                   Catch::Contains("resampled 20x20 to 33x33"));
        // The terrain, a model per tree, and the dead wood's model when there is dead wood.
        CHECK_THAT(check_sdformat(dir, "gz"),
                   Catch::Contains("models " + std::to_string(s.trees.size() + 1 +
                                                              (s.deadwood.empty() ? 0 : 1))));
        const std::string world = io::read_text(dir / "gz/world.sdf");
        std::size_t includes = 0, at = 0;
        while ((at = world.find("<include>", at)) != std::string::npos) ++includes, ++at;
        CHECK(includes == s.trees.size());
        for (const auto& t : s.trees) {
            const auto p = world.find("<name>plant_" + std::to_string(t.id) + "</name><pose>");
            REQUIRE(p != std::string::npos);
            std::istringstream pose(world.substr(world.find("<pose>", p) + 6));
            double x = 0, y = 0, z = 0;
            pose >> x >> y >> z;
            CHECK(x == Approx(t.x_m).margin(1e-6));
            CHECK(y == Approx(t.y_m).margin(1e-6));
            CHECK(z == Approx(dem.sample_bilinear(t.x_m, t.y_m)).margin(1e-6));
        }
        CHECK(fs::exists(dir / "gz/README.md"));
        // The heightmap is centred on the terrain (cell centres 1 .. 39 m: the centre is 20 m),
        // in world.sdf and in the sidecar's own SDF snippet alike.
        const json side = read_json(dir / "gz/terrain.png.json");
        CHECK(side["gazebo"]["pos_m"][0].get<double>() == Approx(20));
        CHECK(side["gazebo"]["pos_m"][1].get<double>() == Approx(20));
        CHECK_THAT(side["gazebo"]["sdf"].get<std::string>(), Catch::Contains("<pos>20 20 "));
        CHECK_THAT(world, Catch::Contains("<pos>20 20 "));
        CHECK(fs::file_size(dir / "gz/picture.png") > 10000);
    }

    SECTION("MAVS: every referenced file exists; MAVS's own diameter rule gives the DBH") {
        succeeds(dir, "export scene run.h5 --format mavs -o mavs");
        const json scene = read_json(dir / "mavs/scene.json");
        const fs::path root = scene["PathToMeshes"].get<std::string>();
        CHECK(fs::exists(root / scene["Surface Mesh"][0]["Mesh"].get<std::string>()));
        CHECK(fs::exists(scene["VegOverrideFile"].get<std::string>()));
        std::map<std::string, json> veg;
        const json override_file = read_json(scene["VegOverrideFile"].get<std::string>());
        for (const auto& v : override_file["veg_models"]) veg[v["mesh"].get<std::string>()] = v;
        // Stems matched by position (truth.txt and Objects list the same trees).
        std::size_t n = 0;
        std::vector<double> offsets;
        for (const auto& obj : scene["Objects"]) {
            const std::string mesh = obj["Mesh"];
            CHECK(fs::exists(root / mesh));
            if (mesh == "meshes/deadwood.obj") continue; // solid, checked in its own test
            REQUIRE(veg.count(mesh) == 1);
            for (const auto& inst : obj["Instances"]) {
                const double x = inst["Position"][0], y = inst["Position"][1];
                const Tree* t = nullptr;
                for (const auto& c : s.trees)
                    if (std::abs(c.x_m - x) < 1e-9 && std::abs(c.y_m - y) < 1e-9) t = &c;
                REQUIRE(t != nullptr);
                ++n;
                // MAVS: d = diameter * (instance height) / mesh height, ground near z = 0.
                // Every base is the DEM's height less one offset for the whole scene.
                const double shift = dem.sample_bilinear(x, y) - inst["Position"][2].get<double>();
                if (!offsets.empty()) CHECK(shift == Approx(offsets.front()).margin(1e-6));
                offsets.push_back(shift);
                const double h = veg[mesh]["height"].get<double>() * inst["Scale"][2].get<double>();
                CHECK(h == Approx(t->height_m).epsilon(1e-6));
                const double d =
                    veg[mesh]["diameter"].get<double>() * h / veg[mesh]["height"].get<double>();
                if (t->dbh_m > 0) CHECK(std::abs(d / t->dbh_m - 1) < 0.06);
            }
        }
        CHECK(n == s.trees.size());
    }

    SECTION("Unreal: a landscape of an accepted size and a data table in centimetres") {
        CHECK_THAT(succeeds(dir, "export scene run.h5 --format unreal -o ue"),
                   Catch::Contains("resampled to 22 x 22"));
        const RasterD land = terrain::io::read_png16(dir / "ue/landscape.png");
        CHECK(land.nx() == land.ny());
        CHECK(terrain::io::is_unreal_landscape_size(land.nx()));
        std::istringstream csv(io::read_text(dir / "ue/trees.csv"));
        std::string line;
        std::getline(csv, line);
        CHECK(line.rfind("Name,species,stage,mesh,x_cm,y_cm,z_cm,yaw_deg", 0) == 0);
        std::size_t n = 0;
        while (std::getline(csv, line)) {
            std::vector<std::string> f;
            std::istringstream row(line);
            for (std::string c; std::getline(row, c, ',');) f.push_back(c);
            REQUIRE(f.size() == 15);
            const Tree& t = by_id.at(std::stoll(f[0].substr(6)));
            CHECK(std::stod(f[4]) == Approx(100 * t.x_m));
            CHECK(std::stod(f[5]) == Approx(-100 * t.y_m)); // left-handed: Y points south
            CHECK(std::stod(f[11]) == Approx(100 * t.dbh_m));
            CHECK(fs::exists(dir / "ue/meshes" / (f[3] + ".obj")));
            ++n;
        }
        CHECK(n == s.trees.size());
    }

    SECTION("layers: GDAL reads every layer on the terrain's grid") {
        succeeds(dir, "export layers run.h5 -o layers");
        for (const char* f : {"elevation_m", "canopy_height_m", "stems_per_ha",
                              "basal_area_m2_per_ha", "dominant_species", "leaf_area_m2",
                              "soil_water_content_m3_per_m3", "relative_soil_moisture",
                              "surface_water_depth_m", "water_table_depth_m", "catchment_id"}) {
            const RasterD l = terrain::io::read_gdal(dir / "layers" / (std::string(f) + ".tif"));
            CHECK(l.nx() == dem.nx());
            CHECK(l.ny() == dem.ny());
            CHECK(l.grid().origin_x_m == Approx(dem.grid().origin_x_m));
            CHECK(l.grid().origin_y_m == Approx(dem.grid().origin_y_m));
            CHECK(l.cell_size() == Approx(dem.cell_size()));
        }
        const RasterD z = terrain::io::read_gdal(dir / "layers/elevation_m.tif");
        CHECK((z.array() - dem.array()).abs().maxCoeff() < 1e-4);
        // The moisture layers hold what their labels say, from the run's own soil and water:
        // the volumetric content is the snapshot's, the relative moisture is 0 at the wilting
        // point and 1 at field capacity (it once held the volumetric content labelled relative).
        const RasterD theta =
            run::read_snapshot_raster(dir / "run.h5", -1, "soil_moisture", dem.grid());
        const RasterD fc = terrain::io::read_hdf5(dir / "run.h5", "/soil/field_capacity");
        const RasterD wp = terrain::io::read_hdf5(dir / "run.h5", "/soil/wilting_point");
        const RasterD vol = terrain::io::read_gdal(dir / "layers/soil_water_content_m3_per_m3.tif");
        const RasterD rel = terrain::io::read_gdal(dir / "layers/relative_soil_moisture.tif");
        double mean_theta = 0, mean_rel = 0;
        for (Eigen::Index k = 0; k < theta.size(); ++k) {
            const double t = theta.data()[k], f = fc.data()[k], w = wp.data()[k];
            REQUIRE(f > w);
            CHECK(vol.data()[k] == Approx(t).epsilon(1e-6)); // Float32 in the file
            CHECK(rel.data()[k] == Approx((t - w) / (f - w)).margin(1e-5));
            mean_theta += t;
            mean_rel += rel.data()[k];
        }
        mean_theta /= static_cast<double>(theta.size());
        mean_rel /= static_cast<double>(theta.size());
        CHECK(mean_theta < 0.6);            // a volumetric content, m3/m3
        CHECK(mean_rel > mean_theta + 0.1); // a silt loam near field capacity: near 1
        const auto info = shell(dir, "gdalinfo layers/soil_water_content_m3_per_m3.tif");
        CHECK_THAT(info.out, Catch::Contains("UNITS=m3/m3"));
        CHECK_THAT(io::read_text(dir / "layers/README.md"),
                   Catch::Contains("| relative_soil_moisture.tif | 1 |"));
    }

    SECTION("region: only the stems inside, the terrain cut to whole cells") {
        auto r =
            test::run(dir, "export scene run.h5 --format gltf -o part.glb --region 10,10,30,26");
        INFO(r.out);
        REQUIRE(r.code == 0);
        const Scene part = load_scene(dir / "run.h5", -1, Region{10, 10, 30, 26});
        CHECK(part.terrain.nx() == 10);
        CHECK(part.terrain.ny() == 8);
        CHECK(part.terrain.grid().origin_x_m == Approx(10));
        std::size_t inside = 0;
        for (const auto& t : s.trees)
            inside += t.x_m >= 10 && t.x_m < 30 && t.y_m >= 10 && t.y_m < 26;
        CHECK(part.trees.size() == inside);
    }

    SECTION("species meshes: a user's OBJ replaces the trees of its species in every format") {
        // A pyramid 2 m tall, y up (as many modelling tools write), with a material library.
        std::ofstream(dir / "cone.obj") << "mtllib cone.mtl\nv -0.5 0 -0.5\nv 0.5 0 -0.5\nv 0.5 0 "
                                           "0.5\nv -0.5 0 0.5\nv 0 2 0\nusemtl leaf\nf 1 2 5\nf "
                                           "2 3 5\nf 3 4 5\nf 4 1 5\nf 4 3 2 1\n";
        std::ofstream(dir / "cone.mtl") << "newmtl leaf\nKd 0.1 0.5 0.1\n";
        std::ofstream(dir / "meshes.json")
            << R"({"meshes": [{"species": "Birch", "obj": "cone.obj", "height_m": 2, "rotate_y_to_z": true}]})";
        std::size_t birches = 0;
        for (const auto& t : s.trees)
            birches += s.species[static_cast<std::size_t>(t.species)].name == "Birch";
        REQUIRE(birches > 0);
        const std::string with = " --species-meshes meshes.json";
        succeeds(dir, "export scene run.h5 --format gltf -o user.glb" + with);
        check_gltf_validator(dir, "user.glb");
        const auto [j, bin] = read_glb(dir / "user.glb");
        std::size_t user_instances = 0;
        for (const auto& node : j["nodes"])
            if (node["name"] == "user_cone_trees") {
                const auto& at = node["extensions"]["EXT_mesh_gpu_instancing"]["attributes"];
                const auto sc = accessor_floats(j, bin, at["SCALE"]);
                const auto ids = accessor_floats(j, bin, at["_PLANT_ID"]);
                for (std::size_t k = 0; k < ids.size(); ++k) {
                    const Tree& t = by_id.at(static_cast<std::int64_t>(ids[k]));
                    CHECK(sc[3 * k + 1] == Approx(t.height_m / 2).epsilon(1e-6));
                    ++user_instances;
                }
            }
        CHECK(user_instances == birches);
        succeeds(dir, "export scene run.h5 --format mavs -o um" + with);
        CHECK(fs::exists(dir / "um/meshes/user_cone.obj"));
        CHECK(fs::exists(dir / "um/meshes/cone.mtl"));
        const json scene = read_json(dir / "um/scene.json");
        std::size_t mavs_user = 0;
        for (const auto& obj : scene["Objects"])
            if (obj["Mesh"] == "meshes/user_cone.obj") {
                CHECK(obj["Rotate Y to Z"] == true);
                mavs_user += obj["Instances"].size();
            }
        CHECK(mavs_user == birches);
        succeeds(dir, "export scene run.h5 --format gazebo -o ug" + with);
        check_sdformat(dir, "ug");
        succeeds(dir, "export scene run.h5 --format unreal -o uu" + with);
        CHECK(fs::exists(dir / "uu/meshes/user_cone.obj"));
        // Bad mesh files: named file, entry, key and value.
        auto bad = [&](const std::string& text, const std::string& expect) {
            std::ofstream(dir / "bad.json") << text;
            const auto b = test::run(
                dir, "export scene run.h5 --format gltf -o bad.glb --species-meshes bad.json");
            CHECK(b.code == 2);
            CHECK_THAT(b.out, Catch::Contains(expect));
            CHECK(!fs::exists(dir / "bad.glb"));
        };
        bad(R"({"meshes": [{"species": "Oak", "obj": "cone.obj", "height_m": 2}]})",
            "'Oak': the run has no such species (Horse chestnut, Birch");
        bad(R"({"meshes": [{"species": "Birch", "obj": "nope.obj", "height_m": 2}]})",
            "meshes[0].obj = 'nope.obj': no such file");
        bad(R"({"meshes": [{"species": "Birch", "stage": "old", "obj": "cone.obj", "height_m": 2}]})",
            "stage = 'old'");
        bad(R"({"meshes": [{"species": "Birch", "obj": "cone.obj", "height_m": 0}]})", "height_m");
        bad(R"({"meshes": [{"species": "Birch", "obj": "cone.obj", "height_m": 2, "scale": 3}]})",
            "unknown key 'scale'");
        std::ofstream(dir / "broken.obj") << "v 0 0 0\nv 1 0 0\nf 1 2 7\n";
        bad(R"({"meshes": [{"species": "Birch", "obj": "broken.obj", "height_m": 2}]})",
            "broken.obj:3: face index 7");
    }

    SECTION("the same export twice gives the same bytes") {
        REQUIRE(test::run(dir, "export scene run.h5 --format gltf -o a.glb").code == 0);
        REQUIRE(test::run(dir, "export scene run.h5 --format gltf -o b.glb").code == 0);
        CHECK(io::read_text(dir / "a.glb") == io::read_text(dir / "b.glb"));
    }

    SECTION("bad input: named, exit 2, nothing written and no user file touched") {
        fs::create_directories(dir / "mine");
        std::ofstream(dir / "mine/notes.txt") << "keep me";
        auto r = test::run(dir, "export scene run.h5 --format mavs -o mine");
        CHECK(r.code == 2);
        CHECK_THAT(r.out, Catch::Contains("--force"));
        CHECK(!fs::exists(dir / "mine/scene.json"));
        r = test::run(dir, "export scene run.h5 --format mavs -o mine --force");
        CHECK(r.code == 0);
        CHECK(io::read_text(dir / "mine/notes.txt") == "keep me");
        CHECK(fs::exists(dir / "mine/scene.json"));
        const std::pair<const char*, const char*> bad[] = {
            {"--format mavs -o x --snapshot 99", "--snapshot 99"},
            {"--format mavs -o x --region 500,500,600,600", "outside the terrain"},
            {"--format mavs -o x --region 1,2,abc,4", "'abc'"},
            {"--format usd -o x", "--format usd"},
            {"--format gazebo -o x --region 0,0,40,20", "square"}};
        for (const auto& [args, expect] : bad) {
            r = test::run(dir, std::string("export scene run.h5 ") + args);
            CHECK(r.code == 2);
            CHECK_THAT(r.out, Catch::Contains(expect));
        }
        CHECK(!fs::exists(dir / "x"));
        // No staging folder is left behind.
        for (const auto& e : fs::directory_iterator(dir.path()))
            CHECK(e.path().filename().string().find(".partial-") == std::string::npos);
    }
}

TEST_CASE("export layers: the input DEM's coordinate system is carried through the run",
          "[export][layers][crs]") {
    test::TempDir dir;
    // A DEM in UTM zone 16N (gdal_translate assigns it), as a field survey would deliver.
    std::ofstream(dir / "scene.json") << test::small_scene(2).dump(2);
    REQUIRE(test::run(dir, "run scene.json -o plain.h5 --no-pictures").code == 0);
    REQUIRE(test::run(dir, "export layers plain.h5 -o plain").code == 0);
    const auto none = shell(dir, "gdalinfo plain/stems_per_ha.tif");
    CHECK_THAT(none.out, !Catch::Contains("UTM"));
    auto r = shell(dir, "gdal_translate -q -a_srs EPSG:32616 -a_ullr 500000 4000040 500040 4000000 "
                        "plain/elevation_m.tif utm.tif");
    INFO(r.out);
    REQUIRE(r.code == 0);
    json scene = test::small_scene(2);
    scene["terrain"] = {{"file", "utm.tif"}};
    std::ofstream(dir / "utm.json") << scene.dump(2);
    r = test::run(dir, "run utm.json -o utm.h5 --no-pictures");
    INFO(r.out);
    REQUIRE(r.code == 0);
    CHECK_THAT(run::read_run_terrain(dir / "utm.h5").crs_wkt(), Catch::Contains("UTM zone 16N"));
    REQUIRE(test::run(dir, "export layers utm.h5 -o layers --region 500010,4000010,500030,4000030")
                .code == 0);
    for (const char* f :
         {"elevation_m", "stems_per_ha", "relative_soil_moisture", "catchment_id"}) {
        r = shell(dir, std::string("gdalinfo layers/") + f + ".tif");
        INFO(r.out);
        CHECK(r.code == 0);
        CHECK_THAT(r.out, Catch::Contains("UTM zone 16N"));
        CHECK_THAT(r.out,
                   Catch::Contains("Origin = (500010.000000000000000,4000030.000000000000000)"));
        CHECK_THAT(r.out, Catch::Contains("Pixel Size = (2.000000000000000,-2.000000000000000)"));
    }
    CHECK_THAT(io::read_text(dir / "layers/README.md"), Catch::Contains("carried from its DEM"));
}

TEST_CASE("export: shrubs and objects keep their stems, the ground layer becomes tufts and a layer",
          "[export][cli][lifeform][slow]") {
    // A tree, a shrub, a grass and a MAVS cube on 40 m x 40 m for 10 years.
    auto entry = [](const std::string& mesh, const std::string& name, double arrivals, double hmax,
                    double ratio) {
        return json{{"Mesh File", mesh},
                    {"Species Name", name},
                    {"Num New Per Area", arrivals},
                    {"Growth Rate", 0.3},
                    {"Max Height", hmax},
                    {"Min Height", 0.0},
                    {"Mesh Height", 1.0},
                    {"Height To Diameter Ratio", ratio},
                    {"Max Age", 60},
                    {"Rotate Mesh", true}};
    };
    test::TempDir dir;
    json shrub = entry("vegetation/yaupon.obj", "Yaupon", 0.004, 3.0, 0.5);
    shrub["physiology"] = {{"seeds_per_yr_at_30cm", 0.0}}; // arrivals only: a few dozen shrubs
    std::ofstream(dir / "eco.json") << json{
        {"Species",
         {entry("vegetation/oak.obj", "Oak", 0.004, 20.0, 0.05), shrub,
          entry("vegetation/grass.obj", "Grass", 1.0, 0.3, 0.05),
          entry("misc/cube.obj", "Cube", 0.003, 1.0,
                0.5)}}}.dump(2);
    json scene = test::small_scene(10);
    scene["vegetation"]["ecosystem"] = (dir / "eco.json").string();
    scene["vegetation"]["initial"] = "bare";
    std::ofstream(dir / "scene.json") << scene.dump(2);
    const std::string out = succeeds(dir, "run scene.json -o run.h5 --no-pictures");
    CHECK_THAT(out, Catch::Contains("ground layer:"));
    const Scene s = load_scene(dir / "run.h5", -1);
    const auto snap = run::read_snapshot_plants(dir / "run.h5", -1);
    std::map<eco::LifeForm, int> forms;
    std::map<std::int64_t, run::PlantRecord> plant;
    for (const auto& p : snap.plants) {
        ++forms[static_cast<eco::LifeForm>(p.life_form)];
        plant[p.id] = p;
    }
    REQUIRE(forms[eco::LifeForm::tree] > 0);
    REQUIRE(forms[eco::LifeForm::shrub] > 0);
    REQUIRE(forms[eco::LifeForm::object] > 0);
    REQUIRE(s.trees.size() == snap.plants.size());
    const auto under = run::read_snapshot_undergrowth(dir / "run.h5", -1);

    // glTF: valid; each instance's trunk is the stem: a shrub's base is its stem at the ground,
    // an object's its footprint (0.5 m), a tree's larger than its DBH (taper to breast height).
    succeeds(dir, "export scene run.h5 --format gltf -o scene.glb");
    check_gltf_validator(dir, "scene.glb");
    const auto [j, bin] = read_glb(dir / "scene.glb");
    std::size_t seen = 0;
    for (const auto& node : j["nodes"]) {
        if (!node.contains("extensions") || !node["name"].get<std::string>().ends_with("_trunks"))
            continue;
        const auto& at = node["extensions"]["EXT_mesh_gpu_instancing"]["attributes"];
        const auto ids = accessor_floats(j, bin, at["_PLANT_ID"]);
        const auto scale = accessor_floats(j, bin, at["SCALE"]);
        for (std::size_t k = 0; k < ids.size(); ++k) {
            const auto& p = plant.at(static_cast<std::int64_t>(ids[k]));
            CAPTURE(p.id, p.life_form);
            const double base = scale[3 * k]; // glTF Y-up: (d, H, d)
            CHECK(scale[3 * k + 1] == Approx(p.height_m).epsilon(1e-6));
            switch (static_cast<eco::LifeForm>(p.life_form)) {
            case eco::LifeForm::shrub:
                CHECK(base == Approx(std::max(p.stem_diameter_m, 1e-3)).epsilon(1e-6));
                break;
            case eco::LifeForm::object:
                CHECK(base == Approx(0.5).epsilon(1e-6));
                break;
            default:
                CHECK(base >= p.dbh_m * (1 - 1e-6));
            }
            ++seen;
        }
    }
    CHECK(seen == snap.plants.size());

    // The ground layer as tufts: their count follows the cover (Poisson, mean cover x area / a
    // tuft's area), every one on the terrain, the same ones in a region cut, and each format
    // holds them all (Gazebo none, with a note).
    REQUIRE(!s.tufts.empty());
    const double expected_tufts = under.ground_cover_fraction * s.terrain.grid().width_m() *
                                  s.terrain.grid().height_m() / kTuftAreaM2;
    CHECK(std::abs(static_cast<double>(s.tufts.size()) - expected_tufts) <
          4 * std::sqrt(expected_tufts));
    for (const auto& t : s.tufts) {
        REQUIRE(s.species[static_cast<std::size_t>(t.species)].name == "Grass");
        CHECK(t.z_m == Approx(s.terrain.sample_bilinear(t.x_m, t.y_m)).margin(1e-9));
    }
    const Scene cut = load_scene(dir / "run.h5", -1, Region{4, 4, 20, 20});
    REQUIRE(!cut.tufts.empty());
    for (const auto& t : cut.tufts) {
        CHECK(t.x_m >= 4);
        CHECK(t.x_m < 20);
        bool found = false;
        for (const auto& u : s.tufts) found = found || (u.x_m == t.x_m && u.y_m == t.y_m);
        CHECK(found);
    }
    std::size_t grass_instances = 0;
    for (const auto& node : j["nodes"])
        if (node["name"] == "grass_grass")
            grass_instances =
                accessor_floats(
                    j, bin,
                    node["extensions"]["EXT_mesh_gpu_instancing"]["attributes"]["TRANSLATION"])
                    .size() /
                3;
    CHECK(grass_instances == s.tufts.size());
    succeeds(dir, "export scene run.h5 --format mavs -o mavs");
    const json mavs = read_json(dir / "mavs/scene.json");
    std::size_t mavs_tufts = 0;
    for (const auto& o : mavs["Objects"])
        if (o["Mesh"] == "meshes/grass_grass.obj") mavs_tufts = o["Instances"].size();
    CHECK(mavs_tufts == s.tufts.size());
    const json veg = read_json(dir / "mavs/veg_override.json");
    bool listed = false;
    for (const auto& v : veg["veg_models"])
        listed = listed || (v["mesh"] == "meshes/grass_grass.obj" && v["diameter"] == 0.01);
    CHECK(listed);
    succeeds(dir, "export scene run.h5 --format unreal -o unreal");
    std::ifstream grass_csv(dir / "unreal/grass.csv");
    std::size_t rows = 0;
    for (std::string line; std::getline(grass_csv, line);) ++rows;
    CHECK(rows == s.tufts.size() + 1);

    // Gazebo: one model per plant, parsed by libsdformat.
    CHECK_THAT(succeeds(dir, "export scene run.h5 --format gazebo -o gz"),
               Catch::Contains("grass tufts are left out"));
    CHECK_THAT(check_sdformat(dir, "gz"),
               Catch::Contains("models " + std::to_string(snap.plants.size() + 1 +
                                                          (s.deadwood.empty() ? 0 : 1))));

    // Layers: the ground cover as the snapshot holds it; stems and basal area count trees only.
    succeeds(dir, "export layers run.h5 -o layers");
    const RasterD cover = terrain::io::read_raster(dir / "layers/ground_cover.tif");
    double mean = 0;
    for (std::int64_t k = 0; k < cover.size(); ++k) mean += cover.data()[k];
    mean /= static_cast<double>(cover.size());
    CHECK(mean == Approx(under.ground_cover_fraction).epsilon(1e-5));
    CHECK(under.ground_cover_fraction > 0.0);
    const RasterD ba = terrain::io::read_raster(dir / "layers/basal_area_m2_per_ha.tif");
    double ba_sum = 0, expect = 0;
    for (std::int64_t k = 0; k < ba.size(); ++k)
        if (std::isfinite(ba.data()[k])) ba_sum += ba.data()[k];
    // The layer integrates to the stand's basal area (per ha, summed over cells of the area).
    const double cell_ha = ba.cell_size() * ba.cell_size() / 1e4;
    for (const auto& p : snap.plants) expect += std::numbers::pi * p.dbh_m * p.dbh_m / 4;
    CHECK(ba_sum * cell_ha == Approx(expect).epsilon(0.05));
}

TEST_CASE("export scene: a DEM at a large northing exports about a local origin, to a millimetre",
          "[export][cli][frame]") {
    // float32 at northings of 4.5e6 m rounds to 0.5 m steps; every format must be local.
    test::TempDir dir;
    std::ofstream(dir / "scene.json") << test::small_scene(2).dump(2);
    REQUIRE(test::run(dir, "run scene.json -o plain.h5 --no-pictures").code == 0);
    REQUIRE(test::run(dir, "export layers plain.h5 -o plain").code == 0);
    const double ox = 612340, oy = 4512300;
    auto r = shell(dir, "gdal_translate -q -a_srs EPSG:32616 -a_ullr 612340 4512340 612380 "
                        "4512300 plain/elevation_m.tif utm.tif");
    INFO(r.out);
    REQUIRE(r.code == 0);
    json scene = test::small_scene(2);
    scene["terrain"] = {{"file", "utm.tif"}};
    std::ofstream(dir / "utm.json") << scene.dump(2);
    succeeds(dir, "run utm.json -o utm.h5 --no-pictures");
    const Scene s = load_scene(dir / "utm.h5", -1);
    REQUIRE(s.trees.size() > 10);
    const auto by_id = trees_by_id(s);
    auto frame_is = [&](const json& f, double x, double y) {
        CHECK(f["origin_x_m"].get<double>() == x);
        CHECK(f["origin_y_m"].get<double>() == y);
        CHECK_THAT(f["crs_wkt"].get<std::string>(), Catch::Contains("UTM zone 16N"));
    };

    // glTF: the instances' float32 translations, plus the sidecar's origin, give every stem.
    succeeds(dir, "export scene utm.h5 --format gltf -o s.glb --no-pictures");
    check_gltf_validator(dir, "s.glb");
    frame_is(read_json(dir / "s.glb.json")["frame"], ox, oy);
    const auto glb = read_glb(dir / "s.glb"); // (clang 14 cannot capture structured bindings)
    const json& j = glb.first;
    const std::string& bin = glb.second;
    std::size_t seen = 0;
    each_trunks_node(j, [&](const json&, const json& at) {
        const auto pos = accessor_floats(j, bin, at["TRANSLATION"]);
        const auto ids = accessor_floats(j, bin, at["_PLANT_ID"]);
        for (std::size_t k = 0; k < ids.size(); ++k, ++seen) {
            const Tree& t = by_id.at(static_cast<std::int64_t>(ids[k]));
            CHECK(pos[3 * k] + ox == Approx(t.x_m).margin(1e-3));
            CHECK(-pos[3 * k + 2] + oy == Approx(t.y_m).margin(1e-3));
        }
    });
    CHECK(seen == s.trees.size());

    // Unreal: the table and the landscape share the local frame.
    succeeds(dir, "export scene utm.h5 --format unreal -o ue --no-pictures");
    frame_is(read_json(dir / "ue/frame.json"), ox, oy);
    std::istringstream csv(io::read_text(dir / "ue/trees.csv"));
    std::string line;
    std::getline(csv, line);
    std::size_t rows = 0;
    while (std::getline(csv, line)) {
        std::vector<std::string> f;
        std::istringstream row(line);
        for (std::string c; std::getline(row, c, ',');) f.push_back(c);
        const Tree& t = by_id.at(std::stoll(f[0].substr(6)));
        CHECK(std::abs(std::stod(f[4])) < 5000); // within the 40 m terrain, cm
        CHECK(std::stod(f[4]) / 100 + ox == Approx(t.x_m).margin(1e-3));
        CHECK(-std::stod(f[5]) / 100 + oy == Approx(t.y_m).margin(1e-3));
        ++rows;
    }
    CHECK(rows == s.trees.size());
    CHECK_THAT(io::read_text(dir / "ue/README.md"), Catch::Contains("Location X 100, Y -3900"));

    // MAVS with an -o ending in '/': one separator in PathToMeshes, positions local.
    succeeds(dir, "export scene utm.h5 --format mavs -o mavs/ --no-pictures");
    const json ms = read_json(dir / "mavs/scene.json");
    const std::string root = ms["PathToMeshes"];
    CHECK(root.find("//") == std::string::npos);
    CHECK(root.ends_with("/"));
    CHECK(fs::exists(root + "terrain.obj"));
    CHECK(fs::exists(ms["VegOverrideFile"].get<std::string>()));
    frame_is(read_json(dir / "mavs/frame.json"), ox, oy);
    for (const auto& obj : ms["Objects"])
        for (const auto& inst : obj["Instances"]) {
            if (obj["Mesh"] == "meshes/deadwood.obj") continue; // one instance at the origin
            const double x = inst["Position"][0].get<double>() + ox;
            const double y = inst["Position"][1].get<double>() + oy;
            std::size_t near = 0;
            for (const auto& t : s.trees) near += std::hypot(t.x_m - x, t.y_m - y) < 1e-6;
            CHECK(near == 1);
        }

    // Gazebo and a user's origin: poses are stems less that origin.
    succeeds(dir,
             "export scene utm.h5 --format gazebo -o gz --no-pictures --origin 612350,4512310");
    frame_is(read_json(dir / "gz/frame.json"), 612350, 4512310);
    const std::string world = io::read_text(dir / "gz/world.sdf");
    for (const auto& t : s.trees) {
        const auto p = world.find("<name>plant_" + std::to_string(t.id) + "</name><pose>");
        REQUIRE(p != std::string::npos);
        std::istringstream pose(world.substr(world.find("<pose>", p) + 6));
        double x = 0, y = 0;
        pose >> x >> y;
        CHECK(x + 612350 == Approx(t.x_m).margin(1e-6));
        CHECK(y + 4512310 == Approx(t.y_m).margin(1e-6));
    }
    r = test::run(dir, "export scene utm.h5 --format gazebo -o gz2 --origin 1,x");
    CHECK(r.code == 2);
    CHECK_THAT(r.out, Catch::Contains("--origin 1,x: 'x' is not a number"));
}

TEST_CASE("species meshes: an OBJ's material libraries are copied only from its own folder",
          "[export][cli][security]") {
    test::TempDir dir;
    std::ofstream(dir / "scene.json") << test::small_scene(2).dump(2);
    succeeds(dir, "run scene.json -o run.h5 --no-pictures");
    fs::create_directories(dir / "m/sub");
    fs::create_directories(dir / "outside");
    std::ofstream(dir / "outside/secret.mtl") << "newmtl secret\nKd 1 0 0\n";
    std::ofstream(dir / "m/sub/ok.mtl") << "newmtl leaf\nKd 0.1 0.5 0.1\n";
    fs::create_symlink(dir / "outside/secret.mtl", dir / "m/link.mtl");
    const std::string faces = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n";
    std::ofstream(dir / "m/meshes.json")
        << R"({"meshes": [{"species": "Birch", "obj": "tree.obj", "height_m": 2}]})";
    struct Case {
        std::string mtllib, expect;
    };
    const Case bad[] = {
        {"/etc/shadow", "tree.obj:1: mtllib '/etc/shadow': an absolute path"},
        {"../outside/secret.mtl", "mtllib '../outside/secret.mtl': leads out of the OBJ's folder"},
        {"sub/../../outside/secret.mtl", "leads out of the OBJ's folder ('..')"},
        {"link.mtl", "mtllib 'link.mtl': leads out of the OBJ's folder (to "},
        {"missing.mtl", "mtllib 'missing.mtl': no such file"},
        {"sub/ok.mtl /etc/passwd", "mtllib '/etc/passwd': an absolute path"},
    };
    for (const auto& c : bad)
        for (const char* format : {"mavs", "unreal", "gazebo", "gltf"}) {
            CAPTURE(c.mtllib, format);
            std::ofstream(dir / "m/tree.obj", std::ios::trunc)
                << "mtllib " + c.mtllib + "\n" + faces;
            const auto r =
                test::run(dir, std::string("export scene run.h5 --no-pictures --format ") + format +
                                   " -o out --species-meshes m/meshes.json");
            CHECK(r.code == 2);
            CHECK_THAT(r.out, Catch::Contains(c.expect));
            CHECK_FALSE(fs::exists(dir / "out"));
        }
    // Inside the folder, in a sub-folder: copied where the OBJ looks for it.
    std::ofstream(dir / "m/tree.obj", std::ios::trunc) << "mtllib sub/ok.mtl\n" + faces;
    succeeds(dir, "export scene run.h5 --no-pictures --format mavs -o out --species-meshes "
                  "m/meshes.json");
    CHECK(io::read_text(dir / "out/meshes/sub/ok.mtl") == io::read_text(dir / "m/sub/ok.mtl"));
    for (const auto& e : fs::recursive_directory_iterator(dir / "out"))
        CHECK(e.path().filename() != "secret.mtl");
}
