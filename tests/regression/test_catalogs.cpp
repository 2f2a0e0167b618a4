// The catalogues as properties: every key of every parameter catalogue, set to a value other than
// its default, survives the resolved JSON a run stores and the scene that resume rebuilds from it;
// every output column is written and read back; docs/parameters.md is what the catalogues say.
#include "support/run_cli.hpp"
#include "support/scenes.hpp"
#include "support/temp_dir.hpp"

#include "ecoterra/analyses/describe.hpp"
#include "ecoterra/eco/ecosystem.hpp"
#include "ecoterra/eco/outputs.hpp"
#include "ecoterra/eco/scene_config.hpp"
#include "ecoterra/eco/species.hpp"
#include "ecoterra/hydro/scene.hpp"
#include "ecoterra/run/records.hpp"
#include "ecoterra/run/run.hpp"
#include "ecoterra/run/run_reader.hpp"
#include "ecoterra/terrain/generate.hpp"
#include "ecoterra/terrain/io/raster_io.hpp"

#include <H5Cpp.h>
#include <catch2/catch.hpp>

#include <fstream>
#include <functional>
#include <sstream>

using namespace ecoterra;
using nlohmann::json;

namespace {

/// Values to try for a parameter other than its default: the range's ends and middle, the other
/// choices, the other flag value.
template <class S>
std::vector<json> other_values(const Param<S>& p, const json& current) {
    std::vector<json> v;
    switch (p.kind) {
    case ParamKind::number:
    case ParamKind::integer: {
        const double lo = std::isfinite(p.min) ? p.min : -1e3;
        const double hi = std::isfinite(p.max) ? p.max : 1e3;
        for (double x : {lo, hi, 0.5 * (lo + hi), lo + 0.01 * (hi - lo), hi - 0.01 * (hi - lo),
                         0.25 * (lo + hi)}) {
            if (p.kind == ParamKind::integer) x = std::round(x);
            if (p.kind == ParamKind::integer ? json(static_cast<long long>(x)) != current
                                             : json(x) != current)
                v.push_back(p.kind == ParamKind::integer ? json(static_cast<long long>(x))
                                                         : json(x));
        }
        break;
    }
    case ParamKind::flag:
        v.push_back(!current.get<bool>());
        break;
    case ParamKind::choice:
        for (const auto& c : p.choices)
            if (json(c) != current) v.push_back(c);
        break;
    case ParamKind::text:
        v.push_back(current.get<std::string>() + "_other");
        break;
    case ParamKind::choices:
        for (const auto& c : p.choices)
            if (json::array({c}) != current) v.push_back(json::array({c}));
        break;
    }
    return v;
}

json* at_path(json& j, const std::string& dotted) {
    json* node = &j;
    std::size_t start = 0;
    for (;;) {
        const auto dot = dotted.find('.', start);
        node = &(*node)[dotted.substr(start, dot - start)];
        if (dot == std::string::npos) return node;
        start = dot + 1;
    }
}

/// For each key of catalogue `c` (section `section` of the scene): some other value loads,
/// appears in the resolved scene, and the scene rebuilt from the resolved JSON (as resume does)
/// has the same value and the same resolved JSON. `fix` may mend the section after a key changed
/// (a rule across keys, such as sand + silt + clay = 100).
template <class S, class Load, class Get>
void check_scene_catalog(const ParamCatalog<S>& c, const json& base, Load load, Get get,
                         const std::function<void(json&, const std::string&)>& fix = {}) {
    const auto base_scene = load(base);
    for (const auto& p : c.params()) {
        const std::string key = c.section() + "." + p.key;
        const json current = p.get(get(base_scene));
        bool tried = false;
        for (const json& v : other_values(p, current)) {
            json scene = base;
            *at_path(scene, key) = v;
            if (fix) fix(*at_path(scene, c.section()), p.key);
            try {
                const auto first = load(scene);
                json resolved = first.resolved;
                INFO(key << " = " << v.dump());
                CHECK(*at_path(resolved, key) == v);
                const auto again = load(resolved);
                CHECK(again.resolved == resolved);
                CHECK(p.get(get(again)) == v);
                tried = true;
                break;
            } catch (const InputError&) {
                // Another key limits this one (a cross-key rule): try the next value.
            }
        }
        INFO(key << ": no value other than the default " << current.dump() << " loads");
        CHECK(tried);
    }
}

json read_json_file(const std::filesystem::path& p) {
    std::ifstream f(p);
    std::stringstream ss;
    ss << f.rdbuf();
    return json::parse(ss.str());
}

} // namespace

