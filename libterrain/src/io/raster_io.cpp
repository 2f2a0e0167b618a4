#include "ecoterra/terrain/io/raster_io.hpp"

#include <algorithm>

namespace ecoterra::terrain::io {

namespace {
std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
    return s;
}
bool ends_with(const std::string& s, const std::string& suffix) {
    return s.size() >= suffix.size() &&
           s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}
} // namespace

RasterFormat format_from_path(const std::filesystem::path& path) {
    const std::string name = lower(path.filename().string());
    if (ends_with(name, ".gazebo.png")) return RasterFormat::gazebo_png;
    if (ends_with(name, ".h5") || ends_with(name, ".hdf5")) return RasterFormat::hdf5;
    if (ends_with(name, ".asc")) return RasterFormat::esri_ascii;
    if (ends_with(name, ".tif") || ends_with(name, ".tiff")) return RasterFormat::geotiff;
    if (ends_with(name, ".png")) return RasterFormat::png16;
    if (ends_with(name, ".obj")) return RasterFormat::obj;
    throw InputError(path.string() + ": unknown raster format '" + path.extension().string() +
                     "' (use .h5, .asc, .tif, .png, .gazebo.png or .obj)");
}

RasterFormat format_from_name(const std::string& name) {
    const std::string n = lower(name);
    if (n == "hdf5" || n == "h5") return RasterFormat::hdf5;
    if (n == "asc" || n == "esri-ascii") return RasterFormat::esri_ascii;
    if (n == "geotiff" || n == "tif" || n == "tiff") return RasterFormat::geotiff;
    if (n == "png" || n == "png16") return RasterFormat::png16;
    if (n == "gazebo-png" || n == "gazebo") return RasterFormat::gazebo_png;
    if (n == "obj") return RasterFormat::obj;
    throw InputError("--format: unknown raster format '" + name +
                     "' (hdf5, asc, geotiff, png, gazebo-png, obj)");
}

std::string format_name(RasterFormat f) {
    switch (f) {
    case RasterFormat::hdf5:
        return "hdf5";
    case RasterFormat::esri_ascii:
        return "asc";
    case RasterFormat::geotiff:
        return "geotiff";
    case RasterFormat::png16:
        return "png";
    case RasterFormat::gazebo_png:
        return "gazebo-png";
    case RasterFormat::obj:
        return "obj";
    }
    return "unknown";
}

std::pair<std::string, std::string> split_hdf5_reference(const std::string& text) {
    for (const std::string ext : {".h5:", ".hdf5:"}) {
        const auto at = lower(text).rfind(ext);
        if (at == std::string::npos || ends_with(lower(text), ext.substr(0, ext.size() - 1)))
            continue;
        const std::string file = text.substr(0, at + ext.size() - 1);
        std::string dataset = text.substr(at + ext.size());
        if (dataset.empty() || dataset == "/")
            throw InputError(text + ": name a dataset after the colon, e.g. " + file +
                             ":/snapshots/0000/soil_moisture");
        if (dataset.front() != '/') {
            std::string absolute(1, '/');
            absolute += dataset;
            dataset = absolute;
        }
        return {file, dataset};
    }
    return {text, ""};
}

RasterD read_raster(const std::filesystem::path& path, std::vector<std::string>* warnings) {
    // FILE.h5:/DATASET names one dataset of an HDF5 file, e.g. a snapshot's raster of a run file
    // (run.h5:/snapshots/0002/soil_moisture; the snapshot links are followed).
    const std::string text = path.string();
    if (const auto [file, dataset] = split_hdf5_reference(text); !dataset.empty()) {
        RasterD z = read_hdf5(file, dataset);
        require_valid_cells(z, text);
        return z;
    }
    if (!std::filesystem::exists(path)) throw InputError(path.string() + ": no such file");
    const std::string name = lower(path.filename().string());
    RasterD z;
    if (ends_with(name, ".h5") || ends_with(name, ".hdf5"))
        z = read_hdf5(path);
    else if (ends_with(name, ".asc"))
        z = read_esri_ascii(path);
    else if (ends_with(name, ".png"))
        z = read_png16(path, warnings);
    else if (ends_with(name, ".obj"))
        z = read_obj(path);
    else
        z = read_gdal(path, warnings); // GeoTIFF and anything else GDAL opens
    require_valid_cells(z, path.string());
    return z;
}

void write_raster(const RasterD& z, const std::filesystem::path& path, RasterFormat format,
                  const WriteOptions& opt) {
    require_valid_cells(z, path.string());
    switch (format) {
    case RasterFormat::hdf5:
        write_hdf5(z, path, opt);
        break;
    case RasterFormat::esri_ascii:
        write_esri_ascii(z, path);
        break;
    case RasterFormat::geotiff:
        write_geotiff(z, path);
        break;
    case RasterFormat::png16:
        write_png16(z, path, opt);
        break;
    case RasterFormat::gazebo_png:
        write_gazebo_png(z, path, opt);
        break;
    case RasterFormat::obj:
        write_obj(z, path);
        break;
    }
}

} // namespace ecoterra::terrain::io
