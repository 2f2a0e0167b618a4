// ecoterra.Run: the coupled engine stepped from Python (docs/python.md), and ecoterra.run(), the
// program's `ecoterra run`.
#include "bindings.hpp"

#include "ecoterra/analyses/analyses.hpp"
#include "ecoterra/archive.hpp"
#include "ecoterra/eco/ecosystem.hpp"
#include "ecoterra/error.hpp"
#include "ecoterra/provenance.hpp"
#include "ecoterra/run/records.hpp"
#include "ecoterra/run/run.hpp"

#include <pybind11/stl.h>

#include <memory>

namespace ecoterra::python {

namespace {

/// A run stepped from Python. The engine holds its own copy of the scene.
class PyRun {
public:
    explicit PyRun(const PyScene& s) : m_eco(std::make_shared<eco::Ecosystem>(s.scene)) {}
    explicit PyRun(std::unique_ptr<eco::Ecosystem> e) : m_eco(std::move(e)) {}

    eco::Ecosystem& engine() {
        if (!m_eco) throw Error("this ecoterra.Run is closed");
        return *m_eco;
    }
    /// The owner of a view: it keeps the engine alive while the view lives, even past close().
    py::object view_owner() {
        engine();
        return keep_alive(m_eco);
    }
    void close() { m_eco.reset(); }
    bool closed() const { return !m_eco; }

private:
    std::shared_ptr<eco::Ecosystem> m_eco;
};

/// The state as a checkpoint's bytes, its series inside (a run file's /checkpoint/state keeps them
/// in the file's /series).
py::bytes state_bytes(PyRun& r) {
    ArchiveWriter a;
    r.engine().save_state(a);
    const auto& b = a.bytes();
    return {reinterpret_cast<const char*>(b.data()), b.size()};
}

std::unique_ptr<PyRun> from_state(const PyScene& s, const py::bytes& state) {
    auto run = std::make_unique<PyRun>(s);
    const std::string b = state;
    ArchiveReader r(reinterpret_cast<const std::uint8_t*>(b.data()), b.size(), "state");
    with_context("state", [&] { run->engine().load_state(r); });
    return run;
}

/// The live plants as columns (the snapshot's plant table, docs/formats.md): name -> numpy array.
py::dict plant_table(PyRun& r) {
    const auto& e = r.engine();
    const auto& species = e.scene().ecosystem.species;
    std::vector<run::PlantRecord> rec;
    for (const auto& p : eco::rows(e.plants()))
        if (p.alive) rec.push_back(run::plant_record(p, species[p.species]));
    py::dict d;
    for (const auto& c : run::plant_columns()) {
        py::array_t<double> a(static_cast<py::ssize_t>(rec.size()));
        double* out = a.mutable_data();
        for (std::size_t k = 0; k < rec.size(); ++k) out[k] = c.get(rec[k]);
        d[py::str(c.name)] =
            c.type == ColumnType::float64 ? py::object(a) : py::object(a.attr("astype")("int64"));
    }
    return d;
}

py::dict table_dict(const Table& t) {
    py::dict d;
    for (std::size_t k = 0; k < t.names.size(); ++k)
        d[py::str(t.names[k])] =
            py::array_t<double>(static_cast<py::ssize_t>(t.columns[k].size()), t.columns[k].data());
    return d;
}

py::dict units_dict(const Table& t) {
    py::dict d;
    for (std::size_t k = 0; k < t.names.size(); ++k) d[py::str(t.names[k])] = t.units[k];
    return d;
}

/// ecoterra.run(): the program's `ecoterra run` (snapshots, checkpoint, resume, pictures).
py::object run_file(const py::handle& scene, const std::filesystem::path& output,
                    std::optional<int> years, bool resume, bool pictures, bool force) {
    run::RunOptions opt;
    opt.output = output;
    opt.resume = resume;
    opt.replace = force;
    opt.pictures = pictures;
    opt.years = years;
    std::optional<eco::EcoScene> sc;
    if (!scene.is_none()) {
        const auto& s = py::cast<const PyScene&>(scene);
        sc = s.scene;
        opt.provenance = provenance({{"scene_file", "python"}, {"overrides", s.set}});
        if (years && !resume) {
            sc->years = *years;
            sc->resolved["simulation"]["years"] = *years;
            opt.years.reset();
        }
    } else {
        opt.provenance = provenance();
    }
    const run::RunSummary sum = [&] {
        py::gil_scoped_release free;
        return run::run_ecosystem(sc ? &*sc : nullptr, opt);
    }();
    py::dict d;
    d["years_run"] = sum.years_run;
    d["years_total"] = sum.years_total;
    d["snapshots"] = sum.snapshots;
    d["reached_target"] = sum.reached_target;
    d["stand"] = from_json(analyses::stand_json(sum.stand));
    d["water_residual_relative"] = sum.water_residual_relative;
    d["carbon_residual_relative"] = sum.carbon_residual_relative;
    d["seconds"] = sum.seconds;
    d["plant_years"] = sum.plant_years;
    return d;
}

void register_run_state(py::class_<PyRun>& c) {
    c.def("state", &state_bytes, "the engine's state as a checkpoint's bytes")
        .def_static("from_state", &from_state, py::arg("scene"), py::arg("state"),
                    "a run of `scene` continued from state() bytes")
        .def_static(
            "from_run_file",
            [](const std::filesystem::path& path) {
                return std::make_unique<PyRun>(run::load_run_engine(path));
            },
            py::arg("path"), "the run in an ecoterra run file (RUN.h5), at its last checkpoint")
        .def(
            "write",
            [](PyRun& r, const std::filesystem::path& path, bool force) {
                run::write_run_file(r.engine(), path, provenance({{"scene_file", "python"}}),
                                    force);
            },
            py::arg("path"), py::arg("force") = false,
            "writes the run as it stands into a run file (one snapshot and the checkpoint), read "
            "by ecoterra.mobility, ecoterra.export_scene and every ecoterra command")
        .def("close", &PyRun::close, "frees the engine; any later call raises ecoterra.Error")
        .def_property_readonly("closed", &PyRun::closed);
}

/// A read-only view over one of the engine's rasters; the view keeps the engine alive.
template <class Get>
auto engine_view(Get get) {
    return [get](PyRun& r) { return raster_view(get(r.engine()), r.view_owner()); };
}

void register_run_fields(py::class_<PyRun>& c) {
    // Views: read-only numpy arrays over the engine's own memory (no copy); they change as the
    // run steps, and keep the engine alive even after close(). Row j is the j-th from the south.
    using E = eco::Ecosystem;
    c.def_property_readonly("soil_moisture", engine_view([](E& e) -> const RasterD& {
                                return e.hydrology().soil_moisture();
                            }),
                            "root-zone water content, m3/m3 (view)")
        .def_property_readonly("critical_layer_moisture", engine_view([](E& e) -> const RasterD& {
                                   return e.hydrology().critical_layer_moisture();
                               }),
                               "water content of the critical layer, m3/m3 (view)")
        .def_property_readonly(
            "elevation", engine_view([](E& e) -> const RasterD& { return e.scene().hydro.dem; }),
            "terrain elevation, m (view)")
        .def_property_readonly("vegetation_density", engine_view([](E& e) -> const RasterD& {
                                   return e.hydrology().vegetation_density();
                               }),
                               "vegetation density 0..1 seen by the runoff, 1 (view)")
        .def_property_readonly(
            "surface_water_depth",
            [](PyRun& r) { return raster_copy(r.engine().hydrology().surface_water_depth()); },
            "standing water depth, m (a copy)")
        .def_property_readonly(
            "water_table_depth",
            [](PyRun& r) { return raster_copy(r.engine().hydrology().water_table_depth()); },
            "depth of the water table below the surface, m; NaN without groundwater (a copy)")
        .def_property_readonly(
            "terrain_grid", [](PyRun& r) { return grid_dict(r.engine().scene().hydro.dem.grid()); })
        .def_property_readonly("plant_grid",
                               [](PyRun& r) { return grid_dict(r.engine().plant_grid()); });
}

void register_run_plants(py::class_<PyRun>& c) {
    c.def("plants", &plant_table,
          "the live plants: {column: numpy array}, the columns of a snapshot's plant table")
        .def_property_readonly("species",
                               [](PyRun& r) {
                                   std::vector<std::string> n;
                                   for (const auto& s : r.engine().scene().ecosystem.species)
                                       n.push_back(s.name);
                                   return n;
                               })
        .def(
            "remove_plants",
            [](PyRun& r, const std::vector<std::int64_t>& ids) {
                return r.engine().remove_plants(ids);
            },
            py::arg("ids"),
            "cuts the plants with these ids now, as a thinning does (stumps and slash to the dead "
            "wood, the year's harvest sums); returns how many")
        .def(
            "stand", [](PyRun& r) { return from_json(analyses::stand_json(r.engine().stand())); },
            "the stand metrics of the trees, as `ecoterra stand` reports them")
        .def(
            "yearly", [](PyRun& r) { return table_dict(r.engine().yearly()); },
            "the yearly table: {column: numpy array}")
        .def(
            "daily", [](PyRun& r) { return table_dict(r.engine().daily()); },
            "the daily table: {column: numpy array}")
        .def("units", [](PyRun& r) {
            py::dict d = units_dict(r.engine().yearly());
            for (const auto& [k, v] : units_dict(r.engine().daily())) d[k] = v;
            return d;
        });
}

} // namespace

void register_run(py::module_& m) {
    py::class_<PyRun> c(m, "Run", "The coupled engine of a scene, stepped from Python.");
    c.def(py::init<const PyScene&>(), py::arg("scene"))
        .def(
            "step_day",
            [](PyRun& r) {
                py::gil_scoped_release free;
                return r.engine().step_day();
            },
            "one day; True when it closed a year")
        .def(
            "step_year",
            [](PyRun& r, int years) {
                if (years < 0)
                    throw InputError("step_year: years must be >= 0, got " + std::to_string(years));
                py::gil_scoped_release free;
                for (int y = 0; y < years; ++y) r.engine().run_year();
            },
            py::arg("years") = 1, "to the end of the current year, `years` times")
        .def_property_readonly("years_done", [](PyRun& r) { return r.engine().years_done(); })
        .def_property_readonly("days_done", [](PyRun& r) { return r.engine().days_done(); })
        .def_property_readonly("water_residual_relative", [](PyRun& r) {
            const auto& h = r.engine().hydrology();
            return std::abs(h.cumulative_residual_m3()) /
                   std::max(h.cumulative_throughput_m3(), 1e-300);
        });
    register_run_state(c);
    register_run_fields(c);
    register_run_plants(c);
    m.def("run", &run_file, py::arg("scene"), py::arg("output"), py::arg("years") = py::none(),
          py::arg("resume") = false, py::arg("pictures") = false, py::arg("force") = false,
          "`ecoterra run`: grows `scene` into the run file `output` with its snapshots and "
          "checkpoint (resume=True continues it; scene may then be None)");
}

} // namespace ecoterra::python