TEST_CASE("every scene key round-trips through the resolved scene and a resume") {
    test::TempDir dir;
    // Small grid so that each load is quick.
    json eco_base = test::small_scene(1);
    eco_base["terrain"]["generate"]["size"] = 8;
    auto load_eco = [&](const json& s) { return eco::load_eco_scene(s, dir.path()); };
    auto eco_self = [](const eco::EcoScene& e) -> const eco::EcoScene& { return e; };
    auto hydro_opts = [](const eco::EcoScene& e) -> const hydro::HydrologyOptions& {
        return e.hydro.options;
    };
    auto climate = [](const eco::EcoScene& e) -> const hydro::Climate& { return e.hydro.climate; };
    check_scene_catalog(eco::vegetation_catalog(), eco_base, load_eco, eco_self);
    check_scene_catalog(eco::eco_simulation_catalog(), eco_base, load_eco, eco_self);
    check_scene_catalog(hydro::hydrology_catalog(), eco_base, load_eco, hydro_opts);
    check_scene_catalog(hydro::climate_catalog(), eco_base, load_eco, climate);
    // vegetation.initial.random below its own section.
    auto initial = [](const eco::EcoScene& e) -> const eco::InitialPlants& { return e.initial; };
    check_scene_catalog(eco::initial_random_catalog(), eco_base, load_eco, initial);

    json hydro_base = eco_base;
    hydro_base.erase("vegetation");
    hydro_base["simulation"].erase("snapshot_interval_years");
    auto load_hydro = [&](const json& s) { return hydro::load_hydro_scene(s, dir.path()); };
    auto hydro_self = [](const hydro::HydroScene& h) -> const hydro::HydroScene& { return h; };
    check_scene_catalog(hydro::hydro_simulation_catalog(), hydro_base, load_hydro, hydro_self);

    // Soil and the hydrology scene's vegetation cover (the file keys are checked below).
    auto uniform = [](const eco::EcoScene& e) -> const hydro::SoilComposition& {
        return e.hydro.soil_spec.uniform;
    };
    // A changed fraction takes its difference from another, so the three still sum to 100.
    auto sum_to_100 = [](json& soil, const std::string& key) {
        const std::string other = key == "silt_pct" ? "sand_pct" : "silt_pct";
        if (key != "sand_pct" && key != "silt_pct" && key != "clay_pct") return;
        double rest = 100.0;
        for (const char* k : {"sand_pct", "silt_pct", "clay_pct"})
            if (k != other) rest -= soil.value(k, 0.0);
        soil[other] = rest;
    };
    check_scene_catalog(hydro::soil_composition_catalog(), eco_base, load_eco, uniform, sum_to_100);
    json random_base = eco_base;
    random_base["soil"] = {{"random", {{"sand_pct", 30}, {"silt_pct", 50}, {"clay_pct", 20}}}};
    auto random = [](const eco::EcoScene& e) -> const hydro::RandomSoilParams& {
        return e.hydro.soil_spec.random;
    };
    check_scene_catalog(hydro::random_soil_catalog(), random_base, load_eco, random, sum_to_100);
    const ParamCatalog<hydro::VegetationCover> density_only(
        "vegetation", {hydro::vegetation_cover_catalog().params().front()});
    auto cover = [](const hydro::HydroScene& h) -> const hydro::VegetationCover& {
        return h.cover;
    };
    check_scene_catalog(density_only, hydro_base, load_hydro, cover);
}

