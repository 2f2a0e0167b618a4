// ecoterra.Terrain: heightmaps generated, read, written and analysed from Python (docs/python.md),
// as `ecoterra terrain generate | convert | analyze` do.
#include "bindings.hpp"

#include "ecoterra/error.hpp"
#include "ecoterra/terrain/analysis.hpp"
#include "ecoterra/terrain/generate.hpp"
#include "ecoterra/terrain/io/raster_io.hpp"

#include <pybind11/stl.h>

namespace ecoterra::python {

namespace {

/// An elevation raster, m, and where it came from.
struct PyTerrain {
    RasterD z;
    nlohmann::json resolved; ///< the generator's specification with its defaults (null if read)
    std::vector<std::string> warnings;
};

PyTerrain generate(const py::handle& spec, const py::kwargs& kw) {
    nlohmann::json s = spec.is_none() ? nlohmann::json::object() : to_json(spec, "spec");
    if (!s.is_object()) throw InputError("generate_terrain: the specification must be a dict");
    for (const auto& [k, v] : kw) s[py::cast<std::string>(k)] = to_json(v, "generate_terrain");
    terrain::GeneratedTerrain t = [&] {
        py::gil_scoped_release free;
        return terrain::generate_terrain(s);
    }();
    return {std::move(t.z), std::move(t.resolved), std::move(t.warnings)};
}

PyTerrain from_array(const py::array_t<double, py::array::c_style | py::array::forcecast>& a,
                     double cell_size_m, double origin_x_m, double origin_y_m) {
    if (a.ndim() != 2)
        throw InputError("Terrain.from_array: a 2-D array (ny, nx) is needed, got " +
                         std::to_string(a.ndim()) + " dimensions");
    if (!(cell_size_m > 0))
        throw InputError("Terrain.from_array: cell_size_m must be > 0 m, got " +
                         std::to_string(cell_size_m));
    GridSpec g{static_cast<int>(a.shape(1)), static_cast<int>(a.shape(0)), cell_size_m, origin_x_m,
               origin_y_m};
    RasterD z(g, 0.0);
    std::copy(a.data(), a.data() + g.size(), z.data());
    return {std::move(z), nullptr, {}};
}

py::object analyze(const PyTerrain& t, double border_m, double closing_radius_m) {
    terrain::AnalysisOptions o;
    o.border_m = border_m;
    o.closing_radius_m = closing_radius_m;
    o.validate();
    const auto a = [&] {
        py::gil_scoped_release free;
        return terrain::analyze_terrain(t.z, o);
    }();
    return from_json(a.to_json(o));
}

} // namespace

void register_terrain(py::module_& m) {
    py::class_<PyTerrain>(m, "Terrain", "An elevation raster, m (docs/terrain.md).")
        .def_static("from_array", &from_array, py::arg("z"), py::arg("cell_size_m") = 1.0,
                    py::arg("origin_x_m") = 0.0, py::arg("origin_y_m") = 0.0,
                    "a terrain from a 2-D array (ny, nx), row 0 at the south edge (copied)")
        .def_property_readonly(
            "z",
            [](py::object self) {
                auto& t = self.cast<PyTerrain&>();
                const auto& g = t.z.grid();
                return py::array_t<double>(
                    {static_cast<py::ssize_t>(g.ny), static_cast<py::ssize_t>(g.nx)},
                    {static_cast<py::ssize_t>(sizeof(double) * g.nx),
                     static_cast<py::ssize_t>(sizeof(double))},
                    t.z.data(), self);
            },
            "elevation, m: a writable view (ny, nx) over the terrain's memory, row 0 south")
        .def_property_readonly("grid", [](const PyTerrain& t) { return grid_dict(t.z.grid()); })
        .def_property_readonly("resolved", [](const PyTerrain& t) { return from_json(t.resolved); })
        .def_readonly("warnings", &PyTerrain::warnings)
        .def(
            "write",
            [](const PyTerrain& t, const std::filesystem::path& path) {
                terrain::io::write_raster(t.z, path);
            },
            py::arg("path"), "writes the raster; the format follows the extension")
        .def("analyze", &analyze, py::arg("border_m") = 5.0, py::arg("closing_radius_m") = 0.25,
             "`ecoterra terrain analyze`: RMS, slopes, roughness classes, fractal dimension");
    m.def("generate_terrain", &generate, py::arg("spec") = py::none(),
          "`ecoterra terrain generate`: a dict as --config takes it, keys as keywords too, e.g. "
          "generate_terrain(method='fbm', size=128, seed=3, params={'hurst': 0.8})");
    m.def(
        "read_terrain",
        [](const std::filesystem::path& path) {
            PyTerrain t;
            t.z = terrain::io::read_raster(path, &t.warnings);
            return t;
        },
        py::arg("path"), "reads an elevation raster (HDF5, GeoTIFF, ESRI ASCII, PNG, ...)");
}

} // namespace ecoterra::python
