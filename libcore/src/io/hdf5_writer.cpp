#include "ecoterra/io/hdf5_writer.hpp"

#include <hdf5.h>
#include <zlib.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <map>
#include <unistd.h>
#include <utility>
#include <vector>

// The file is built in memory (HDF5's core driver, no backing store) and written to the disk by
// commit() with plain checked writes. HDF5 1.10 cannot survive a failed close: a dataset or file
// whose flush fails on a full disk is left half closed, and the library's own clean-up at exit
// closes it again and crashes. In memory nothing HDF5 does can fail for want of disk, so every
// disk error is ours to report. Written on the C API so that each handle is closed exactly once
// and nothing prints from a destructor.
namespace ecoterra::io {

namespace {
constexpr hsize_t kChunk = 256;
constexpr unsigned kDeflate = 4;

/// The innermost message on HDF5's error stack (e.g. the operating system's "No space left on
/// device"), or `fallback`.
std::string hdf5_reason(const std::string& fallback) {
    std::string reason;
    auto walk = [](unsigned, const H5E_error2_t* e, void* data) -> herr_t {
        auto& out = *static_cast<std::string*>(data);
        if (out.empty() && e->desc && *e->desc) out = e->desc;
        return 0;
    };
    H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, walk, &reason);
    H5Eclear2(H5E_DEFAULT);
    // A failed system call is described at length; keep its message ("No space left on device").
    const std::string key = "error message = '";
    if (const auto at = reason.find(key); at != std::string::npos) {
        const auto from = at + key.size();
        reason = reason.substr(from, reason.find('\'', from) - from);
    }
    return reason.empty() ? fallback : fallback + " (" + reason + ")";
}

struct Failure {
    std::string what;
};

hid_t check(hid_t id, const char* call) {
    if (id < 0) throw Failure{hdf5_reason(std::string(call) + " failed")};
    return id;
}
void check(herr_t status, const char* call) {
    if (status < 0) throw Failure{hdf5_reason(std::string(call) + " failed")};
}
bool check_tri(htri_t answer, const char* call) {
    if (answer < 0) throw Failure{hdf5_reason(std::string(call) + " failed")};
    return answer > 0;
}

/// An HDF5 identifier closed once, by `close()` (which reports failure) or by the destructor
/// (which cannot). After a failed close the identifier is forgotten, never closed again.
class Handle {
public:
    using Closer = herr_t (*)(hid_t);
    Handle() = default;
    Handle(hid_t id, Closer c) : m_id(id), m_close(c) {}
    Handle(const Handle&) = delete;
    Handle& operator=(const Handle&) = delete;
    Handle(Handle&& o) noexcept
        : m_id(std::exchange(o.m_id, H5I_INVALID_HID)), m_close(o.m_close) {}
    Handle& operator=(Handle&& o) noexcept {
        if (this != &o) {
            release();
            m_id = std::exchange(o.m_id, H5I_INVALID_HID);
            m_close = o.m_close;
        }
        return *this;
    }
    ~Handle() { release(); }
    hid_t id() const { return m_id; }
    void close(const char* call) {
        const hid_t id = std::exchange(m_id, H5I_INVALID_HID);
        if (id >= 0) check(m_close(id), call);
    }

private:
    void release() {
        const hid_t id = std::exchange(m_id, H5I_INVALID_HID);
        if (id >= 0) m_close(id);
    }
    hid_t m_id = H5I_INVALID_HID;
    Closer m_close = nullptr;
};

Handle dataspace(int rank, const hsize_t* dims) {
    return {check(rank == 0 ? H5Screate(H5S_SCALAR) : H5Screate_simple(rank, dims, nullptr),
                  "H5Screate"),
            H5Sclose};
}

void put_attr(hid_t obj, const std::string& name, hid_t type, const void* value) {
    if (check_tri(H5Aexists(obj, name.c_str()), "H5Aexists"))
        check(H5Adelete(obj, name.c_str()), "H5Adelete");
    Handle space = dataspace(0, nullptr);
    Handle a{check(H5Acreate2(obj, name.c_str(), type, space.id(), H5P_DEFAULT, H5P_DEFAULT),
                   "H5Acreate"),
             H5Aclose};
    check(H5Awrite(a.id(), type, value), "H5Awrite");
    a.close("H5Aclose");
}
/// Variable-length UTF-8 strings: h5py returns them as str, not bytes.
Handle utf8_string_type() {
    Handle t{check(H5Tcopy(H5T_C_S1), "H5Tcopy"), H5Tclose};
    check(H5Tset_size(t.id(), H5T_VARIABLE), "H5Tset_size");
    check(H5Tset_cset(t.id(), H5T_CSET_UTF8), "H5Tset_cset");
    return t;
}
void string_attr(hid_t obj, const std::string& name, const std::string& v) {
    Handle t = utf8_string_type();
    const char* p = v.c_str();
    put_attr(obj, name, t.id(), &p);
}
void int64_attr(hid_t obj, const std::string& name, std::int64_t v) {
    put_attr(obj, name, H5T_NATIVE_INT64, &v);
}
void double_attr(hid_t obj, const std::string& name, double v) {
    put_attr(obj, name, H5T_NATIVE_DOUBLE, &v);
}

/// Raw chunk bytes compressed by one batch of write_chunks (bounds the copies held at once).
constexpr std::size_t kBatchBytes = std::size_t{32} << 20;
/// A batch this large compresses on all threads.
constexpr std::size_t kParallelBytes = std::size_t{1} << 20;

/// A chunk's bytes as they went into zlib (padded, shuffled) and what zlib made of them.
struct KeptChunk {
    std::vector<unsigned char> input, output;
};
} // namespace

