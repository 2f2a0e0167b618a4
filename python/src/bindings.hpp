#pragma once
// Shared pieces of the Python module (docs/python.md): JSON across the boundary, rasters as numpy
// arrays, and the registration functions of each part.
#include "ecoterra/eco/scene_config.hpp"
#include "ecoterra/raster.hpp"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl/filesystem.h>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace ecoterra::python {

namespace py = pybind11;

/// A Python object (dict, list, str, number, bool, None) as JSON, through the json module: the
/// same parser and error messages as a scene file.
nlohmann::json to_json(const py::handle& obj, const std::string& what);
/// JSON as Python objects.
py::object from_json(const nlohmann::json& j);

/// A read-only numpy view (ny, nx) over a raster the `owner` keeps alive: no copy.
template <class T>
py::array_t<T> raster_view(const Raster<T>& r, const py::handle& owner) {
    const auto& g = r.grid();
    py::array_t<T> a(
        {static_cast<py::ssize_t>(g.ny), static_cast<py::ssize_t>(g.nx)},
        {static_cast<py::ssize_t>(sizeof(T) * g.nx), static_cast<py::ssize_t>(sizeof(T))}, r.data(),
        owner);
    py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
    return a;
}

/// A Python object that owns a copy of `p`: the base of views over what `p` holds, so that the
/// memory lives as long as the views, whatever happens to the object that handed them out.
template <class T>
py::object keep_alive(const std::shared_ptr<T>& p) {
    return py::capsule(new std::shared_ptr<T>(p),
                       [](void* q) { delete static_cast<std::shared_ptr<T>*>(q); });
}

/// A copy of a raster as a numpy array (ny, nx), for rasters computed on request.
template <class T>
py::array_t<T> raster_copy(const Raster<T>& r) {
    const auto& g = r.grid();
    py::array_t<T> a({static_cast<py::ssize_t>(g.ny), static_cast<py::ssize_t>(g.nx)});
    std::copy(r.data(), r.data() + static_cast<std::size_t>(g.nx) * g.ny, a.mutable_data());
    return a;
}

/// The grid as a dict: nx, ny, cell_size_m, origin_x_m, origin_y_m.
py::dict grid_dict(const GridSpec& g);

/// A scene as Python holds it: the loaded scene and the JSON it came from.
struct PyScene {
    eco::EcoScene scene;
    nlohmann::json source;        ///< the scene's JSON after the overrides
    std::filesystem::path base;   ///< the folder its relative paths are read from
    std::vector<std::string> set; ///< the overrides, as `ecoterra run --set` takes them
};

/// `set` as "key=value" strings: a dict's values are written as JSON (strings as they are), a
/// list or tuple of strings is taken as it is.
std::vector<std::string> overrides(const py::handle& set);

void register_errors(py::module_& m);
void register_scene(py::module_& m);
void register_run(py::module_& m);
void register_terrain(py::module_& m);
void register_analyses(py::module_& m);
void register_bmi(py::module_& m);
void register_ensemble(py::module_& m);

} // namespace ecoterra::python
