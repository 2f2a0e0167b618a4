// A window of a DEM on a new grid, through GDAL's warper (the library form of gdalwarp).
#include "ecoterra/terrain/io/dem_window.hpp"

#include "ecoterra/error.hpp"
#include "ecoterra/terrain/io/raster_io.hpp"

#include "gdal_util.hpp"

#include <cpl_conv.h>
#include <cpl_string.h>
#include <gdal_utils.h>
#include <ogr_srs_api.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace ecoterra::terrain::io {

namespace {

using nlohmann::json;

std::string num(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%.10g", v);
    return b;
}

/// Full precision, for GDAL's arguments.
std::string exact(double v) {
    char b[40];
    std::snprintf(b, sizeof b, "%.17g", v);
    return b;
}

std::string list(const double* v, int n) {
    std::string s = "[";
    for (int k = 0; k < n; ++k) s += (k ? ", " : "") + num(v[k]);
    return s + "]";
}

struct Srs {
    OGRSpatialReferenceH h = nullptr;
    Srs() = default;
    explicit Srs(OGRSpatialReferenceH x) : h(x) {
        if (h) OSRSetAxisMappingStrategy(h, OAMS_TRADITIONAL_GIS_ORDER);
    }
    Srs(const Srs&) = delete;
    Srs& operator=(const Srs&) = delete;
    Srs(Srs&& o) noexcept : h(o.h) { o.h = nullptr; }
    Srs& operator=(Srs&& o) noexcept {
        std::swap(h, o.h);
        return *this;
    }
    ~Srs() {
        if (h) OSRDestroySpatialReference(h);
    }
    std::string wkt() const {
        char* w = nullptr;
        std::string s;
        if (h && OSRExportToWkt(h, &w) == OGRERR_NONE && w) s = w;
        CPLFree(w);
        return s;
    }
    std::string name() const {
        const char* n = h ? OSRGetName(h) : nullptr;
        return n ? n : "";
    }
    int epsg() const {
        if (!h) return 0;
        const char* auth = OSRGetAuthorityName(h, nullptr);
        const char* code = OSRGetAuthorityCode(h, nullptr);
        return (auth && code && std::string(auth) == "EPSG") ? std::atoi(code) : 0;
    }
};

Srs srs_from_user(const std::string& text, const std::string& where) {
    Srs s(OSRNewSpatialReference(nullptr));
    if (OSRSetFromUserInput(s.h, text.c_str()) != OGRERR_NONE)
        throw InputError(where + " = '" + text + "': not a coordinate system GDAL knows (" +
                         gdal::Quiet::last() + "); give EPSG:n, WKT or a PROJ string");
    OSRSetAxisMappingStrategy(s.h, OAMS_TRADITIONAL_GIS_ORDER);
    return s;
}

/// The WGS 84 UTM zone of a point in degrees (EPSG 326zz north, 327zz south).
Srs utm_zone_of(double lon, double lat, const std::string& where) {
    const int epsg = gdal::utm_epsg(lon, lat);
    if (epsg == 0)
        throw InputError(where + ": the window's centre (" + num(lon) + ", " + num(lat) +
                         ") degrees lies outside the UTM zones; give terrain.crs");
    return srs_from_user("EPSG:" + std::to_string(epsg), where);
}

struct Box {
    double x0, y0, x1, y1;
    double w() const { return x1 - x0; }
    double h() const { return y1 - y0; }
};

/// The window in the source's coordinates (the centre form: just its centre, a zero box).
Box source_window(const DemRequest& req, const double* gt, int nx, int ny, const Box& extent) {
    const DemWindow& w = req.window;
    const int forms = (w.bounds ? 1 : 0) + (w.pixels ? 1 : 0) + (w.centre ? 1 : 0);
    const std::string key = req.key + ".window";
    if (forms > 1) throw InputError(key + ": give one of 'bounds', 'pixels', 'centre'");
    Box b = extent;
    if (w.bounds) {
        const auto& v = *w.bounds;
        b = {v[0], v[1], v[2], v[3]};
        if (!(std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]) &&
              std::isfinite(v[3]) && v[0] < v[2] && v[1] < v[3]))
            throw InputError(key + ".bounds = " + list(v.data(), 4) +
                             ": give [x_min, y_min, x_max, y_max] with x_min < x_max and "
                             "y_min < y_max, in the DEM's coordinate system");
    } else if (w.pixels) {
        const auto& v = *w.pixels;
        if (!(v[0] >= 0 && v[1] >= 0 && v[2] >= 1 && v[3] >= 1 && v[0] + v[2] <= nx &&
              v[1] + v[3] <= ny))
            throw InputError(key + ".pixels = " + list(v.data(), 4) +
                             ": give [column, row, columns, rows] within the DEM's " +
                             std::to_string(nx) + " x " + std::to_string(ny) +
                             " pixels (row 0 is the first, northern row)");
        const double xa = gt[0] + v[0] * gt[1], xb = gt[0] + (v[0] + v[2]) * gt[1];
        const double ya = gt[3] + v[1] * gt[5], yb = gt[3] + (v[1] + v[3]) * gt[5];
        b = {std::min(xa, xb), std::min(ya, yb), std::max(xa, xb), std::max(ya, yb)};
    } else if (w.centre) {
        const auto& c = *w.centre;
        if (!(std::isfinite(c[0]) && std::isfinite(c[1]) && w.size_m[0] > 0 && w.size_m[1] > 0 &&
              std::isfinite(w.size_m[0]) && std::isfinite(w.size_m[1])))
            throw InputError(key + ": centre " + list(c.data(), 2) + " and size_m " +
                             list(w.size_m.data(), 2) +
                             ": give a finite centre and a positive width and height in metres");
        b = {c[0], c[1], c[0], c[1]};
    }
    const double tol = 1e-6 * std::abs(gt[1]);
    if (b.x0 < extent.x0 - tol || b.x1 > extent.x1 + tol || b.y0 < extent.y0 - tol ||
        b.y1 > extent.y1 + tol) {
        const double e[4] = {extent.x0, extent.y0, extent.x1, extent.y1};
        const double g[4] = {b.x0, b.y0, b.x1, b.y1};
        throw InputError(key + " " + (w.centre ? "centre " + list(g, 2) : list(g, 4)) +
                         " reaches outside " + req.path.string() + ", whose extent is " +
                         list(e, 4) + " (x_min, y_min, x_max, y_max in its coordinate system)");
    }
    return b;
}