/// One dataset's kept chunks (ChunkCache): `generation` is the last writer's that wrote it.
struct ChunkCache::Impl {
    struct Dataset {
        std::vector<KeptChunk> chunks;
        std::uint64_t generation = 0;
        int writes = 0;
        bool keep = true; ///< false once it is not worth keeping (write_cached)
    };
    std::map<std::string, Dataset> datasets;
    std::uint64_t generation = 0;
    Counts counts;
};

ChunkCache::ChunkCache() : m_impl(std::make_unique<Impl>()) {}
ChunkCache::~ChunkCache() = default;

ChunkCache::Counts ChunkCache::counts() const {
    Counts c = m_impl->counts;
    c.bytes_held = 0;
    for (const auto& [path, d] : m_impl->datasets)
        for (const auto& k : d.chunks) c.bytes_held += k.input.size() + k.output.size();
    return c;
}

namespace {
/// One chunk of `data` (row-major [rows, cols] of `elem`-byte values) as HDF5's filters store it:
/// padded with zeros to the full chunk, its bytes shuffled (HDF5's shuffle filter: byte j of every
/// value, then byte j + 1, ...) when `shuffle`, then deflated by zlib's compress2 at kDeflate, as
/// HDF5's deflate filter calls it. `raw` and `shuffled` are scratch of the chunk's size. With
/// `kept`, zlib's input is compared with the kept one's: if equal the kept output is taken
/// (`reused`), else the chunk is compressed and kept. False if zlib fails.
bool filter_chunk(const unsigned char* data, hsize_t rows, hsize_t cols, std::size_t elem,
                  hsize_t y0, hsize_t x0, hsize_t crows, hsize_t ccols, bool shuffle,
                  std::vector<unsigned char>& raw, std::vector<unsigned char>& shuffled,
                  std::vector<unsigned char>& out, KeptChunk* kept, bool& reused) {
    const std::size_t values = static_cast<std::size_t>(crows * ccols), bytes = values * elem;
    raw.assign(bytes, 0);
    const std::size_t n = static_cast<std::size_t>(std::min(ccols, cols - x0)) * elem;
    for (hsize_t r = 0; r < crows && y0 + r < rows; ++r)
        std::memcpy(raw.data() + r * ccols * elem, data + ((y0 + r) * cols + x0) * elem, n);
    const unsigned char* src = raw.data();
    if (shuffle && elem > 1 && values > 1) {
        shuffled.resize(bytes);
        for (std::size_t j = 0; j < elem; ++j)
            for (std::size_t i = 0; i < values; ++i) shuffled[j * values + i] = raw[i * elem + j];
        src = shuffled.data();
    }
    reused =
        kept && kept->input.size() == bytes && std::memcmp(kept->input.data(), src, bytes) == 0;
    if (reused) {
        out = kept->output;
        return true;
    }
    uLongf len = compressBound(static_cast<uLong>(bytes));
    out.resize(len);
    if (compress2(out.data(), &len, src, static_cast<uLong>(bytes), static_cast<int>(kDeflate)) !=
        Z_OK)
        return false;
    out.resize(len);
    if (kept) {
        kept->input.assign(src, src + bytes);
        kept->output = out;
    }
    return true;
}

/// Writes `data` into the chunked dataset `ds` (rank 1 or 2, created with the shuffle filter if
/// `shuffle` and the deflate filter at kDeflate) chunk by chunk with H5Dwrite_chunk: the chunks
/// are filtered here as HDF5 would filter them (filter_chunk), on all threads for large data, and
/// written in order. HDF5 filters on the calling thread alone (9 % of a dense 1 km2 year's CPU
/// time, docs/scaling.md). The stored bytes do not depend on the thread count. With `kept` (sized
/// here to the chunk count), each chunk is compared with and refreshes its kept one; returns the
/// number of chunks reused.
std::int64_t write_chunks(hid_t ds, int rank, const hsize_t* dims, const hsize_t* chunk,
                          std::size_t elem, bool shuffle, const unsigned char* data,
                          std::vector<KeptChunk>* kept) {
    const hsize_t rows = rank == 2 ? dims[0] : 1, cols = dims[rank - 1];
    const hsize_t crows = rank == 2 ? chunk[0] : 1, ccols = chunk[rank - 1];
    const hsize_t gy = (rows + crows - 1) / crows, gx = (cols + ccols - 1) / ccols;
    const auto chunks = static_cast<std::int64_t>(gy * gx);
    const std::size_t chunk_bytes = static_cast<std::size_t>(crows * ccols) * elem;
    const auto batch =
        static_cast<std::int64_t>(std::max<std::size_t>(1, kBatchBytes / chunk_bytes));
    if (kept) kept->resize(static_cast<std::size_t>(chunks));
    std::vector<std::vector<unsigned char>> out(static_cast<std::size_t>(std::min(batch, chunks)));
    std::int64_t reused_total = 0;
    for (std::int64_t b0 = 0; b0 < chunks; b0 += batch) {
        const std::int64_t b1 = std::min(chunks, b0 + batch);
        const bool parallel =
            b1 - b0 > 1 && static_cast<std::size_t>(b1 - b0) * chunk_bytes >= kParallelBytes;
        std::atomic<bool> failed{false};
        std::int64_t reused_here = 0;
#pragma omp parallel if (parallel) reduction(+ : reused_here)
        {
            std::vector<unsigned char> raw, shuffled;
#pragma omp for schedule(dynamic, 1)
            for (std::int64_t c = b0; c < b1; ++c) {
                const auto cy = static_cast<hsize_t>(c) / gx, cx = static_cast<hsize_t>(c) % gx;
                bool reused = false;
                if (!filter_chunk(data, rows, cols, elem, cy * crows, cx * ccols, crows, ccols,
                                  shuffle, raw, shuffled, out[static_cast<std::size_t>(c - b0)],
                                  kept ? &(*kept)[static_cast<std::size_t>(c)] : nullptr, reused))
                    failed = true;
                reused_here += reused;
            }
        }
        if (failed) throw Failure{"zlib's compress2 failed"};
        reused_total += reused_here;
        for (std::int64_t c = b0; c < b1; ++c) {
            const auto cy = static_cast<hsize_t>(c) / gx, cx = static_cast<hsize_t>(c) % gx;
            const hsize_t offset[2] = {rank == 2 ? cy * crows : cx * ccols, cx * ccols};
            const auto& o = out[static_cast<std::size_t>(c - b0)];
            check(H5Dwrite_chunk(ds, H5P_DEFAULT, 0, offset, o.size(), o.data()), "H5Dwrite_chunk");
        }
    }
    return reused_total;
}

template <class T>
hid_t native_type() {
    if constexpr (std::is_same_v<T, float>)
        return H5T_NATIVE_FLOAT;
    else if constexpr (std::is_same_v<T, double>)
        return H5T_NATIVE_DOUBLE;
    else if constexpr (std::is_same_v<T, std::int32_t>)
        return H5T_NATIVE_INT32;
    else if constexpr (std::is_same_v<T, std::int64_t>)
        return H5T_NATIVE_INT64;
    else
        return H5T_NATIVE_UINT8;
}
} // namespace

