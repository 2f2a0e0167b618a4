// Ensembles from Python (docs/python.md): one member run as `ecoterra ensemble --member` runs it,
// the summary written as `ecoterra ensemble --summary` writes it, and a member's record read.
#include "bindings.hpp"

#include "ecoterra/ensemble/manifest.hpp"
#include "ecoterra/ensemble/member.hpp"
#include "ecoterra/ensemble/summary.hpp"
#include "ecoterra/error.hpp"

#include <pybind11/stl.h>

namespace ecoterra::python {

namespace {

/// Runs member `index` of the manifest into `output` (prepared as the program prepares it);
/// returns its record (status, metrics, seeds).
py::object run_member(const std::filesystem::path& manifest, const std::filesystem::path& output,
                      long long index) {
    const ensemble::Manifest m = ensemble::load_manifest(manifest);
    if (index < 0 || static_cast<std::size_t>(index) >= m.members())
        throw InputError(manifest.string() + ": member " + std::to_string(index) +
                         " is outside [0, " + std::to_string(m.members()) + ")");
    ensemble::prepare_output(output, m);
    const ensemble::Member mb = ensemble::make_member(m, static_cast<std::size_t>(index));
    {
        py::gil_scoped_release free;
        ensemble::run_member(output, m, mb, 1);
    }
    const auto rec = ensemble::read_member_record(output, m, static_cast<std::size_t>(index));
    return rec ? from_json(*rec) : py::none();
}

/// Writes the summary of the ensemble in `output`; returns the counts and the files written.
py::dict summary(const std::filesystem::path& output) {
    const ensemble::Manifest m = ensemble::manifest_of_output(output);
    const auto r = ensemble::write_summary(output, m);
    py::dict d;
    d["members"] = r.members;
    d["ok"] = r.ok;
    d["failed"] = r.failed;
    d["missing"] = r.missing;
    d["failures"] = r.failures;
    std::vector<std::string> files;
    for (const auto& f : r.files) files.push_back(f.string());
    d["files"] = files;
    return d;
}

} // namespace

void register_ensemble(py::module_& m) {
    m.def(
        "ensemble_members",
        [](const std::filesystem::path& manifest) {
            return ensemble::load_manifest(manifest).members();
        },
        py::arg("manifest"), "the number of members of an ensemble manifest");
    m.def("run_ensemble_member", &run_member, py::arg("manifest"), py::arg("output"),
          py::arg("index"),
          "runs one member as `ecoterra ensemble MANIFEST -o OUTPUT --member INDEX`; its record");
    m.def("ensemble_summary", &summary, py::arg("output"),
          "writes the summary of the ensemble in OUTPUT (`ecoterra ensemble --summary`); the "
          "counts and the files, read them with pandas (summary/members.csv, aggregate.csv)");
}

} // namespace ecoterra::python
