// The analyses of a run file from Python (docs/python.md): mobility lines and scene exports, with
// the options and messages of `ecoterra mobility`, `ecoterra export scene` and the ensembles.
#include "bindings.hpp"

#include "ecoterra/analyses/analyses.hpp"
#include "ecoterra/error.hpp"
#include "ecoterra/export/formats.hpp"
#include "ecoterra/export/scene.hpp"
#include "ecoterra/io/staging.hpp"
#include "ecoterra/mobility/map.hpp"
#include "ecoterra/mobility/stand.hpp"
#include "ecoterra/run/run_reader.hpp"

#include <pybind11/stl.h>

namespace ecoterra::python {

namespace {

/// Keyword arguments as a JSON object, each value checked as JSON.
nlohmann::json keyword_json(const py::kwargs& kw, const std::string& what) {
    nlohmann::json a = nlohmann::json::object();
    for (const auto& [k, v] : kw) a[py::cast<std::string>(k)] = to_json(v, what);
    return a;
}

/// Speed made good along random lines through snapshot `snapshot` of the run file, as the
/// ensembles' `mobility` analysis drives them; `options` are its keys (docs/parameters.md,
/// analyses.mobility: vehicle, lines, length_m, seed, soil, deadwood, effects, ...).
py::object mobility(const std::filesystem::path& run_file, int snapshot,
                    const py::kwargs& options) {
    const nlohmann::json a = keyword_json(options, "mobility");
    const auto opt =
        with_context("mobility", [&] { return analyses::mobility_catalog().read(a, {}); });
    nlohmann::json out;
    {
        py::gil_scoped_release free;
        const auto v = mobility::load_vehicle(opt.vehicle);
        const auto w = run::read_driving_world(run_file, snapshot, opt.deadwood, opt.soil);
        auto lines = opt.lines_options();
        if (w.ground) lines.smg.ground = w.ground->maps();
        const auto r = mobility::analyse_stand(v, w.stems, w.dem, lines, w.dead.logs);
        out = analyses::mobility_json(r, v);
        out["seed"] = opt.seed;
    }
    return from_json(out);
}

/// The mobility map of snapshot `snapshot` of the run file, as the ensembles' `mobility_map`
/// analysis makes it (`options`: its keys: vehicle, cell_m, headings, soil, deadwood, ...): the
/// summary as `ecoterra mobility map` writes it, with the mean speed (m/s), the GO share (1) and
/// the limiting factor per cell as numpy arrays (ny, nx).
py::object mobility_map(const std::filesystem::path& run_file, int snapshot,
                        const py::kwargs& options) {
    const nlohmann::json a = keyword_json(options, "mobility_map");
    const auto opt =
        with_context("mobility_map", [&] { return analyses::mobility_map_catalog().read(a, {}); });
    std::optional<mobility::MobilityMap> map;
    {
        py::gil_scoped_release free;
        const auto v = mobility::load_vehicle(opt.vehicle);
        const auto w = run::read_driving_world(run_file, snapshot, opt.deadwood, opt.soil);
        map = mobility::mobility_map(v, w.dem, w.stems, w.dead.logs,
                                     w.ground ? w.ground->maps() : mobility::GroundMaps{},
                                     opt.map_options());
    }
    py::dict d = from_json(mobility::to_json(*map));
    d["speed_mean_m_per_s"] = raster_copy(map->speed_mean_m_per_s);
    d["go_fraction"] = raster_copy(map->go_fraction);
    d["limiting"] = raster_copy(map->limiting);
    return d;
}

/// `ecoterra export scene`: snapshot `snapshot` of the run file as scenes for simulators, one
/// folder per format under `output` (scene_gltf/, scene_mavs/, ...); the folders written.
std::vector<std::string> export_scene(const std::filesystem::path& run_file,
                                      const std::filesystem::path& output,
                                      const std::vector<std::string>& formats, int snapshot,
                                      bool force) {
    namespace ex = ecoterra::exporter;
    if (formats.empty()) throw InputError("export_scene: give at least one format");
    std::vector<ex::SceneFormat> fs;
    for (const auto& f : formats) fs.push_back(ex::scene_format_from_name(f));
    std::vector<std::string> written;
    py::gil_scoped_release free;
    const ex::Scene s = ex::in_local_frame(ex::load_scene(run_file, snapshot));
    std::filesystem::create_directories(output);
    for (std::size_t k = 0; k < fs.size(); ++k) {
        const std::filesystem::path dir = output / ("scene_" + formats[k]);
        io::OutputFolder folder(dir, force);
        ex::ExportOptions opt;
        opt.final_dir = dir;
        ex::write_scene(s, fs[k], folder, opt);
        folder.commit();
        written.push_back(dir.string());
    }
    return written;
}

} // namespace

void register_analyses(py::module_& m) {
    m.def("mobility", &mobility, py::arg("run_file"), py::arg("snapshot") = -1,
          "speed made good of a vehicle along random lines through a run's snapshot, as the "
          "ensembles' mobility analysis (keys as keywords: vehicle=..., lines=200, ...); the "
          "figures as `ecoterra mobility --json` writes them");
    m.def("mobility_map", &mobility_map, py::arg("run_file"), py::arg("snapshot") = -1,
          "the mobility map of a run's snapshot, as the ensembles' mobility_map analysis (keys as "
          "keywords: vehicle=..., cell_m=..., headings=8, ...): its summary and its rasters");
    m.def("export_scene", &export_scene, py::arg("run_file"), py::arg("output"),
          py::arg("formats") = std::vector<std::string>{"gltf"}, py::arg("snapshot") = -1,
          py::arg("force") = false,
          "`ecoterra export scene`: formats among gltf, mavs, gazebo, unreal; the folders written");
}

} // namespace ecoterra::python