struct Hdf5Writer::Impl {
    Handle file;
    std::string where;
    int fd = -1; ///< the temporary file, opened at once so that an unwritable folder fails early
    ChunkCache::Impl* cache = nullptr; ///< kept chunks (Hdf5Writer(target, cache)), or none
    std::uint64_t generation = 0;      ///< this writer's in `cache`

    /// write_chunks through the cache's kept chunks of `path` where there is a cache, the
    /// dataset is not too large and its chunks are still kept (ChunkCache).
    void write_cached(const std::string& path, int rank, const hsize_t* dims, const hsize_t* chunk,
                      std::size_t elem, bool shuffle, hid_t ds, const unsigned char* data) {
        std::size_t bytes = elem;
        std::int64_t chunks = 1;
        for (int d = 0; d < rank; ++d) {
            bytes *= static_cast<std::size_t>(dims[d]);
            chunks *= static_cast<std::int64_t>((dims[d] + chunk[d] - 1) / chunk[d]);
        }
        const std::size_t most =
            rank == 1 ? ChunkCache::kMaxSeriesBytes : ChunkCache::kMaxRasterBytes;
        if (!cache || bytes > most) {
            if (cache) cache->datasets.erase(path);
            write_chunks(ds, rank, dims, chunk, elem, shuffle, data, nullptr);
            return;
        }
        ChunkCache::Impl::Dataset& kept = cache->datasets[path];
        kept.generation = generation;
        const std::int64_t reused = write_chunks(ds, rank, dims, chunk, elem, shuffle, data,
                                                 kept.keep ? &kept.chunks : nullptr);
        cache->counts.reused += reused;
        cache->counts.compressed += chunks - reused;
        // A dataset of several chunks none of which a second write repeated changes throughout
        // (a checkpoint's bytes): keeping its chunks would cost memory for nothing. (One of a
        // single chunk may be a short series that grows into chunks the next writes repeat.)
        if (kept.keep && ++kept.writes >= 2 && reused == 0 && chunks >= 4) {
            kept.keep = false;
            std::vector<KeptChunk>().swap(kept.chunks);
        }
    }

