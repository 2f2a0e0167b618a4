#pragma once
// A self-describing HDF5 output file, written atomically: datasets go into a temporary file that
// replaces the target only on commit(). Every dataset carries `units` and `description`
// attributes; rasters also carry the grid (cell_size_m, origin_x_m, origin_y_m, row_order).
#include "ecoterra/io/atomic_file.hpp"
#include "ecoterra/raster.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace ecoterra::io {

/// Compressed chunks kept from one file to the next written with the same cache: a file that is
/// written again and again with mostly the same content (a run's main file, rewritten at every
/// snapshot with its series grown and its terrain unchanged) compresses only the chunks that
/// changed. A chunk is reused only when its bytes, as they go into zlib, equal the stored ones
/// (compared in full), so every file is byte for byte what it would be without the cache. Only
/// the datasets of the last file written are kept; not kept are series over kMaxSeriesBytes
/// (2,000 years of daily values fit), rasters over kMaxRasterBytes (a large scene's rasters would
/// cost more memory than their compression costs time) and datasets of four chunks or more of
/// which a later write reused none (a checkpoint's bytes change throughout). One writer at a time
/// may use a cache.
class ChunkCache {
public:
    static constexpr std::size_t kMaxSeriesBytes = std::size_t{16} << 20;
    static constexpr std::size_t kMaxRasterBytes = std::size_t{1} << 20;
    struct Counts {
        std::int64_t reused = 0, compressed = 0; ///< chunks since the cache was made
        std::size_t bytes_held = 0;              ///< the stored chunks' input and output bytes
    };
    ChunkCache();
    ~ChunkCache();
    ChunkCache(const ChunkCache&) = delete;
    ChunkCache& operator=(const ChunkCache&) = delete;
    Counts counts() const;
    struct Impl;

private:
    friend class Hdf5Writer;
    std::unique_ptr<Impl> m_impl;
};

class Hdf5Writer {
public:
    explicit Hdf5Writer(const std::filesystem::path& target);
    /// The same, reusing and refreshing the compressed chunks of `cache` (see ChunkCache); the
    /// cache must outlive the writer.
    Hdf5Writer(const std::filesystem::path& target, ChunkCache& cache);
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
