#pragma once
// A self-describing HDF5 output file, written atomically: datasets go into a temporary file that
// replaces the target only on commit(). Every dataset carries `units` and `description`
// attributes; rasters also carry the grid (cell_size_m, origin_x_m, origin_y_m, row_order).
#include "ecoterra/io/atomic_file.hpp"
#include "ecoterra/raster.hpp"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace ecoterra::io {

class Hdf5Writer {
public:
    explicit Hdf5Writer(const std::filesystem::path& target);
    ~Hdf5Writer();
    Hdf5Writer(const Hdf5Writer&) = delete;
    Hdf5Writer& operator=(const Hdf5Writer&) = delete;

    /// Writes a raster as a chunked, compressed [ny, nx] dataset (row 0 = south) at `path`
    /// (parent groups are created). Float rasters are stored as float32.
    void raster(const std::string& path, const RasterD& r, const std::string& units,
                const std::string& description);
    void raster(const std::string& path, const Raster<float>& r, const std::string& units,
                const std::string& description);
    void raster(const std::string& path, const Raster<std::int32_t>& r, const std::string& units,
                const std::string& description);
    void raster(const std::string& path, const Raster<std::uint8_t>& r, const std::string& units,
                const std::string& description);
    /// A 1-D double dataset.
    void series(const std::string& path, const std::vector<double>& v, const std::string& units,
                const std::string& description);
    void series(const std::string& path, const std::vector<std::int32_t>& v,
                const std::string& units, const std::string& description);
    void series(const std::string& path, const std::vector<std::int64_t>& v,
                const std::string& units, const std::string& description);
    void series(const std::string& path, const std::vector<std::uint8_t>& v,
                const std::string& units, const std::string& description);
    /// A link at `path` to the object `object` of another HDF5 file (`file` is relative to this
    /// file's folder or absolute); readers follow it transparently.
    void external_link(const std::string& path, const std::string& file, const std::string& object);
    /// A string attribute (variable-length UTF-8) on a group (created if needed) or dataset.
    void attribute(const std::string& object, const std::string& name, const std::string& value);
    void attribute(const std::string& object, const std::string& name, double value);
    /// An integer attribute (counts, years, seeds: exact, and integers to h5py and pandas).
    void integer_attribute(const std::string& object, const std::string& name, std::int64_t value);
    /// A 1-D dataset of variable-length UTF-8 strings (h5py: `ds.asstr()[()]`).
    void strings(const std::string& path, const std::vector<std::string>& v,
                 const std::string& description);
    /// Closes the file and moves it into place.
    void commit();

private:
    struct Impl;
    AtomicOutput m_out;
    std::unique_ptr<Impl> m_impl;
};

/// What an HDF5 file holds of ecoterra's runs: "an ecoterra run file (it holds /checkpoint)",
/// "... (it holds /snapshots)", "an ecoterra snapshot file (it holds /NNNN/plants)", or "" for any
/// other file (a raster, a pond, a file that is not HDF5 or cannot be opened).
std::string hdf5_run_kind(const std::filesystem::path& file);

} // namespace ecoterra::io