    /// After a commit: the cache keeps only the datasets this writer wrote.
    void forget_others() {
        if (!cache) return;
        std::erase_if(cache->datasets,
                      [&](const auto& d) { return d.second.generation != generation; });
    }

    ~Impl() {
        if (fd >= 0) ::close(fd);
    }

    /// Writes the whole file image to `fd` and closes it.
    void write_image(const std::vector<char>& image) {
        std::size_t done = 0;
        while (done < image.size()) {
            const ssize_t n = ::write(fd, image.data() + done, image.size() - done);
            if (n < 0 && errno == EINTR) continue;
            if (n < 0) throw IoError(where + ": write failed: " + std::strerror(errno));
            done += static_cast<std::size_t>(n);
        }
        const int rc = ::close(std::exchange(fd, -1));
        if (rc != 0) throw IoError(where + ": write failed: " + std::strerror(errno));
    }

    bool exists(const std::string& path) const {
        return check_tri(H5Lexists(file.id(), path.c_str(), H5P_DEFAULT), "H5Lexists");
    }

    /// Creates the groups above `path`.
    void ensure_parents(const std::string& path) {
        std::size_t pos = 1;
        while ((pos = path.find('/', pos)) != std::string::npos) {
            const std::string g = path.substr(0, pos);
            if (!exists(g)) {
                Handle gcpl{check(H5Pcreate(H5P_GROUP_CREATE), "H5Pcreate"), H5Pclose};
                check(H5Pset_obj_track_times(gcpl.id(), false), "H5Pset_obj_track_times");
                Handle h{
                    check(H5Gcreate2(file.id(), g.c_str(), H5P_DEFAULT, gcpl.id(), H5P_DEFAULT),
                          "H5Gcreate"),
                    H5Gclose};
                h.close("H5Gclose");
            }
            ++pos;
        }
    }

