#pragma once
// Reading and writing elevation rasters in every format ecoterra supports. The format is chosen
// from the file name (or given explicitly); see docs/formats.md for each layout.
//
//   .h5 .hdf5       HDF5: dataset /elevation, float32 [ny, nx], row 0 = south edge, attributes
//                   cell_size_m, origin_x_m, origin_y_m, units, row_order; group /provenance
//   .asc            ESRI ASCII grid (first data row = north edge)
//   .tif .tiff      GeoTIFF through GDAL (Float32, DEFLATE, north-up); reading takes any raster
//                   GDAL opens
//   .png            16-bit grayscale PNG spanning the full 0..65535 range + sidecar FILE.png.json
//                   with the vertical scale and offset (m), cell size, origin, Unreal and Gazebo
//                   import settings
//   .gazebo.png     as .png, resampled to a square of side 2^n + 1 cells as Gazebo requires
//   .obj            Wavefront OBJ mesh, Z up, metres, two triangles per 2x2 block of cell centres
#include "ecoterra/raster.hpp"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <utility>

namespace ecoterra::terrain::io {

enum class RasterFormat { hdf5, esri_ascii, geotiff, png16, gazebo_png, obj };

/// The format named by a file's extension; throws InputError naming the file otherwise.
RasterFormat format_from_path(const std::filesystem::path& path);
/// The format with this name (hdf5, asc, geotiff, png, gazebo-png, obj).
RasterFormat format_from_name(const std::string& name);
std::string format_name(RasterFormat f);

struct WriteOptions {
    nlohmann::json provenance = nlohmann::json::object(); ///< stored where the format allows
    std::vector<std::string>* warnings = nullptr;         ///< where notes are appended
};

/// A raster reference "FILE.h5:/DATASET" (or .hdf5) split into the file and the dataset (with a
/// leading '/'); a plain path gives itself and an empty dataset. InputError for "FILE.h5:" or
/// "FILE.h5:/" with no dataset named.
std::pair<std::string, std::string> split_hdf5_reference(const std::string& reference);

/// Reads an elevation raster (m); NODATA becomes NaN. Throws IoError/InputError naming the file.
/// Notes (a PNG without sidecar, a geographic coordinate system) go to `warnings` if given.
RasterD read_raster(const std::filesystem::path& path,
                    std::vector<std::string>* warnings = nullptr);
/// Writes atomically (temporary name, then rename).
void write_raster(const RasterD& z, const std::filesystem::path& path, RasterFormat format,
                  const WriteOptions& opt = {});
inline void write_raster(const RasterD& z, const std::filesystem::path& path,
                         const WriteOptions& opt = {}) {
    write_raster(z, path, format_from_path(path), opt);
}

// Per-format entry points (used by read_raster / write_raster and by tests).
/// The dataset of a run file (hydrology or ecosystem) that holds its terrain, m.
inline constexpr const char* kRunTerrainDataset = "/terrain/elevation";
RasterD read_hdf5(const std::filesystem::path& path, const std::string& dataset = "/elevation");
void write_hdf5(const RasterD& z, const std::filesystem::path& path, const WriteOptions& opt);
RasterD read_esri_ascii(const std::filesystem::path& path);
void write_esri_ascii(const RasterD& z, const std::filesystem::path& path);
RasterD read_gdal(const std::filesystem::path& path, std::vector<std::string>* warnings = nullptr);
/// GeoTIFF with the UNITS metadata item set to `units`.
void write_geotiff(const RasterD& z, const std::filesystem::path& path,
                   const std::string& units = "m");
RasterD read_png16(const std::filesystem::path& path, std::vector<std::string>* warnings = nullptr);
void write_png16(const RasterD& z, const std::filesystem::path& path, const WriteOptions& opt);
void write_gazebo_png(const RasterD& z, const std::filesystem::path& path, const WriteOptions& opt);
RasterD read_obj(const std::filesystem::path& path);
void write_obj(const RasterD& z, const std::filesystem::path& path);

/// The sidecar path of a PNG heightmap: FILE.png.json.
std::filesystem::path png_sidecar_path(const std::filesystem::path& png);
/// True if n is a valid Unreal Engine landscape side (components x quads + 1, s5 of terrain.md).
bool is_unreal_landscape_size(int n);
/// The smallest 2^k + 1 >= n.
int gazebo_side_for(int n);

} // namespace ecoterra::terrain::io
