// ecoterra.Bmi: the Basic Model Interface 2.0 in Python (the names and calling conventions of the
// specification's Python binding, bmipy: arrays are numpy arrays the caller passes in and gets
// back filled), over the C++ implementation (libbmi).
#include "bindings.hpp"

#include "ecoterra/bmi/ecoterra_bmi.hpp"
#include "ecoterra/error.hpp"

#include <pybind11/stl.h>

namespace ecoterra::python {

namespace {

using Impl = bmi_impl::EcoterraBmi;
using Doubles = py::array_t<double, py::array::c_style>;
using Ints = py::array_t<int, py::array::c_style | py::array::forcecast>;

/// `dest` must be a writable C-ordered float64 array of at least `n` items.
double* out(Doubles& dest, py::ssize_t n, const std::string& what) {
    if (dest.size() < n)
        throw InputError("BMI: " + what + ": the destination holds " + std::to_string(dest.size()) +
                         " values, " + std::to_string(n) + " are needed");
    return dest.mutable_data();
}

void register_bmi_info(py::class_<Impl>& c) {
    c.def("get_component_name", &Impl::GetComponentName)
        .def("get_input_item_count", &Impl::GetInputItemCount)
        .def("get_output_item_count", &Impl::GetOutputItemCount)
        .def("get_input_var_names",
             [](Impl& m) { return py::tuple(py::cast(m.GetInputVarNames())); })
        .def("get_output_var_names",
             [](Impl& m) { return py::tuple(py::cast(m.GetOutputVarNames())); })
        .def("get_var_grid", &Impl::GetVarGrid, py::arg("name"))
        .def(
            "get_var_type",
            [](Impl& m, const std::string& n) {
                return m.GetVarType(n) == "double" ? "float64" : m.GetVarType(n);
            },
            py::arg("name"), "the numpy dtype name")
        .def("get_var_units", &Impl::GetVarUnits, py::arg("name"))
        .def("get_var_itemsize", &Impl::GetVarItemsize, py::arg("name"))
        .def("get_var_nbytes", &Impl::GetVarNbytes, py::arg("name"))
        .def("get_var_location", &Impl::GetVarLocation, py::arg("name"))
        .def("get_current_time", &Impl::GetCurrentTime)
        .def("get_start_time", &Impl::GetStartTime)
        .def("get_end_time", &Impl::GetEndTime)
        .def("get_time_units", &Impl::GetTimeUnits)
        .def("get_time_step", &Impl::GetTimeStep);
}

void register_bmi_values(py::class_<Impl>& c) {
    c.def(
         "get_value",
         [](Impl& m, const std::string& name, Doubles dest) {
             m.GetValue(name, out(dest, m.GetGridSize(m.GetVarGrid(name)), name));
             return dest;
         },
         py::arg("name"), py::arg("dest"),
         "fills dest (float64, the variable's size) and returns it")
        .def(
            "get_value_ptr",
            [](Impl& m, const std::string& name) {
                auto* p = static_cast<double*>(m.GetValuePtr(name));
                const int g = m.GetVarGrid(name);
                int shape[2];
                m.GetGridShape(g, shape);
                // The view keeps the engine alive, even past finalize().
                py::array_t<double> a({static_cast<py::ssize_t>(shape[0] * shape[1])}, {8}, p,
                                      keep_alive(m.shared_engine()));
                py::detail::array_proxy(a.ptr())->flags &=
                    ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
                return a;
            },
            py::arg("name"), "a read-only flat view over the engine's memory (no copy)")
        .def(
            "get_value_at_indices",
            [](Impl& m, const std::string& name, Doubles dest, Ints inds) {
                const auto n = static_cast<int>(inds.size());
                m.GetValueAtIndices(name, out(dest, n, name), const_cast<int*>(inds.data()), n);
                return dest;
            },
            py::arg("name"), py::arg("dest"), py::arg("inds"))
        .def(
            "set_value",
            [](Impl& m, const std::string& name,
               py::array_t<double, py::array::c_style | py::array::forcecast> src) {
                if (src.size() != m.GetGridSize(m.GetVarGrid(name)))
                    throw InputError("BMI: set_value('" + name + "'): " +
                                     std::to_string(src.size()) + " values for a variable of " +
                                     std::to_string(m.GetGridSize(m.GetVarGrid(name))));
                m.SetValue(name, const_cast<double*>(src.data()));
            },
            py::arg("name"), py::arg("src"))
        .def(
            "set_value_at_indices",
            [](Impl& m, const std::string& name, Ints inds,
               py::array_t<double, py::array::c_style | py::array::forcecast> src) {
                if (src.size() != inds.size())
                    throw InputError("BMI: set_value_at_indices: " + std::to_string(inds.size()) +
                                     " indices and " + std::to_string(src.size()) + " values");
                m.SetValueAtIndices(name, const_cast<int*>(inds.data()),
                                    static_cast<int>(inds.size()), const_cast<double*>(src.data()));
            },
            py::arg("name"), py::arg("inds"), py::arg("src"));
}

/// get_grid_shape, _spacing and _origin: one value per dimension of the grid into `dest`.
template <class T, class F>
auto per_dimension(F f, const char* what) {
    return [f, what](Impl& m, int grid, py::array_t<T, py::array::c_style> dest) {
        if (dest.size() < m.GetGridRank(grid))
            throw InputError(std::string("BMI: ") + what + ": the destination holds " +
                             std::to_string(dest.size()) + " values, the grid has " +
                             std::to_string(m.GetGridRank(grid)) + " dimensions");
        (m.*f)(grid, dest.mutable_data());
        return dest;
    };
}

void register_bmi_grid(py::class_<Impl>& c) {
    c.def("get_grid_rank", &Impl::GetGridRank, py::arg("grid"))
        .def("get_grid_size", &Impl::GetGridSize, py::arg("grid"))
        .def("get_grid_type", &Impl::GetGridType, py::arg("grid"))
        .def("get_grid_shape", per_dimension<int>(&Impl::GetGridShape, "get_grid_shape"),
             py::arg("grid"), py::arg("shape"))
        .def("get_grid_spacing", per_dimension<double>(&Impl::GetGridSpacing, "get_grid_spacing"),
             py::arg("grid"), py::arg("spacing"))
        .def("get_grid_origin", per_dimension<double>(&Impl::GetGridOrigin, "get_grid_origin"),
             py::arg("grid"), py::arg("origin"))
        .def(
            "get_grid_x",
            [](Impl& m, int grid, Doubles x) {
                int shape[2] = {0, 0};
                m.GetGridShape(grid, shape);
                m.GetGridX(grid, out(x, shape[1], "get_grid_x"));
                return x;
            },
            py::arg("grid"), py::arg("x"))
        .def(
            "get_grid_y",
            [](Impl& m, int grid, Doubles y) {
                int shape[2] = {0, 0};
                m.GetGridShape(grid, shape);
                m.GetGridY(grid, out(y, shape[0], "get_grid_y"));
                return y;
            },
            py::arg("grid"), py::arg("y"))
        .def(
            "get_grid_z", [](Impl& m, int grid, Doubles z) { m.GetGridZ(grid, z.mutable_data()); },
            py::arg("grid"), py::arg("z"))
        .def("get_grid_node_count", &Impl::GetGridNodeCount, py::arg("grid"))
        .def("get_grid_edge_count", &Impl::GetGridEdgeCount, py::arg("grid"))
        .def("get_grid_face_count", &Impl::GetGridFaceCount, py::arg("grid"));
}

} // namespace

void register_bmi(py::module_& module) {
    py::class_<Impl> c(module, "Bmi",
                       "ecoterra behind the CSDMS Basic Model Interface 2.0: initialize with a "
                       "scene file; one update is one day (docs/python.md, BMI)");
    c.def(py::init([](const py::handle& set) { return Impl(overrides(set)); }),
          py::arg("set") = py::none())
        .def(
            "initialize",
            [](Impl& m, const std::filesystem::path& config) { m.Initialize(config.string()); },
            py::arg("config_file"))
        .def("update",
             [](Impl& m) {
                 py::gil_scoped_release free;
                 m.Update();
             })
        .def(
            "update_until",
            [](Impl& m, double t) {
                py::gil_scoped_release free;
                m.UpdateUntil(t);
            },
            py::arg("time"))
        .def("finalize", &Impl::Finalize);
    register_bmi_info(c);
    register_bmi_values(c);
    register_bmi_grid(c);
}

} // namespace ecoterra::python