    /// Creates, writes and closes a chunked, compressed dataset; `attrs` adds its attributes.
    template <class T, class Attrs>
    void dataset(const std::string& path, int rank, const hsize_t* dims, const hsize_t* chunk,
                 bool shuffle, const T* data, Attrs&& attrs) {
        ensure_parents(path);
        Handle space = dataspace(rank, dims);
        Handle plist{check(H5Pcreate(H5P_DATASET_CREATE), "H5Pcreate"), H5Pclose};
        // No modification times in the objects: the same run gives the same bytes.
        check(H5Pset_obj_track_times(plist.id(), false), "H5Pset_obj_track_times");
        if (chunk) {
            check(H5Pset_chunk(plist.id(), rank, chunk), "H5Pset_chunk");
            if (shuffle) check(H5Pset_shuffle(plist.id()), "H5Pset_shuffle");
            check(H5Pset_deflate(plist.id(), kDeflate), "H5Pset_deflate");
        }
        const hid_t type = native_type<T>();
        Handle ds{check(H5Dcreate2(file.id(), path.c_str(), type, space.id(), H5P_DEFAULT,
                                   plist.id(), H5P_DEFAULT),
                        "H5Dcreate"),
                  H5Dclose};
        if (data && chunk)
            write_cached(path, rank, dims, chunk, sizeof(T), shuffle, ds.id(),
                         reinterpret_cast<const unsigned char*>(data));
        else if (data)
            check(H5Dwrite(ds.id(), type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), "H5Dwrite");
        attrs(ds.id());
        ds.close("H5Dclose");
    }

    template <class T>
    void raster(const std::string& path, const Raster<T>& r, const std::string& units,
                const std::string& desc) {
        const hsize_t dims[2] = {static_cast<hsize_t>(r.ny()), static_cast<hsize_t>(r.nx())};
        const hsize_t chunk[2] = {std::min(kChunk, dims[0]), std::min(kChunk, dims[1])};
        dataset(path, 2, dims, chunk, true, r.data(), [&](hid_t ds) {
            string_attr(ds, "units", units);
            string_attr(ds, "description", desc);
            string_attr(ds, "row_order", "south_to_north");
            double_attr(ds, "cell_size_m", r.cell_size());
            double_attr(ds, "origin_x_m", r.grid().origin_x_m);
            double_attr(ds, "origin_y_m", r.grid().origin_y_m);
            if (!r.crs_wkt().empty()) string_attr(ds, "crs_wkt", r.crs_wkt());
        });
    }

    template <class T>
    void series(const std::string& path, const std::vector<T>& v, const std::string& units,
                const std::string& desc) {
        const hsize_t dims[1] = {static_cast<hsize_t>(v.size())};
        const hsize_t chunk[1] = {std::min<hsize_t>(4096, dims[0])};
        dataset(path, 1, dims, v.empty() ? nullptr : chunk, false, v.empty() ? nullptr : v.data(),
                [&](hid_t ds) {
                    string_attr(ds, "units", units);
                    string_attr(ds, "description", desc);
                });
    }

    void strings(const std::string& path, const std::vector<std::string>& v,
                 const std::string& desc) {
        ensure_parents(path);
        const hsize_t dims[1] = {static_cast<hsize_t>(v.size())};
        Handle space = dataspace(1, dims);
        Handle t = utf8_string_type();
        Handle dcpl{check(H5Pcreate(H5P_DATASET_CREATE), "H5Pcreate"), H5Pclose};
        check(H5Pset_obj_track_times(dcpl.id(), false), "H5Pset_obj_track_times");
        Handle ds{check(H5Dcreate2(file.id(), path.c_str(), t.id(), space.id(), H5P_DEFAULT,
                                   dcpl.id(), H5P_DEFAULT),
                        "H5Dcreate"),
                  H5Dclose};
        std::vector<const char*> p;
        for (const auto& x : v) p.push_back(x.c_str());
        if (!p.empty())
            check(H5Dwrite(ds.id(), t.id(), H5S_ALL, H5S_ALL, H5P_DEFAULT, p.data()), "H5Dwrite");
        string_attr(ds.id(), "description", desc);
        ds.close("H5Dclose");
    }