gdal::Dataset open_source(const std::filesystem::path& path) {
    const std::string where = path.string();
    if (!std::filesystem::exists(path)) throw InputError(where + ": no such file");
    const RasterFormat f = format_from_path(path);
    if (f == RasterFormat::geotiff || f == RasterFormat::esri_ascii) {
        gdal::Dataset d(GDALOpen(where.c_str(), GA_ReadOnly));
        if (!d) throw InputError(where + ": GDAL cannot read it: " + gdal::Quiet::last());
        if (GDALGetRasterCount(d.get()) < 1) throw InputError(where + ": has no raster band");
        return d;
    }
    return gdal::dataset_from_raster(read_raster(path), where);
}

const char* gdal_method(const std::string& m) {
    return m == "nearest" ? "near" : m.c_str();
}

} // namespace

const std::vector<std::string>& dem_resampling_methods() {
    static const std::vector<std::string> m{"auto",        "nearest", "bilinear", "cubic",
                                            "cubicspline", "lanczos", "average"};
    return m;
}

namespace {

/// The source, its grid and systems, and the window in the target system: what the warp needs.
struct WarpPlan {
    gdal::Dataset src;
    int snx = 0, sny = 0;
    double gt[6] = {};
    Box extent{}, sw{}, tw{}; ///< the DEM's extent; the window in the source's, target's system
    Srs source, target;       ///< target.h null: the source's own
    std::string crs;          ///< the target as a user may give it back
    bool reproject = false;
    double own_cell = 0, cell = 0;
    int nx = 0, ny = 0;
};

void check_request(const DemRequest& req) {
    const auto& methods = dem_resampling_methods();
    if (std::find(methods.begin(), methods.end(), req.resampling) == methods.end())
        throw InputError(req.key + ".resampling = '" + req.resampling +
                         "': not a method (auto, nearest, bilinear, cubic, cubicspline, lanczos, "
                         "average)");
    if (!(req.cell_m >= 0 && std::isfinite(req.cell_m)))
        throw InputError(req.key + ".cell_m = " + num(req.cell_m) +
                         ": give a positive cell side in metres (0: the DEM's own)");
}

/// The source's grid and extent, and the window in its system.
void plan_source(const DemRequest& req, WarpPlan& p) {
    const std::string where = req.path.string();
    p.src = open_source(req.path);
    p.snx = GDALGetRasterXSize(p.src.get());
    p.sny = GDALGetRasterYSize(p.src.get());
    double* gt = p.gt;
    if (GDALGetGeoTransform(p.src.get(), gt) != CE_None)
        throw InputError(where + ": has no geotransform, so " + req.key +
                         ".window, cell_m and crs have no coordinates to work in");
    if (gt[2] != 0.0 || gt[4] != 0.0 || gt[1] == 0.0 || gt[5] == 0.0)
        throw InputError(where + ": rotated or degenerate geotransform (" + list(gt, 6) + ")");
    p.extent = {std::min(gt[0], gt[0] + p.snx * gt[1]), std::min(gt[3], gt[3] + p.sny * gt[5]),
                std::max(gt[0], gt[0] + p.snx * gt[1]), std::max(gt[3], gt[3] + p.sny * gt[5])};
    if (req.onto && (req.window.bounds || req.window.pixels || req.window.centre))
        throw InputError(req.key + ": a window and a target grid together");
    p.sw = req.onto ? p.extent : source_window(req, gt, p.snx, p.sny, p.extent);
}

/// The target system: the user's, the window centre's UTM zone for a geographic DEM, or the
/// DEM's own; in metres.
void plan_systems(const DemRequest& req, WarpPlan& p) {
    const std::string where = req.path.string();
    OGRSpatialReferenceH raw = gdal::dataset_srs(p.src.get(), where);
    p.source = Srs(raw ? OSRClone(raw) : nullptr);
    p.crs = req.crs;
    if (req.onto) {
        if (p.source.h && !req.onto_crs_wkt.empty())
            p.target = srs_from_user(req.onto_crs_wkt, req.key + " (the terrain's system)");
    } else if (!req.crs.empty()) {
        if (!p.source.h)
            throw InputError(req.key + ".crs = '" + req.crs + "': " + where +
                             " has no coordinate system to reproject from");
        p.target = srs_from_user(req.crs, req.key + ".crs");
    } else if (p.source.h && OSRIsGeographic(p.source.h)) {
        p.target = utm_zone_of(0.5 * (p.sw.x0 + p.sw.x1), 0.5 * (p.sw.y0 + p.sw.y1), where);
        p.crs = "EPSG:" + std::to_string(p.target.epsg());
    }
    p.reproject = p.target.h && !OSRIsSame(p.source.h, p.target.h);
    if (p.target.h && OSRIsGeographic(p.target.h))
        throw InputError(req.key + ".crs = '" + req.crs +
                         "' is geographic (degrees); ecoterra works in metres: give a projected "
                         "system");
    if (const Srs& t = p.target.h ? p.target : p.source; t.h && OSRIsProjected(t.h)) {
        const double unit = OSRGetLinearUnits(t.h, nullptr);
        if (std::abs(unit - 1.0) > 1e-9)
            throw InputError(where + ": its coordinate system " + t.name() +
                             " counts in units of " + num(unit) +
                             " m; ecoterra works in metres: give " + req.key +
                             ".crs (a projected system in metres, e.g. the UTM zone)");
    }
}

/// Transforms a box (or, with `point`, its corner alone) from the source to the target system.
Box transform(const WarpPlan& p, const Box& b, bool point, const std::string& what) {
    OGRCoordinateTransformationH ct = OCTNewCoordinateTransformation(p.source.h, p.target.h);
    if (!ct)
        throw InputError(what + ": GDAL cannot transform it to " + p.target.name() + ": " +
                         gdal::Quiet::last());
    Box t = b;
    const bool ok =
        point ? OCTTransform(ct, 1, &t.x0, &t.y0, nullptr) != 0
              : OCTTransformBounds(ct, b.x0, b.y0, b.x1, b.y1, &t.x0, &t.y0, &t.x1, &t.y1, 21) != 0;
    OCTDestroyCoordinateTransformation(ct);
    if (!ok)
        throw InputError(what + ": GDAL cannot transform it to " + p.target.name() + ": " +
                         gdal::Quiet::last());
    if (point) t.x1 = t.x0, t.y1 = t.y0;
    return t;
}

/// The window in the target system, snapped to whole cells of the target cell.
void plan_grid(const DemRequest& req, WarpPlan& p) {
    if (req.onto) { // the given grid, exactly
        const GridSpec& g = *req.onto;
        p.tw = {g.origin_x_m, g.origin_y_m, g.origin_x_m + g.width_m(),
                g.origin_y_m + g.height_m()};
        p.cell = g.cell_size_m;
        p.nx = g.nx;
        p.ny = g.ny;
        p.own_cell = std::abs(p.gt[1]);
        if (p.reproject) {
            const Box tp = transform(p, p.extent, false, req.path.string());
            p.own_cell = std::sqrt(tp.w() * tp.h() / (static_cast<double>(p.snx) * p.sny));
        }
        return;
    }
    const bool centre = req.window.centre.has_value();
    p.tw = p.reproject ? transform(p, p.sw, centre, req.key + ".window") : p.sw;
    // The DEM's own cell in the target system: its side where nothing is reprojected, else the
    // side of a square holding as much of the window as one source cell does.
    p.own_cell = std::abs(p.gt[1]);
    if (p.reproject) {
        const Box probe = centre ? p.extent : p.sw;
        const double cells = (probe.w() / std::abs(p.gt[1])) * (probe.h() / std::abs(p.gt[5]));
        const Box tp = centre ? transform(p, probe, false, req.path.string()) : p.tw;
        p.own_cell = std::sqrt(tp.w() * tp.h() / cells);
    }
    p.cell = req.cell_m > 0 ? req.cell_m : p.own_cell;
    const double half_w = 0.5 * req.window.size_m[0], half_h = 0.5 * req.window.size_m[1];
    if (centre) p.tw = {p.tw.x0 - half_w, p.tw.y0 - half_h, p.tw.x0 + half_w, p.tw.y0 + half_h};
    const double nxd = std::max(1.0, std::round(p.tw.w() / p.cell));
    const double nyd = std::max(1.0, std::round(p.tw.h() / p.cell));
    if (!(nxd * nyd <= 4.0e9))
        throw InputError(req.key + ".cell_m = " + num(p.cell) + ": the window would hold " +
                         num(nxd) + " x " + num(nyd) + " cells");
    ensure_fits_in_memory(static_cast<std::int64_t>(nxd * nyd), 16.0,
                          req.path.string() + " (window)");
    p.nx = static_cast<int>(nxd);
    p.ny = static_cast<int>(nyd);
    if (centre) {
        const double cx = 0.5 * (p.tw.x0 + p.tw.x1), cy = 0.5 * (p.tw.y0 + p.tw.y1);
        p.tw = {cx - 0.5 * p.nx * p.cell, cy - 0.5 * p.ny * p.cell, cx + 0.5 * p.nx * p.cell,
                cy + 0.5 * p.ny * p.cell};
    } else {
        p.tw.x1 = p.tw.x0 + p.nx * p.cell;
        p.tw.y1 = p.tw.y0 + p.ny * p.cell;
    }
}

/// GDAL's warper onto the planned grid, in memory.
gdal::Dataset warp(const WarpPlan& p, const std::string& method, const std::string& where) {
    std::vector<std::string> args{"-of",
                                  "MEM",
                                  "-te",
                                  exact(p.tw.x0),
                                  exact(p.tw.y0),
                                  exact(p.tw.x1),
                                  exact(p.tw.y1),
                                  "-ts",
                                  std::to_string(p.nx),
                                  std::to_string(p.ny),
                                  "-r",
                                  gdal_method(method),
                                  "-ot",
                                  "Float64",
                                  "-dstnodata",
                                  "nan",
                                  "-et",
                                  "0"};
    const std::string target_wkt = p.target.wkt();
    if (p.reproject) args.insert(args.end(), {"-t_srs", target_wkt});
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    GDALWarpAppOptions* o = GDALWarpAppOptionsNew(argv.data(), nullptr);
    if (!o) throw IoError(where + ": GDAL refuses the warp options: " + gdal::Quiet::last());
    GDALDatasetH in = p.src.get();
    int usage_error = 0;
    gdal::Dataset out(GDALWarp("", nullptr, 1, &in, o, &usage_error));
    GDALWarpAppOptionsFree(o);
    if (!out) throw IoError(where + ": GDAL's warper failed: " + gdal::Quiet::last());
    return out;
}

json record(const DemRequest& req, const WarpPlan& p, const std::string& method,
            std::int64_t missing) {
    const Srs& t = p.target.h ? p.target : p.source;
    json w = json::object();
    if (req.window.bounds) w["bounds"] = *req.window.bounds;
    if (req.window.pixels) w["pixels"] = *req.window.pixels;
    if (req.window.centre) w = {{"centre", *req.window.centre}, {"size_m", req.window.size_m}};
    const bool degrees = p.source.h && OSRIsGeographic(p.source.h);
    return {{"file", req.path.string()},
            {"window", w},
            {"method", "GDAL warper (gdalwarp), exact transformation"},
            {"resampling", method},
            {"source",
             {{"size", {p.snx, p.sny}},
              {"cell", std::abs(p.gt[1])},
              {"crs", p.source.name()},
              {"epsg", p.source.epsg()},
              {"units", degrees ? "degrees" : "m"}}},
            {"size", {p.nx, p.ny}},
            {"cell_m", p.cell},
            {"bounds_m", {p.tw.x0, p.tw.y0, p.tw.x1, p.tw.y1}},
            {"crs", t.name()},
            {"epsg", t.epsg()},
            {"reprojected", p.reproject},
            {"no_data_cells", missing}};
}

} // namespace