TEST_CASE("file keys of a scene resolve to paths that a resume finds from any folder") {
    test::TempDir dir;
    json base = test::small_scene(1);
    base["terrain"]["generate"]["size"] = 8;
    const auto first = eco::load_eco_scene(base, dir.path());
    const GridSpec g = first.hydro.dem.grid();
    // Soil and vegetation rasters on the terrain's grid, named relative to the scene's folder.
    RasterD sand(g, 40.0), silt(g, 40.0), clay(g, 20.0), ph(g, 5.5), density(g, 0.25);
    sand(3, 4) = 60.0;
    silt(3, 4) = 20.0;
    for (const auto& [r, name] : {std::pair<const RasterD*, const char*>{&sand, "sand.asc"},
                                  {&silt, "silt.asc"},
                                  {&clay, "clay.asc"},
                                  {&ph, "ph.asc"},
                                  {&density, "density.asc"}})
        terrain::io::write_raster(*r, dir.path() / name);
    json scene = base;
    scene["soil"] = {{"rasters",
                      {{"sand_pct", "sand.asc"},
                       {"silt_pct", "silt.asc"},
                       {"clay_pct", "clay.asc"},
                       {"ph", "ph.asc"}}}};
    const auto a = eco::load_eco_scene(scene, dir.path());
    // The resolved scene names absolute paths; rebuilt from another folder it is the same scene.
    const auto b = eco::load_eco_scene(a.resolved, "/");
    CHECK(b.resolved == a.resolved);
    CHECK(std::filesystem::path(a.resolved["soil"]["rasters"]["sand_pct"].get<std::string>())
              .is_absolute());
    CHECK(b.hydro.soil.sand_pct(3, 4) == 60.0);
    CHECK(b.hydro.soil.ph(0, 0) == 5.5);
    json missing = scene;
    missing["soil"]["rasters"].erase("clay_pct");
    CHECK_THROWS_WITH(eco::load_eco_scene(missing, dir.path()),
                      Catch::Contains("soil.rasters.clay_pct"));

    json hscene = base;
    hscene.erase("vegetation");
    hscene["simulation"].erase("snapshot_interval_years");
    hscene["vegetation"] = {{"density_file", "density.asc"}};
    const auto h = hydro::load_hydro_scene(hscene, dir.path());
    const auto h2 = hydro::load_hydro_scene(h.resolved, "/");
    CHECK(h2.resolved == h.resolved);
    CHECK(h2.vegetation_density(1, 1) == 0.25);
    hscene["vegetation"]["density"] = 0.5;
    CHECK_THROWS_WITH(hydro::load_hydro_scene(hscene, dir.path()), Catch::Contains("not both"));
}

TEST_CASE("every species key round-trips through the species JSON a run stores") {
    const json eco_file = read_json_file(test::data_dir() / "ecosystems/southwest_desert.json");
    for (const auto* cat : {&eco::mavs_species_catalog(), &eco::physiology_catalog()}) {
        const auto def = eco::parse_ecosystem(eco_file, "eco.json");
        const eco::Species& s0 = def.species.front();
        for (const auto& p : cat->params()) {
            const std::string key = cat->section().empty() ? p.key : cat->section() + "." + p.key;
            bool tried = false;
            for (const json& v : other_values(p, p.get(s0))) {
                json f = eco_file;
                *at_path(f["Species"][0], key) = v;
                try {
                    const auto a = eco::parse_ecosystem(f, "eco.json");
                    const json stored = eco::species_to_json(a.species.front());
                    json lookup = stored; // at_path inserts null where a key is missing
                    INFO(key << " = " << v.dump());
                    CHECK(*at_path(lookup, key) == v);
                    json again_file = eco_file;
                    again_file["Species"][0] = stored;
                    const auto b = eco::parse_ecosystem(again_file, "eco.json");
                    CHECK(eco::species_to_json(b.species.front()) == stored);
                    tried = true;
                    break;
                } catch (const InputError&) {
                }
            }
            INFO(key << ": no value other than the default loads");
            CHECK(tried);
        }
    }
}

