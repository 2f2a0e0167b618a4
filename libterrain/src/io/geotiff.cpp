// GeoTIFF (and any raster GDAL can open) through GDAL's C API.
#include "ecoterra/io/atomic_file.hpp"
#include "ecoterra/terrain/io/raster_io.hpp"

#include "gdal_util.hpp"

#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_string.h>
#include <cstdlib>
#include <gdal.h>
#include <gdalwarper.h>
#include <hdf5.h>
#include <ogr_srs_api.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <vector>

namespace ecoterra::terrain::io {

namespace gdal {

void init() {
    static std::once_flag once;
    std::call_once(once, [] {
        GDALAllRegister();
        // GDAL's HDF5 driver probes files of any name; HDF5 would print its error stack for each
        // file that is not HDF5. ecoterra reports errors itself.
        H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    });
}

OGRSpatialReferenceH dataset_srs(GDALDatasetH ds, const std::string& where) {
    OGRSpatialReferenceH srs = GDALGetSpatialRef(ds);
    if (!srs) return nullptr;
    const char* auth = OSRGetAuthorityName(srs, nullptr);
    const char* code = OSRGetAuthorityCode(srs, nullptr);
    if (!auth || !code || std::string(auth) != "EPSG") return srs;
    OGRSpatialReferenceH registry = OSRNewSpatialReference(nullptr);
    const bool known = OSRImportFromEPSG(registry, std::atoi(code)) == OGRERR_NONE;
    const auto kind = [](OGRSpatialReferenceH s) {
        return OSRIsGeocentric(s)   ? "geocentric"
               : OSRIsProjected(s)  ? "projected"
               : OSRIsGeographic(s) ? "geographic"
                                    : "other";
    };
    const std::string declared = kind(srs), registered = known ? kind(registry) : declared;
    OSRDestroySpatialReference(registry);
    if (declared != registered)
        throw InputError(where + ": its coordinate system is " + declared +
                         " but names EPSG:" + code + ", a " + registered +
                         " system; the file's georeferencing is damaged (give it a coordinate "
                         "system with gdal_edit.py -a_srs)");
    return srs;
}

int utm_epsg(double lon, double lat) {
    if (!(lat > -80 && lat < 84 && lon >= -180 && lon <= 180)) return 0;
    const int zone = std::clamp(static_cast<int>(std::floor((lon + 180) / 6)) + 1, 1, 60);
    return (lat >= 0 ? 32600 : 32700) + zone;
}

Quiet::Quiet() {
    CPLPushErrorHandler(CPLQuietErrorHandler);
    CPLErrorReset();
}
Quiet::~Quiet() {
    CPLPopErrorHandler();
}
std::string Quiet::last() {
    const char* m = CPLGetLastErrorMsg();
    return (m && *m) ? std::string(m) : std::string("unknown GDAL error");
}

} // namespace gdal

using gdal::Dataset;
using QuietGdal = gdal::Quiet;
inline void init_gdal() {
    gdal::init();
}

namespace {

/// A warped view of a dataset in geographic coordinates (degrees) in the WGS 84 UTM zone of its
/// centre (metres, square cells, bilinear), since slopes, roughness and every model in ecoterra
/// need metres; `note` says so. The view reads through `ds`, which must outlive it.
Dataset utm_view(GDALDatasetH ds, const std::string& where, std::string& note) {
    double gt[6];
    if (GDALGetGeoTransform(ds, gt) != CE_None)
        throw InputError(where + ": geographic coordinates but no geotransform");
    const double lon = gt[0] + 0.5 * GDALGetRasterXSize(ds) * gt[1];
    const double lat = gt[3] + 0.5 * GDALGetRasterYSize(ds) * gt[5];
    const int epsg = gdal::utm_epsg(lon, lat);
    if (epsg == 0)
        throw InputError(where + ": geographic coordinates centred at (" + std::to_string(lon) +
                         ", " + std::to_string(lat) +
                         ") degrees, outside the UTM zones; reproject it to a projected system "
                         "in metres first");
    const int zone = epsg % 100;
    OGRSpatialReferenceH utm = OSRNewSpatialReference(nullptr);
    char* wkt = nullptr;
    if (OSRImportFromEPSG(utm, epsg) != OGRERR_NONE || OSRExportToWkt(utm, &wkt) != OGRERR_NONE) {
        OSRDestroySpatialReference(utm);
        throw IoError(where + ": GDAL cannot build UTM zone " + std::to_string(zone) +
                      " (EPSG:" + std::to_string(epsg) + "): " + QuietGdal::last());
    }
    const double degrees = std::abs(gt[1]);
    Dataset warped(GDALAutoCreateWarpedVRT(ds, nullptr, wkt, GRA_Bilinear, 0.125, nullptr));
    CPLFree(wkt);
    OSRDestroySpatialReference(utm);
    if (!warped) throw IoError(where + ": GDAL cannot reproject it to UTM: " + QuietGdal::last());
    double wt[6];
    GDALGetGeoTransform(warped.get(), wt);
    const double src_cells =
        static_cast<double>(GDALGetRasterXSize(ds)) * static_cast<double>(GDALGetRasterYSize(ds));
    const double view_cells = static_cast<double>(GDALGetRasterXSize(warped.get())) *
                              static_cast<double>(GDALGetRasterYSize(warped.get()));
    if (view_cells > 4 * src_cells + 1e6)
        throw InputError(where + ": reprojected to UTM it would hold " +
                         std::to_string(static_cast<long long>(view_cells)) + " cells for " +
                         std::to_string(static_cast<long long>(src_cells)) +
                         " in the file; its geotransform is damaged or it spans too much of the "
                         "globe for one UTM zone");
    char text[320];
    std::snprintf(text, sizeof text,
                  "%s: geographic coordinates (cells of %.6g degrees) reprojected to WGS 84 / "
                  "UTM zone %d%s (EPSG:%d), cells of %.6g m, bilinear; ecoterra works in metres",
                  where.c_str(), degrees, zone, lat >= 0 ? "N" : "S", epsg, std::abs(wt[1]));
    note = text;
    return warped;
}

} // namespace

namespace {

/// Cells a dataset's files may declare per byte they hold: far beyond DEFLATE's ~1000:1 on
/// float32 (258 cells a byte) and what LERC or ZSTD reach on real terrain.
constexpr double kMaxCellsPerByte = 1e4;
/// Rasters up to this many cells (1 GiB at 16 bytes a cell) are read whatever their size on disk.
constexpr double kSmallRasterCells = 67108864.0;

/// A header may declare far more cells than its files hold data for (fuzzing found a 294-byte
/// GeoTIFF of 16,385 x 64,261 cells whose tiles are missing: GDAL reads it as empty, after
/// ecoterra has allocated 8 GB for it; fuzz/crashes/geotiff/huge_raster_no_data_oom.tif).
void check_declared_size(GDALDatasetH ds, const GridSpec& g, const std::string& where) {
    const double cells = static_cast<double>(g.size());
    if (cells <= kSmallRasterCells) return;
    double bytes = 0;
    char** files = GDALGetFileList(ds);
    for (char** f = files; f && *f; ++f) {
        std::error_code ec;
        const auto n = std::filesystem::file_size(*f, ec);
        if (!ec) bytes += static_cast<double>(n);
    }
    CSLDestroy(files);
    if (bytes > 0 && cells > kMaxCellsPerByte * bytes)
        throw InputError(where + ": the header declares " + std::to_string(g.nx) + " x " +
                         std::to_string(g.ny) + " cells, but its files hold only " +
                         std::to_string(static_cast<long long>(bytes)) +
                         " bytes; the file is damaged or truncated");
}

} // namespace

RasterD read_gdal(const std::filesystem::path& path, std::vector<std::string>* warnings) {
    init_gdal();
    QuietGdal quiet;
    const std::string where = path.string();
    if (!std::filesystem::exists(path)) throw InputError(where + ": no such file");
    Dataset source(GDALOpen(where.c_str(), GA_ReadOnly));
    if (!source) throw InputError(where + ": GDAL cannot read it: " + QuietGdal::last());
    std::string reprojected;
    Dataset view; // a UTM view of a geographic raster, read through `source`
    if (OGRSpatialReferenceH srs = gdal::dataset_srs(source.get(), where);
        srs && OSRIsGeographic(srs))
        view = utm_view(source.get(), where, reprojected);
    RasterD z = gdal::raster_from_dataset(view ? view.get() : source.get(), source.get(), where);
    if (warnings && !reprojected.empty()) warnings->push_back(reprojected);
    return z;
}

namespace gdal {

RasterD raster_from_dataset(GDALDatasetH ds, GDALDatasetH source, const std::string& where) {
    const int nx = GDALGetRasterXSize(ds), ny = GDALGetRasterYSize(ds);
    if (GDALGetRasterCount(ds) < 1) throw InputError(where + ": has no raster band");
    double gt[6];
    if (GDALGetGeoTransform(ds, gt) != CE_None) {
        gt[0] = 0;
        gt[1] = 1;
        gt[2] = 0;
        gt[3] = ny;
        gt[4] = 0;
        gt[5] = -1;
    }
    if (gt[2] != 0.0 || gt[4] != 0.0)
        throw InputError(where + ": rotated rasters are not supported (geotransform terms " +
                         std::to_string(gt[2]) + ", " + std::to_string(gt[4]) + ")");
    const double dx = gt[1], dy = gt[5];
    if (std::abs(std::abs(dx) - std::abs(dy)) > 1e-6 * std::abs(dx))
        throw InputError(where + ": non-square cells (" + std::to_string(dx) + " x " +
                         std::to_string(std::abs(dy)) + ") are not supported; resample first");
    GridSpec g{nx, ny, std::abs(dx), dx > 0 ? gt[0] : gt[0] + nx * dx,
               dy < 0 ? gt[3] + ny * dy : gt[3]};
    g.validate(where);
    ensure_fits_in_memory(g.size(), 16.0, where);
    check_declared_size(source, g, where);
    GDALRasterBandH band = GDALGetRasterBand(ds, 1);
    // GDAL decodes whole blocks (strips or tiles) holding every band of a pixel-interleaved
    // file: a small raster whose header declares thousands of bands would make it allocate
    // gigabytes to read band 1 (fuzzing found 17 GB for a 900-byte file of 6 x 6 cells and 65,535
    // bands). The bound: 8 bands' worth of the raster, or 2^26 samples (256 MB of float32).
    int bx = 0, by = 0;
    GDALGetBlockSize(band, &bx, &by);
    const double bands = GDALGetRasterCount(ds);
    const double samples = static_cast<double>(bx) * static_cast<double>(by) * bands;
    // (A 257-byte file of 65,535 x 6 cells in 16,129 bands of 256 x 256 tiles passed the earlier
    // bound, the raster times its bands, and made GDAL allocate 4.2 GB:
    // fuzz/crashes/geotiff/multiband_tile_oom.tif.)
    const double bound = std::max(static_cast<double>(g.size()) * std::min(bands, 8.0), 67108864.0);
    if (!(bx >= 1 && by >= 1 && samples <= bound))
        throw InputError(where + ": " + std::to_string(static_cast<long long>(bands)) +
                         " bands in blocks of " + std::to_string(bx) + " x " + std::to_string(by) +
                         " cells: reading band 1 would decode " +
                         std::to_string(static_cast<long long>(samples)) +
                         " samples for a raster of " + std::to_string(nx) + " x " +
                         std::to_string(ny) + " cells; the file is damaged or not a DEM");
    int has_nodata = 0;
    const double nodata = GDALGetRasterNoDataValue(band, &has_nodata);
    std::vector<double> buf(static_cast<std::size_t>(g.size()));
    if (GDALRasterIO(band, GF_Read, 0, 0, nx, ny, buf.data(), nx, ny, GDT_Float64, 0, 0) != CE_None)
        throw IoError(where + ": GDAL read failed: " + QuietGdal::last());
    RasterD z(g, 0.0);
    if (const char* wkt = GDALGetProjectionRef(ds); wkt && *wkt) z.set_crs_wkt(wkt);
    for (int r = 0; r < ny; ++r) {
        const int j = dy < 0 ? ny - 1 - r : r;
        for (int c = 0; c < nx; ++c) {
            const int i = dx > 0 ? c : nx - 1 - c;
            const double v = buf[static_cast<std::size_t>(r) * nx + c];
            z(i, j) = (has_nodata && (v == nodata || (std::isnan(nodata) && std::isnan(v))))
                          ? std::nan("")
                          : v;
        }
    }
    return z;
}

Dataset dataset_from_raster(const RasterD& z, const std::string& where) {
    init();
    GDALDriverH drv = GDALGetDriverByName("MEM");
    if (!drv) throw IoError("GDAL has no MEM driver");
    Dataset ds(GDALCreate(drv, "", z.nx(), z.ny(), 1, GDT_Float64, nullptr));
    if (!ds) throw IoError(where + ": GDAL cannot hold it in memory: " + Quiet::last());
    const double h = z.cell_size();
    double gt[6] = {z.grid().origin_x_m, h, 0.0, z.grid().origin_y_m + z.ny() * h, 0.0, -h};
    GDALSetGeoTransform(ds.get(), gt);
    if (!z.crs_wkt().empty() && GDALSetProjection(ds.get(), z.crs_wkt().c_str()) != CE_None)
        throw InputError(where + ": GDAL refuses its coordinate system: " + Quiet::last());
    GDALRasterBandH band = GDALGetRasterBand(ds.get(), 1);
    GDALSetRasterNoDataValue(band, std::nan(""));
    std::vector<double> buf(static_cast<std::size_t>(z.size()));
    for (int r = 0; r < z.ny(); ++r)
        for (int i = 0; i < z.nx(); ++i)
            buf[static_cast<std::size_t>(r) * z.nx() + i] = z(i, z.ny() - 1 - r);
    if (GDALRasterIO(band, GF_Write, 0, 0, z.nx(), z.ny(), buf.data(), z.nx(), z.ny(), GDT_Float64,
                     0, 0) != CE_None)
        throw IoError(where + ": GDAL cannot hold it in memory: " + Quiet::last());
    return ds;
}

} // namespace gdal

void write_geotiff(const RasterD& z, const std::filesystem::path& path, const std::string& units) {
    init_gdal();
    QuietGdal quiet;
    ecoterra::io::AtomicOutput out(path);
    GDALDriverH drv = GDALGetDriverByName("GTiff");
    if (!drv) throw IoError("GDAL has no GTiff driver");
    char** opts = nullptr;
    opts = CSLSetNameValue(opts, "TILED", "YES");
    opts = CSLSetNameValue(opts, "COMPRESS", "DEFLATE");
    opts = CSLSetNameValue(opts, "PREDICTOR", "3");
    Dataset ds(GDALCreate(drv, out.temp_path().c_str(), z.nx(), z.ny(), 1, GDT_Float32, opts));
    CSLDestroy(opts);
    if (!ds) throw IoError(path.string() + ": GDAL cannot create it: " + QuietGdal::last());
    const double h = z.cell_size();
    double gt[6] = {z.grid().origin_x_m, h, 0.0, z.grid().origin_y_m + z.ny() * h, 0.0, -h};
    GDALSetGeoTransform(ds.get(), gt);
    if (!z.crs_wkt().empty() && GDALSetProjection(ds.get(), z.crs_wkt().c_str()) != CE_None)
        throw IoError(path.string() +
                      ": GDAL refuses the raster's coordinate system: " + QuietGdal::last());
    GDALRasterBandH band = GDALGetRasterBand(ds.get(), 1);
    GDALSetRasterNoDataValue(band, std::nan(""));
    GDALSetMetadataItem(ds.get(), "UNITS", units.c_str(), nullptr);
    std::vector<float> buf(static_cast<std::size_t>(z.size()));
    for (int r = 0; r < z.ny(); ++r)
        for (int i = 0; i < z.nx(); ++i)
            buf[static_cast<std::size_t>(r) * z.nx() + i] =
                static_cast<float>(z(i, z.ny() - 1 - r));
    if (GDALRasterIO(band, GF_Write, 0, 0, z.nx(), z.ny(), buf.data(), z.nx(), z.ny(), GDT_Float32,
                     0, 0) != CE_None)
        throw IoError(path.string() + ": GDAL write failed: " + QuietGdal::last());
    ds.reset(); // flush and close before the rename
    if (CPLGetLastErrorType() >= CE_Failure)
        throw IoError(path.string() + ": GDAL write failed: " + QuietGdal::last());
    out.commit();
}

} // namespace ecoterra::terrain::io