    /// Calls f on the dataset or group at `object`, creating the group if it does not exist.
    template <class F>
    void on_object(const std::string& object, F&& f) {
        if (object != "/" && !exists(object)) ensure_parents(object + "/");
        Handle o{check(H5Oopen(file.id(), object.c_str(), H5P_DEFAULT), "H5Oopen"), H5Oclose};
        f(o.id());
        o.close("H5Oclose");
    }

    /// Runs `f`, turning an HDF5 failure into an IoError that names the file and `path`.
    template <class F>
    void guarded(const std::string& path, F&& f) {
        try {
            f();
        } catch (const Failure& e) {
            throw IoError(where + ": HDF5 write of " + path + " failed: " + e.what);
        }
    }
};

Hdf5Writer::Hdf5Writer(const std::filesystem::path& target, ChunkCache& cache)
    : Hdf5Writer(target) {
    m_impl->cache = cache.m_impl.get();
    m_impl->generation = ++m_impl->cache->generation;
}

Hdf5Writer::Hdf5Writer(const std::filesystem::path& target) : m_out(target) {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    m_impl = std::make_unique<Impl>();
    m_impl->where = target.string();
    m_impl->fd = ::open(m_out.temp_path().c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (m_impl->fd < 0)
        throw IoError(m_impl->where + ": cannot create the file: " + std::strerror(errno));
    constexpr std::size_t kGrowBytes = 1 << 20;
    Handle fapl{H5Pcreate(H5P_FILE_ACCESS), H5Pclose};
    const hid_t id =
        fapl.id() >= 0 && H5Pset_fapl_core(fapl.id(), kGrowBytes, false) >= 0
            ? H5Fcreate(m_out.temp_path().c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl.id())
            : H5I_INVALID_HID;
    if (id < 0)
        throw IoError(m_impl->where +
                      ": cannot create HDF5 file: " + hdf5_reason("H5Fcreate failed"));
    m_impl->file = Handle(id, H5Fclose);
}

Hdf5Writer::~Hdf5Writer() = default;

void Hdf5Writer::raster(const std::string& path, const RasterD& r, const std::string& units,
                        const std::string& d) {
    Raster<float> f(r.grid());
    f.set_crs_wkt(r.crs_wkt());
    for (std::int64_t k = 0; k < r.size(); ++k) f.data()[k] = static_cast<float>(r.data()[k]);
    raster(path, f, units, d);
}
void Hdf5Writer::raster(const std::string& path, const Raster<float>& r, const std::string& units,
                        const std::string& d) {
    m_impl->guarded(path, [&] { m_impl->raster(path, r, units, d); });
}
void Hdf5Writer::raster(const std::string& path, const Raster<std::int32_t>& r,
                        const std::string& units, const std::string& d) {
    m_impl->guarded(path, [&] { m_impl->raster(path, r, units, d); });
}
void Hdf5Writer::raster(const std::string& path, const Raster<std::uint8_t>& r,
                        const std::string& units, const std::string& d) {
    m_impl->guarded(path, [&] { m_impl->raster(path, r, units, d); });
}
void Hdf5Writer::series(const std::string& path, const std::vector<double>& v,
                        const std::string& units, const std::string& d) {
    m_impl->guarded(path, [&] { m_impl->series(path, v, units, d); });
}
void Hdf5Writer::series(const std::string& path, const std::vector<std::int32_t>& v,
                        const std::string& units, const std::string& d) {
    m_impl->guarded(path, [&] { m_impl->series(path, v, units, d); });
}
void Hdf5Writer::series(const std::string& path, const std::vector<std::int64_t>& v,
                        const std::string& units, const std::string& d) {
    m_impl->guarded(path, [&] { m_impl->series(path, v, units, d); });
}
void Hdf5Writer::series(const std::string& path, const std::vector<std::uint8_t>& v,
                        const std::string& units, const std::string& d) {
    m_impl->guarded(path, [&] { m_impl->series(path, v, units, d); });
}

void Hdf5Writer::external_link(const std::string& path, const std::string& file,
                               const std::string& object) {
    m_impl->guarded(path, [&] {
        m_impl->ensure_parents(path);
        check(H5Lcreate_external(file.c_str(), object.c_str(), m_impl->file.id(), path.c_str(),
                                 H5P_DEFAULT, H5P_DEFAULT),
              "H5Lcreate_external");
    });
}

void Hdf5Writer::attribute(const std::string& object, const std::string& name,
                           const std::string& value) {
    m_impl->guarded(
        object, [&] { m_impl->on_object(object, [&](hid_t o) { string_attr(o, name, value); }); });
}

void Hdf5Writer::attribute(const std::string& object, const std::string& name, double value) {
    m_impl->guarded(
        object, [&] { m_impl->on_object(object, [&](hid_t o) { double_attr(o, name, value); }); });
}

void Hdf5Writer::integer_attribute(const std::string& object, const std::string& name,
                                   std::int64_t value) {
    m_impl->guarded(
        object, [&] { m_impl->on_object(object, [&](hid_t o) { int64_attr(o, name, value); }); });
}

void Hdf5Writer::strings(const std::string& path, const std::vector<std::string>& v,
                         const std::string& description) {
    m_impl->guarded(path, [&] { m_impl->strings(path, v, description); });
}

void Hdf5Writer::commit() {
    std::vector<char> image;
    try {
        const hid_t id = m_impl->file.id();
        check(H5Fflush(id, H5F_SCOPE_GLOBAL), "H5Fflush");
        const ssize_t size = H5Fget_file_image(id, nullptr, 0);
        if (size < 0) check(-1, "H5Fget_file_image");
        image.resize(static_cast<std::size_t>(size));
        if (H5Fget_file_image(id, image.data(), image.size()) != size)
            check(-1, "H5Fget_file_image");
        m_impl->file.close("H5Fclose");
    } catch (const Failure& e) {
        throw IoError(m_impl->where + ": HDF5 close failed: " + e.what);
    }
    m_impl->write_image(image);
    m_out.commit();
    m_impl->forget_others();
}

std::string hdf5_run_kind(const std::filesystem::path& file) {
    // Quietly: a file that is not HDF5 is simply no run.
    H5E_auto2_t old_func = nullptr;
    void* old_data = nullptr;
    H5Eget_auto2(H5E_DEFAULT, &old_func, &old_data);
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    std::string kind;
    if (H5Fis_hdf5(file.c_str()) > 0) {
        const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
        if (f >= 0) {
            for (const char* name : {"checkpoint", "snapshots"})
                if (kind.empty() && H5Lexists(f, name, H5P_DEFAULT) > 0)
                    kind = std::string("an ecoterra run file (it holds /") + name + ")";
            // A snapshot file (RUN.snapshots/NNNN.h5) holds one group NNNN with the plants.
            H5G_info_t info{};
            if (kind.empty() && H5Gget_info(f, &info) >= 0)
                for (hsize_t k = 0; k < info.nlinks && kind.empty(); ++k) {
                    char name[64] = {};
                    if (H5Lget_name_by_idx(f, ".", H5_INDEX_NAME, H5_ITER_INC, k, name, sizeof name,
                                           H5P_DEFAULT) <= 0)
                        continue;
                    const std::string plants = std::string(name) + "/plants";
                    if (H5Lexists(f, name, H5P_DEFAULT) > 0 &&
                        H5Lexists(f, plants.c_str(), H5P_DEFAULT) > 0)
                        kind = "an ecoterra snapshot file (it holds /" + plants + ")";
                }
            H5Fclose(f);
        }
    }
    H5Eset_auto2(H5E_DEFAULT, old_func, old_data);
    return kind;
}

} // namespace ecoterra::io