TEST_CASE("every terrain generator key round-trips through the resolved specification") {
    const auto all = terrain::describe_terrain_params();
    const auto& grid_keys = all.front().second; // "grid and seed": keys of every method
    REQUIRE(all.front().first.rfind("grid and seed", 0) == 0);
    for (std::size_t m = 1; m < all.size(); ++m) {
        const std::string& method = all[m].first;
        const json base = {{"method", method}, {"size", 8}, {"cell_size_m", 1.0}};
        const json resolved = terrain::resolve_terrain_spec(base);
        // The resolved specification is a fixed point: resolving it again changes nothing.
        CHECK(terrain::resolve_terrain_spec(resolved) == resolved);
        std::vector<ParamInfo> keys = all[m].second;
        for (const auto& i : grid_keys)
            if (i.key != "method" && i.key != "preset" && i.key != "size") keys.push_back(i);
        for (const auto& i : keys) {
            if (i.key == "params.D" || i.key == "params.d_high") continue; // aliases
            INFO(method << " " << i.key);
            json lookup = resolved; // at_path inserts null where a key is missing
            const json current = *at_path(lookup, i.key);
            REQUIRE_FALSE(current.is_null());
            if (!current.is_number()) continue;
            // Another value (nearby, so that rules across keys still hold) loads, is resolved as
            // given, and stays through a second resolve.
            bool tried = false;
            const double c = current.get<double>();
            for (const double x : {c * 1.1, c * 0.9, c + 1, c - 1, c + 0.01, c - 0.01}) {
                const json v = current.is_number_integer() ? json(std::llround(x)) : json(x);
                if (v == current) continue;
                json spec = resolved;
                *at_path(spec, i.key) = v;
                try {
                    const json r = terrain::resolve_terrain_spec(spec);
                    json rl = r;
                    CHECK(*at_path(rl, i.key) == v);
                    CHECK(terrain::resolve_terrain_spec(r) == r);
                    tried = true;
                    break;
                } catch (const InputError&) {
                }
            }
            CHECK(tried);
        }
    }
}

