// The HDF5 writer filters its chunks itself (shuffle and deflate, on all threads) and stores them
// with H5Dwrite_chunk. Checked against HDF5's own filter pipeline: every stored chunk must carry
// the bytes HDF5's H5Dwrite stores for the same data and dataset properties, and HDF5's reader
// must decode every value, over shapes with and without partial edge chunks, each element size,
// and one and two threads.
#include "support/temp_dir.hpp"

#include "ecoterra/io/hdf5_writer.hpp"

#include <catch2/catch.hpp>
#include <hdf5.h>
#include <omp.h>

#include <cstdint>
#include <random>
#include <vector>

using namespace ecoterra;
namespace fs = std::filesystem;

namespace {

template <class T>
hid_t h5_type() {
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

/// Values that compress somewhat (a smooth part) and somewhat not (random low bits).
template <class T>
std::vector<T> values(std::size_t n, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> noise(0, 50);
    std::vector<T> v(n);
    for (std::size_t i = 0; i < n; ++i)
        v[i] =
            static_cast<T>(static_cast<double>(i % 797) * 0.25 + noise(rng)); // < 250: fits uint8
    return v;
}

template <class T>
Raster<T> raster_of(const GridSpec& g, const std::vector<T>& v) {
    Raster<T> r(g);
    std::copy(v.begin(), v.end(), r.data());
    return r;
}

/// The chunks HDF5 itself stores for `data` in a dataset of the writer's properties: its own
/// H5Dwrite through its shuffle and deflate (level 4) filters, in a file of its own.
template <class T>
void reference_dataset(hid_t file, const std::vector<hsize_t>& dims,
                       const std::vector<hsize_t>& chunk, bool shuffle,
                       const std::vector<T>& data) {
    const hid_t space = H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr);
    const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
    H5Pset_chunk(dcpl, static_cast<int>(chunk.size()), chunk.data());
    if (shuffle) H5Pset_shuffle(dcpl);
    H5Pset_deflate(dcpl, 4);
    const hid_t ds = H5Dcreate2(file, "/d", h5_type<T>(), space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
    REQUIRE(ds >= 0);
    REQUIRE(H5Dwrite(ds, h5_type<T>(), H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data()) >= 0);
    H5Dclose(ds);
    H5Pclose(dcpl);
    H5Sclose(space);
}

/// The stored (filtered) bytes of the chunk at `offset`, and its filter mask.
std::vector<unsigned char> stored_chunk(hid_t ds, const std::vector<hsize_t>& offset,
                                        std::uint32_t& mask) {
    hsize_t size = 0;
    REQUIRE(H5Dget_chunk_storage_size(ds, offset.data(), &size) >= 0);
    std::vector<unsigned char> bytes(size);
    mask = 0;
    REQUIRE(H5Dread_chunk(ds, H5P_DEFAULT, offset.data(), &mask, bytes.data()) >= 0);
    return bytes;
}

/// Compares the dataset at `path` of `ours` chunk by chunk with /d of `theirs`, and HDF5's
/// reading of ours with `data`. Returns the number of chunks compared.
template <class T>
int compare(const fs::path& ours, const std::string& path, const fs::path& theirs,
            const std::vector<hsize_t>& dims, const std::vector<hsize_t>& chunk,
            const std::vector<T>& data) {
    const hid_t fa = H5Fopen(ours.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    const hid_t fb = H5Fopen(theirs.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    REQUIRE(fa >= 0);
    REQUIRE(fb >= 0);
    const hid_t a = H5Dopen2(fa, path.c_str(), H5P_DEFAULT);
    const hid_t b = H5Dopen2(fb, "/d", H5P_DEFAULT);
    REQUIRE(a >= 0);
    std::vector<T> back(data.size());
    if (!back.empty())
        REQUIRE(H5Dread(a, h5_type<T>(), H5S_ALL, H5S_ALL, H5P_DEFAULT, back.data()) >= 0);
    CHECK(back == data);
    int compared = 0;
    const hsize_t rows = dims.size() == 2 ? dims[0] : 1, rstep = dims.size() == 2 ? chunk[0] : 1;
    for (hsize_t y = 0; y < rows; y += rstep)
        for (hsize_t x = 0; x < dims.back(); x += chunk.back()) {
            const std::vector<hsize_t> offset =
                dims.size() == 2 ? std::vector<hsize_t>{y, x} : std::vector<hsize_t>{x};
            std::uint32_t ma = 1, mb = 1;
            const auto sa = stored_chunk(a, offset, ma);
            const auto sb = stored_chunk(b, offset, mb);
            CHECK(ma == mb);
            CHECK(sa == sb);
            ++compared;
        }
    H5Dclose(a);
    H5Dclose(b);
    H5Fclose(fa);
    H5Fclose(fb);
    return compared;
}

/// Writes HDF5's own dataset of `data` (reference_dataset) into a file of its own in `dir` and
/// compares `path` of `ours` with it (compare). Returns the number of chunks compared.
template <class T>
int check_against_hdf5(const test::TempDir& dir, const fs::path& ours, const std::string& path,
                       int shape, const std::vector<hsize_t>& dims,
                       const std::vector<hsize_t>& chunk, bool shuffle,
                       const std::vector<T>& data) {
    const fs::path ref = dir / ("ref" + std::to_string(shape) + path.substr(3) + ".h5");
    const hid_t rf = H5Fcreate(ref.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    REQUIRE(rf >= 0);
    reference_dataset(rf, dims, chunk, shuffle, data);
    H5Fclose(rf);
    return compare(ours, path, ref, dims, chunk, data);
}

} // namespace

TEST_CASE("Hdf5Writer: its chunks are the bytes of HDF5's own shuffle and deflate filters, on one "
          "and two threads",
          "[core][hdf5]") {
    test::TempDir dir;
    const int threads_before = omp_get_max_threads();
    int shape = 0, chunks = 0;
    // Rasters of 256 x 256 chunks (shuffled): whole chunks, partial edge chunks in either
    // direction or both, a single cell, and a grid large enough to compress on both threads.
    const std::vector<std::pair<int, int>> grids = {{1, 1},     {3, 1000},  {256, 256},
                                                    {257, 255}, {300, 513}, {700, 700}};
    for (const int threads : {1, 2}) {
        omp_set_num_threads(threads);
        for (const auto& [ny, nx] : grids) {
            ++shape;
            GridSpec g;
            g.nx = nx;
            g.ny = ny;
            const std::vector<hsize_t> dims = {static_cast<hsize_t>(ny), static_cast<hsize_t>(nx)};
            const std::vector<hsize_t> chunk = {std::min<hsize_t>(256, dims[0]),
                                                std::min<hsize_t>(256, dims[1])};
            const auto f = values<float>(static_cast<std::size_t>(g.size()), 11u * shape);
            const auto i = values<std::int32_t>(static_cast<std::size_t>(g.size()), 13u * shape);
            const auto u = values<std::uint8_t>(static_cast<std::size_t>(g.size()), 17u * shape);
            const fs::path ours = dir / ("ours" + std::to_string(shape) + ".h5");
            io::Hdf5Writer w(ours);
            w.raster("/g/f", raster_of(g, f), "m", "float");
            w.raster("/g/i", raster_of(g, i), "1", "int32");
            w.raster("/g/u", raster_of(g, u), "1", "uint8");
            w.commit();
            chunks += check_against_hdf5(dir, ours, "/g/f", shape, dims, chunk, true, f);
            chunks += check_against_hdf5(dir, ours, "/g/i", shape, dims, chunk, true, i);
            chunks += check_against_hdf5(dir, ours, "/g/u", shape, dims, chunk, true, u);
        }
        // Series of 4096-value chunks (not shuffled): empty, one value, one short of a chunk,
        // one over, and long (a checkpoint's bytes).
        for (const std::size_t n :
             {std::size_t{1}, std::size_t{4095}, std::size_t{4097}, std::size_t{1} << 20}) {
            ++shape;
            const auto d = values<double>(n, 19u * shape);
            const auto l = values<std::int64_t>(n, 23u * shape);
            const auto b = values<std::uint8_t>(n, 29u * shape);
            const fs::path ours = dir / ("ours" + std::to_string(shape) + ".h5");
            io::Hdf5Writer w(ours);
            w.series("/s/d", d, "m", "double");
            w.series("/s/l", l, "1", "int64");
            w.series("/s/b", b, "1", "bytes");
            w.series("/s/empty", std::vector<double>{}, "1", "no values");
            w.commit();
            const std::vector<hsize_t> dims = {n}, chunk = {std::min<hsize_t>(4096, n)};
            chunks += check_against_hdf5(dir, ours, "/s/d", shape, dims, chunk, false, d);
            chunks += check_against_hdf5(dir, ours, "/s/l", shape, dims, chunk, false, l);
            chunks += check_against_hdf5(dir, ours, "/s/b", shape, dims, chunk, false, b);
        }
    }
    omp_set_num_threads(threads_before);
    // 6 grids of 1, 4, 1, 2, 6 and 9 chunks, three types; 4 series of 1, 1, 2 and 256 chunks,
    // three types; on each thread count.
    CHECK(chunks == 2 * (3 * (1 + 4 + 1 + 2 + 6 + 9) + 3 * (1 + 1 + 2 + 256)));
}

TEST_CASE("Hdf5Writer with a ChunkCache: a rewritten file reuses exactly the chunks it repeats and "
          "is byte for byte HDF5's",
          "[core][hdf5]") {
    test::TempDir dir;
    io::ChunkCache cache;
    GridSpec g;
    g.nx = 300;
    g.ny = 513; // 2 x 3 chunks of 256 x 256, partial at the edges
    const auto terrain = values<float>(static_cast<std::size_t>(g.size()), 3);
    auto grown = values<double>(9000, 5);     // a series that grows: 3 chunks of 4096, then 4
    auto changing = values<double>(20000, 7); // 5 chunks, all changed at every write
    const fs::path first = dir / "first.h5";
    {
        io::Hdf5Writer w(first, cache);
        w.raster("/terrain", raster_of(g, terrain), "m", "unchanged");
        w.series("/grown", grown, "m", "grows");
        w.series("/changing", changing, "1", "changes throughout");
        w.series("/dropped", values<double>(5000, 9), "1", "not in the next file");
        w.commit();
    }
    const io::ChunkCache::Counts c1 = cache.counts();
    CHECK(c1.reused == 0);
    CHECK(c1.compressed == 6 + 3 + 5 + 2);
    CHECK(c1.bytes_held > 0);

    // The next file: the raster repeats (6 chunks), the series grows by 4000 values (its first two
    // chunks repeat; the third, once partial, is now full), the changing one changes everywhere.
    for (auto& x : changing) x += 1;
    const auto more = values<double>(4000, 11);
    grown.insert(grown.end(), more.begin(), more.end());
    const fs::path second = dir / "second.h5";
    {
        io::Hdf5Writer w(second, cache);
        w.raster("/terrain", raster_of(g, terrain), "m", "unchanged");
        w.series("/grown", grown, "m", "grows");
        w.series("/changing", changing, "1", "changes throughout");
        w.commit();
    }
    const io::ChunkCache::Counts c2 = cache.counts();
    CHECK(c2.reused - c1.reused == 6 + 2);
    CHECK(c2.compressed - c1.compressed == 2 + 5);
    // The changing series (5 chunks, none repeated) and the dropped one are no longer held:
    // what is held is the raster's and the grown series' chunks, at most their raw bytes twice.
    const std::size_t raster_raw = 2 * 3 * 256 * 256 * sizeof(float);
    const std::size_t series_raw = 4 * 4096 * sizeof(double);
    CHECK(c2.bytes_held <= 2 * (raster_raw + series_raw));
    CHECK(c2.bytes_held >= raster_raw + series_raw);

    // Every chunk of the second file is what HDF5's own filters store for the same data.
    int chunks = 0;
    chunks +=
        check_against_hdf5(dir, second, "/terrain", 100, {513, 300}, {256, 256}, true, terrain);
    chunks += check_against_hdf5(dir, second, "/grown", 101, {13000}, {4096}, false, grown);
    chunks += check_against_hdf5(dir, second, "/changing", 102, {20000}, {4096}, false, changing);
    CHECK(chunks == 6 + 4 + 5);

    // A third file changing one raster chunk reuses the other five and stores the new one right.
    auto edited = terrain;
    edited[static_cast<std::size_t>(300 * 400 + 10)] += 1; // row 400: the second row of chunks
    const fs::path third = dir / "third.h5";
    {
        io::Hdf5Writer w(third, cache);
        w.raster("/terrain", raster_of(g, edited), "m", "one chunk changed");
        w.commit();
    }
    CHECK(cache.counts().reused - c2.reused == 5);
    CHECK(cache.counts().compressed - c2.compressed == 1);
    CHECK(check_against_hdf5(dir, third, "/terrain", 103, {513, 300}, {256, 256}, true, edited) ==
          6);

    // A raster over 1 MiB is written, not kept: what is held does not grow.
    const std::size_t held = cache.counts().bytes_held;
    GridSpec big;
    big.nx = big.ny = 600; // 1.44 MB of float32
    const auto large = values<float>(static_cast<std::size_t>(big.size()), 13);
    const fs::path fourth = dir / "fourth.h5";
    {
        io::Hdf5Writer w(fourth, cache);
        w.raster("/terrain", raster_of(g, edited), "m", "one chunk changed");
        w.raster("/large", raster_of(big, large), "m", "too large to keep");
        w.commit();
    }
    CHECK(cache.counts().bytes_held == held);
    CHECK(cache.counts().reused - c2.reused == 5 + 6);
    CHECK(check_against_hdf5(dir, fourth, "/large", 104, {600, 600}, {256, 256}, true, large) == 9);
}