DemRead read_dem(const DemRequest& req, std::vector<std::string>* warnings) {
    gdal::init();
    gdal::Quiet quiet;
    const std::string where = req.path.string();
    check_request(req);
    WarpPlan p;
    plan_source(req, p);
    plan_systems(req, p);
    plan_grid(req, p);
    const std::string method = req.resampling != "auto"
                                   ? req.resampling
                                   : (p.cell <= p.own_cell * (1 + 1e-9) ? "cubic" : "average");
    const gdal::Dataset out = warp(p, method, where);
    DemRead r{gdal::raster_from_dataset(out.get(), p.src.get(), where), json::object(), method,
              p.crs};
    std::int64_t missing = 0;
    for (std::int64_t k = 0; k < r.z.size(); ++k) missing += std::isnan(r.z.data()[k]) ? 1 : 0;
    if (missing == r.z.size())
        throw InputError(req.key + ".window of " + where + ": every cell is NODATA");
    if (missing > 0 && warnings)
        warnings->push_back(where + ": " + std::to_string(missing) + " of " +
                            std::to_string(r.z.size()) +
                            " cells of the window have no data (outside the DEM or on its "
                            "NODATA cells); they are treated as outside the terrain");
    r.record = record(req, p, method, missing);
    return r;
}

} // namespace ecoterra::terrain::io
