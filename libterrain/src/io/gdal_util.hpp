#pragma once
// GDAL helpers shared by the raster readers and writers of libterrain (private to the library).
#include "ecoterra/raster.hpp"

#include <gdal.h>
#include <ogr_srs_api.h>

#include <memory>
#include <string>
#include <vector>

namespace ecoterra::terrain::io::gdal {

/// Registers GDAL's drivers once (thread-safe) and silences HDF5's error printing.
void init();

/// Silences GDAL's own printing for the lifetime of the object; the last message is kept.
struct Quiet {
    Quiet();
    ~Quiet();
    Quiet(const Quiet&) = delete;
    Quiet& operator=(const Quiet&) = delete;
    static std::string last();
};

struct DatasetCloser {
    void operator()(void* d) const {
        if (d) GDALClose(d);
    }
};
using Dataset = std::unique_ptr<void, DatasetCloser>;

/// Band 1 of `ds` as a raster (south row first, NODATA as NaN, the dataset's CRS). `source` is
/// the file behind `ds` (itself or what a warped view reads), whose size on disk bounds the
/// cells a damaged header may declare; `where` names it in errors.
RasterD raster_from_dataset(GDALDatasetH ds, GDALDatasetH source, const std::string& where);

/// The coordinate system of `ds` (null without one), checked: a system that names an EPSG code of
/// another kind (a geocentric code declared as geographic, say) is refused with an InputError
/// naming `where`, since PROJ 9.1 crashes transforming from it (fuzz/library-defects/README.md).
OGRSpatialReferenceH dataset_srs(GDALDatasetH ds, const std::string& where);

/// The EPSG code of the WGS 84 UTM zone holding (lon, lat) in degrees (326zz north, 327zz
/// south), or 0 outside the UTM zones (latitudes from -80 to 84).
int utm_epsg(double lon, double lat);

/// An in-memory GDAL dataset (Float64, NODATA NaN) holding `z` north-up with its CRS.
Dataset dataset_from_raster(const RasterD& z, const std::string& where);

} // namespace ecoterra::terrain::io::gdal
