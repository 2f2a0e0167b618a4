#pragma once
// A window of a DEM, reprojected and resampled onto a grid of the scene's cell size through
// GDAL's warper (gdalwarp's library form), so that a 30 m or 90 m DEM of a real place carries a
// 1 ha to 1 km2 forest at 1 m plant cells. docs/formats.md "DEM windows".
#include "ecoterra/raster.hpp"

#include <nlohmann/json.hpp>

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace ecoterra::terrain::io {

/// The part of a DEM to read; at most one of the three forms.
struct DemWindow {
    /// x_min, y_min, x_max, y_max in the DEM's own coordinate system (its units: metres, or
    /// degrees for a geographic DEM).
    std::optional<std::array<double, 4>> bounds;
    /// column, row, columns, rows of the file's pixels; row 0 is the file's first (northern) row,
    /// as gdalinfo and GIS programs count.
    std::optional<std::array<double, 4>> pixels;
    /// A rectangle of width x height metres (in the target system) around a centre given in the
    /// DEM's own coordinate system.
    std::optional<std::array<double, 2>> centre;
    std::array<double, 2> size_m{0, 0};
};

/// What `read_dem` reads: a file, a window, a target cell and system, a resampling method.
struct DemRequest {
    std::filesystem::path path;
    DemWindow window;
    double cell_m = 0; ///< target cell side, m; 0: the DEM's own
    /// auto, nearest, bilinear, cubic, cubicspline, lanczos, average
    std::string resampling = "auto";
    std::string crs;             ///< target system (EPSG:n, WKT, PROJ); "": see read_dem
    std::string key = "terrain"; ///< the scene section named in errors
    /// Instead of a window: exactly this grid (in `onto_crs_wkt`, or the source's system when
    /// that is empty or the source has none), e.g. a soil raster put on the terrain's grid.
    std::optional<GridSpec> onto;
    std::string onto_crs_wkt;
};

/// The resampling methods `DemRequest::resampling` accepts, in the order the docs list them.
const std::vector<std::string>& dem_resampling_methods();

struct DemRead {
    RasterD z;              ///< the window on its new grid, m, with the target CRS
    nlohmann::json record;  ///< what was done: window, method, CRSs, source and target grids
    std::string resampling; ///< the method used ("auto" resolved)
    std::string crs;        ///< the target system as a user may give it back (EPSG:n or WKT)
};

/// Reads the window of `req.path` onto a grid of `req.cell_m` in `req.crs` (default: the DEM's
/// own system; for a geographic DEM the WGS 84 UTM zone of the window's centre). "auto"
/// resampling is cubic convolution when the cell shrinks or stays and the area average when it
/// grows. Any raster ecoterra reads works (GDAL opens GeoTIFF and ASCII grids directly; the
/// others are read first). Throws InputError naming the file, key and value: a window outside
/// the DEM, an empty or inverted window, an unknown method or system, a grid too big for memory.
DemRead read_dem(const DemRequest& req, std::vector<std::string>* warnings = nullptr);

/// True if a request asks for more than reading the file as it is (a window, a cell, a system).
inline bool dem_request_resamples(const DemRequest& r) {
    return r.window.bounds || r.window.pixels || r.window.centre || r.cell_m > 0 ||
           !r.crs.empty() || r.onto.has_value();
}

} // namespace ecoterra::terrain::io
