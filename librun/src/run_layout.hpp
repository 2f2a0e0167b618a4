#pragma once
// The layout of an ecosystem run on disk (docs/formats.md, "Ecosystem runs"): private to libeco,
// shared by the run driver (run.cpp) and the readers (run_reader.cpp).
//
//   RUN.h5                     main file, replaced atomically after every snapshot: terrain, soil,
//                              species, provenance, yearly and daily series, the checkpoint of
//                              the state at the last snapshot, and /snapshots/NNNN links
//   RUN.snapshots/NNNN.h5      one file per snapshot, written atomically once and never touched
//                              again; /snapshots/NNNN in RUN.h5 is an HDF5 external link to it
#include "ecoterra/eco/ecosystem.hpp"
#include "ecoterra/io/hdf5_writer.hpp"
#include "ecoterra/run/records.hpp"

#include <H5Cpp.h>
#include <nlohmann/json.hpp>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace ecoterra::run::layout {

using namespace ecoterra::eco;

namespace fs = std::filesystem;

/// NAME.snapshots for the run file NAME.h5.
std::string snapshot_dir_name(const fs::path& output);
/// NNNN.h5, the file of snapshot `index`.
std::string snapshot_file_name(int index);
/// FNV-1a of a raster's bytes (the terrain a checkpoint belongs to).
std::uint64_t raster_hash(const RasterD& r);
/// "/NNNN": the group that holds snapshot `index` in its file. The run file's link points to it;
/// a group of its own name per file (not the root) lets `h5ls -r --follow-symlinks` list every
/// snapshot (it takes links to the same path as visited).
std::string snapshot_group(int index);
/// Writes snapshot file `path`: plants, soil moisture, standing water, weather of the day, under
/// snapshot_group(index).
void write_snapshot(const Ecosystem& eco, const fs::path& path, int index);
/// Writes the run file `path` (atomically): rasters, species, series, checkpoint and the links to
/// the snapshot files, one per checksum (`/snapshots` attribute `checksums_fnv1a64`, one decimal
/// FNV-1a 64 of each snapshot file's bytes a line; an empty line for a snapshot written before
/// snapshots had checksums).
/// `link_dir` names the snapshot folder the links point into (default: the one of `path`). With
/// `cache`, the chunks the last run file written with it holds unchanged (its terrain, soil maps,
/// the series' earlier rows) are not compressed again (io::ChunkCache: the same bytes).
void write_main(const Ecosystem& eco, const fs::path& path, const nlohmann::json& provenance,
                const std::vector<std::string>& snapshot_checksums,
                const std::string& link_dir = "", io::ChunkCache* cache = nullptr);
/// FNV-1a 64 of a file's bytes, in decimal; IoError naming it if it cannot be read.
std::string file_checksum(const fs::path& file);
/// The snapshot checksums a run file holds (empty strings where it has none: runs written before
/// snapshots had checksums), one per snapshot.
std::vector<std::string> read_snapshot_checksums(const fs::path& run, int snapshots);
/// InputError (`what` + "is damaged ...") unless snapshot `k`'s file matches the checksum the run
/// file holds for it (snapshots without one pass). Each file is hashed once per process while its
/// size and time are unchanged.
void verify_snapshot(const fs::path& run, int k, const fs::path& file, const std::string& what);
std::string read_string_attr(const H5::H5Object& o, const std::string& name);
double read_double_attr(const H5::H5Object& o, const std::string& name);
/// Opens a run file for reading; InputError naming it if it is missing or not a run.
H5::H5File open_run(const fs::path& run);
/// The run's checkpoint (its bytes, checked against their checksum and the scene's terrain) and
/// the year it ends; without `state`, only the year and the terrain's check (no bytes read).
struct RunCheckpoint {
    std::vector<std::uint8_t> bytes;
    int year = 0;
};
RunCheckpoint read_run_checkpoint(const fs::path& run, const eco::EcoScene& sc, bool state = true);
/// Column `column` of the run file's /series/`table` (integers as doubles): what a checkpoint that
/// keeps its series in the run file resumes from. InputError naming the dataset if it is missing.
std::vector<double> read_series_column(const H5::H5File& f, const fs::path& run,
                                       const std::string& table, const std::string& column);
/// Creates `dir` if needed and writes and removes a file in it: IoError naming it if that fails.
void require_writable_folder(const fs::path& dir, const std::string& what);

template <class T>
std::vector<T> read_vector(const H5::Group& g, const std::string& name, const H5::PredType& t) {
    H5::DataSet ds = g.openDataSet(name);
    hsize_t n = 0;
    ds.getSpace().getSimpleExtentDims(&n);
    std::vector<T> v(n);
    if (n) ds.read(v.data(), t);
    return v;
}

/// Opens snapshot `k` of `run` and calls f on its group. The file is found by the run file's
/// present name (RUN.snapshots/NNNN.h5 beside RUN.h5), so that a run file renamed together with
/// its folder still reads; the external links in RUN.h5 serve other tools (h5py, HDFView).
template <class F>
void open_snapshot(const fs::path& run, int k, F&& f) {
    const fs::path parent = run.has_parent_path() ? run.parent_path() : fs::path(".");
    const fs::path file = parent / snapshot_dir_name(run) / snapshot_file_name(k);
    const std::string what =
        run.string() + ": snapshot " + std::to_string(k) + " (" + file.string() + ") ";
    const std::string hint = "; a run file NAME.h5 and its folder NAME.snapshots are moved and "
                             "renamed together";
    std::error_code ec;
    if (!fs::is_regular_file(file, ec)) throw InputError(what + "is missing" + hint);
    verify_snapshot(run, k, file, what);
    try {
        if (!H5::H5File::isHdf5(file.string())) throw InputError(what + "is not an HDF5 file");
        H5::H5File h(file.string(), H5F_ACC_RDONLY);
        // The snapshot's own group /NNNN; files written before it existed hold it at the root.
        const std::string group = snapshot_group(k);
        f(h.openGroup(h.nameExists(group) ? group : std::string("/")));
    } catch (const H5::Exception& e) {
        throw InputError(what + "is damaged (" + e.getDetailMsg() + ")");
    }
}

} // namespace ecoterra::run::layout