TEST_CASE("every output column is written and read back") {
    test::TempDir dir;
    const auto scene = eco::load_eco_scene(test::small_scene(2), dir.path());
    run::RunOptions opt;
    opt.output = dir / "run.h5";
    opt.pictures = false;
    opt.provenance = {{"software", "ecoterra"}, {"version", "test"}};
    run::run_ecosystem(&scene, opt);
    // The same run in memory.
    eco::Ecosystem e(scene);
    e.run_year();
    e.run_year();
    // Snapshot plants: every column, every plant.
    const auto snap = run::read_snapshot_plants(dir / "run.h5", -1);
    REQUIRE(snap.plants.size() == e.plants().size());
    REQUIRE(!snap.plants.empty());
    for (const auto& c : run::plant_columns()) {
        INFO("plant column " << c.name);
        std::vector<double> expect;
        for (const auto& p : eco::rows(e.plants()))
            expect.push_back(c.get(run::plant_record(p, e.scene().ecosystem.species[p.species])));
        CHECK(snap.values(c.name) == expect);
    }
    // Yearly and daily series: every column with its unit.
    H5::H5File f((dir / "run.h5").string(), H5F_ACC_RDONLY);
    auto check_table = [&](const std::string& group, const Table& t) {
        REQUIRE(t.rows() > 0);
        for (std::size_t k = 0; k < t.names.size(); ++k) {
            INFO(group << "/" << t.names[k]);
            H5::DataSet ds = f.openDataSet(group + "/" + t.names[k]);
            hsize_t n = 0;
            ds.getSpace().getSimpleExtentDims(&n);
            std::vector<double> v(n);
            ds.read(v.data(), H5::PredType::NATIVE_DOUBLE);
            CHECK(v == t.columns[k]);
            std::string unit;
            H5::Attribute a = ds.openAttribute("units");
            a.read(a.getStrType(), unit);
            CHECK(unit == t.units[k]);
        }
    };
    check_table("/series/yearly", e.yearly());
    check_table("/series/daily", e.daily());
    CHECK(e.yearly().names.size() == eco::yearly_columns().size());
    // Raster layers: the soil maps and the last snapshot's water state, values and units, as the
    // in-memory engine has them (stored as float32 where the type says so).
    auto check_layer_in = [&](const H5::H5File& file, const std::string& path,
                              const std::string& unit, const std::string& type, auto raster) {
        INFO(path);
        H5::DataSet ds = file.openDataSet(path);
        hsize_t dims[2] = {0, 0};
        ds.getSpace().getSimpleExtentDims(dims);
        REQUIRE(dims[0] == static_cast<hsize_t>(raster.ny()));
        REQUIRE(dims[1] == static_cast<hsize_t>(raster.nx()));
        std::vector<double> v(dims[0] * dims[1]);
        ds.read(v.data(), H5::PredType::NATIVE_DOUBLE);
        for (std::size_t k = 0; k < v.size(); ++k) {
            const double want = type == "float32" ? static_cast<float>(raster.data()[k])
                                                  : static_cast<double>(raster.data()[k]);
            if (std::isnan(want) ? !std::isnan(v[k]) : v[k] != want) {
                FAIL_CHECK("cell " << k << ": " << v[k] << " != " << want);
                break;
            }
        }
        std::string u;
        H5::Attribute a = ds.openAttribute("units");
        a.read(a.getStrType(), u);
        CHECK(u == unit);
        const H5T_class_t cls = ds.getTypeClass();
        CHECK(cls == (type == "float32" ? H5T_FLOAT : H5T_INTEGER));
    };
    auto check_layer = [&](const std::string& path, const std::string& unit,
                           const std::string& type,
                           auto raster) { check_layer_in(f, path, unit, type, raster); };
    const auto& soil = e.hydrology().soil();
    check_layer("/soil/sand_pct", "%", "float32", soil.sand_pct);
    check_layer("/soil/texture_class", "1", "uint8", soil.texture);
    check_layer("/soil/ksat_m_per_s", "m/s", "float32", soil.ksat_m_per_s);
    CHECK(hydro::soil_map_layers().size() == 9);
    for (const auto& l : hydro::soil_map_layers()) CHECK(f.nameExists("/soil/" + l.name));
    const auto& hy = e.hydrology();
    const auto info = run::read_run_info(dir / "run.h5");
    // Through the run file's link to the snapshot file's group /NNNN (docs/formats.md).
    char name[32];
    std::snprintf(name, sizeof name, "/snapshots/%04d", info.snapshots - 1);
    const std::string s = name;
    check_layer(s + "/soil_moisture", "m3/m3", "float32", hy.soil_moisture());
    check_layer(s + "/critical_layer_moisture", "m3/m3", "float32", hy.critical_layer_moisture());
    check_layer(s + "/surface_water_depth_m", "m", "float32", hy.surface_water_depth());
    check_layer(s + "/catchment_id", "1", "int32", hy.catchment_ids());
    check_layer(s + "/water_table_depth_m", "m", "float32", hy.water_table_depth());
    CHECK(hydro::water_state_layers().size() == 5);
    // The stem CSV: the catalogue's header and one row per plant.
    const std::string csv = run::stem_csv(snap.plants, {"a", "b", "c", "d", "e", "f"});
    std::string header;
    for (const auto& c : run::stem_csv_columns()) header += (header.empty() ? "" : ",") + c.name;
    CHECK(csv.substr(0, csv.find('\n')) == header);
    CHECK(static_cast<std::size_t>(std::count(csv.begin(), csv.end(), '\n')) ==
          snap.plants.size() + 1);
}

TEST_CASE("docs/parameters.md is what the catalogues say") {
    std::ifstream f(std::filesystem::path(ECOTERRA_DATA_DIR) / "../docs/parameters.md");
    REQUIRE(f.good());
    std::stringstream ss;
    ss << f.rdbuf();
    const std::string expected = analyses::describe("all", true);
    INFO("regenerate with: ecoterra describe all --markdown > docs/parameters.md");
    CHECK(ss.str() == expected);
}

TEST_CASE("ecoterra describe prints the catalogues and refuses unknown topics") {
    test::TempDir dir;
    const auto ok = test::run(dir, "describe scene");
    CHECK(ok.code == 0);
    CHECK_THAT(ok.out, Catch::Contains("hydrology.root_zone_depth_m") &&
                           Catch::Contains("[0.01, 10]") && Catch::Contains("vegetation.shading"));
    const auto bad = test::run(dir, "describe vehicles");
    CHECK(bad.code == 2);
    CHECK_THAT(bad.out, Catch::Contains("unknown topic 'vehicles'"));
}
