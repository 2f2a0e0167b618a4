// The Python module `ecoterra._ecoterra` (docs/python.md): errors, JSON across the boundary, the
// scene; the run (run.cpp) and the terrain (terrain.cpp) register themselves from here.
#include "bindings.hpp"

#include "ecoterra/error.hpp"
#include "ecoterra/io/atomic_file.hpp"
#include "ecoterra/json_util.hpp"
#include "ecoterra/provenance.hpp"

#include <pybind11/stl.h>

namespace ecoterra::python {

nlohmann::json to_json(const py::handle& obj, const std::string& what) {
    const py::module_ json = py::module_::import("json");
    std::string text;
    try {
        text = py::cast<std::string>(json.attr("dumps")(obj, py::arg("allow_nan") = false));
    } catch (const py::error_already_set& e) {
        throw InputError(what + ": not JSON-like (" + std::string(e.what()) + ")");
    }
    return parse_json(text, what);
}

py::object from_json(const nlohmann::json& j) {
    return py::module_::import("json").attr("loads")(j.dump());
}

py::dict grid_dict(const GridSpec& g) {
    py::dict d;
    d["nx"] = g.nx;
    d["ny"] = g.ny;
    d["cell_size_m"] = g.cell_size_m;
    d["origin_x_m"] = g.origin_x_m;
    d["origin_y_m"] = g.origin_y_m;
    return d;
}

std::vector<std::string> overrides(const py::handle& set) {
    std::vector<std::string> out;
    if (set.is_none()) return out;
    if (py::isinstance<py::dict>(set)) {
        for (const auto& [k, v] : py::reinterpret_borrow<py::dict>(set)) {
            const std::string key = py::cast<std::string>(py::str(k));
            const std::string value = py::isinstance<py::str>(v)
                                          ? py::cast<std::string>(v)
                                          : to_json(v, "set[" + key + "]").dump();
            out.push_back(key + "=" + value);
        }
        return out;
    }
    if (py::isinstance<py::str>(set))
        throw InputError("set: give a dict {key: value} or a list of \"key=value\" strings, not "
                         "one string");
    for (const auto& item : set) out.push_back(py::cast<std::string>(item));
    return out;
}

void register_errors(py::module_& m) {
    // ecoterra.Error is the base of every error the engine raises; InputError (bad input, the
    // message names the file, the key and the value) and IoError (a file that cannot be read or
    // written) derive from it, as in C++. Their messages are the program's.
    static py::exception<Error> error(m, "Error", PyExc_RuntimeError);
    static py::exception<InputError> input(m, "InputError", error.ptr());
    static py::exception<IoError> io(m, "IoError", error.ptr());
    static py::exception<CheckpointError> checkpoint(m, "CheckpointError", input.ptr());
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const CheckpointError& e) {
            PyErr_SetString(checkpoint.ptr(), e.what());
        } catch (const InputError& e) {
            PyErr_SetString(input.ptr(), e.what());
        } catch (const IoError& e) {
            PyErr_SetString(io.ptr(), e.what());
        } catch (const Error& e) {
            PyErr_SetString(error.ptr(), e.what());
        }
    });
}

namespace {

/// A scene from a file (`str` or path) or a dict, with `set` overrides, as `ecoterra run` loads
/// it: relative paths in a file are read from its folder, in a dict from `base_dir`.
PyScene load_scene(const py::handle& source, const py::handle& set, const std::string& base_dir) {
    PyScene s;
    std::string where;
    if (py::isinstance<py::dict>(source)) {
        where = "scene";
        s.source = to_json(source, where);
        s.base = std::filesystem::absolute(base_dir.empty() ? "." : base_dir);
    } else {
        const std::string path = py::cast<std::string>(py::str(source));
        where = path;
        s.source = parse_json(io::read_text(path), path);
        s.base = std::filesystem::absolute(path).parent_path();
    }
    s.set = overrides(set);
    apply_overrides(s.source, s.set);
    s.scene = with_context(where, [&] { return eco::load_eco_scene(s.source, s.base); });
    return s;
}

} // namespace

void register_scene(py::module_& m) {
    py::class_<PyScene>(m, "Scene",
                        "A scene (docs/scenes.md) loaded and checked as `ecoterra run` loads it.")
        .def(py::init(&load_scene), py::arg("source"), py::arg("set") = py::none(),
             py::arg("base_dir") = "",
             "Scene(path or dict, set={key: value} or [\"key=value\"], base_dir='')")
        .def_property_readonly(
            "resolved", [](const PyScene& s) { return from_json(s.scene.resolved); },
            "every key with its value, defaults filled in (a dict)")
        .def_property_readonly("overrides", [](const PyScene& s) { return s.set; })
        .def_property_readonly("years", [](const PyScene& s) { return s.scene.years; })
        .def_property_readonly(
            "notes",
            [](const PyScene& s) {
                std::vector<std::string> n = s.scene.hydro.notes;
                for (const auto& e : s.scene.ecosystem.notes)
                    n.push_back(s.scene.ecosystem.source.string() + ": " + e);
                return n;
            },
            "what the loader did that the user should know (the program prints them as notes)")
        .def_property_readonly("species",
                               [](const PyScene& s) {
                                   std::vector<std::string> n;
                                   for (const auto& sp : s.scene.ecosystem.species)
                                       n.push_back(sp.name);
                                   return n;
                               })
        .def_property_readonly("terrain_grid",
                               [](const PyScene& s) { return grid_dict(s.scene.hydro.dem.grid()); })
        .def("__repr__", [](const PyScene& s) {
            return "<ecoterra.Scene " + std::to_string(s.scene.hydro.dem.nx()) + " x " +
                   std::to_string(s.scene.hydro.dem.ny()) + " cells, " +
                   std::to_string(s.scene.ecosystem.species.size()) + " species, " +
                   std::to_string(s.scene.years) + " years>";
        });
}

} // namespace ecoterra::python

PYBIND11_MODULE(_ecoterra, m) {
    namespace py = pybind11;
    m.doc() = "ecoterra's engine from Python (docs/python.md)";
    m.attr("__version__") = ecoterra::version();
    ecoterra::python::register_errors(m);
    ecoterra::python::register_scene(m);
    ecoterra::python::register_run(m);
    ecoterra::python::register_terrain(m);
    ecoterra::python::register_analyses(m);
    ecoterra::python::register_bmi(m);
    ecoterra::python::register_ensemble(m);
}
