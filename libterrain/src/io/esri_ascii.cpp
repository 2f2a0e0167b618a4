// ESRI ASCII grid (ArcGIS "ASCII to Raster"): a six-line header, then rows north to south.
#include "ecoterra/io/atomic_file.hpp"
#include "ecoterra/terrain/io/raster_io.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>

namespace ecoterra::terrain::io {

namespace {
constexpr double kDefaultNodata = -9999.0;

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
    return s;
}

double parse_number(const std::string& tok, const std::string& where, const std::string& field) {
    double v = 0;
    const char* b = tok.data();
    const char* e = b + tok.size();
    if (!tok.empty() && *b == '+') ++b;
    auto [p, ec] = std::from_chars(b, e, v);
    if (ec != std::errc() || p != e)
        throw InputError(where + ": field " + field + " is not a number: '" + tok + "'");
    return v;
}
/// A whole number of cells in [1, 2^31 - 1] (ncols, nrows).
int parse_count(const std::string& tok, const std::string& where, const std::string& field) {
    const double v = parse_number(tok, where, field);
    if (!(v >= 1 && v <= 2147483647.0) || v != std::floor(v))
        throw InputError(where + ": field " + field +
                         " must be a whole number of cells from 1 to " + "2147483647, got '" + tok +
                         "'");
    return static_cast<int>(v);
}
} // namespace

RasterD read_esri_ascii(const std::filesystem::path& path) {
    const std::string where = path.string();
    const std::string text = ecoterra::io::read_text(path);
    std::istringstream in(text);
    std::map<std::string, std::string> h;
    std::string key;
    // Header: key value pairs until the first token that is not a known key.
    const char* keys[] = {"ncols",     "nrows",    "xllcorner",    "yllcorner", "xllcenter",
                          "yllcenter", "cellsize", "nodata_value", "dx",        "dy"};
    std::streampos data_start = in.tellg();
    while (in >> key) {
        const std::string k = lower(key);
        if (std::find(std::begin(keys), std::end(keys), k) == std::end(keys)) break;
        std::string v;
        if (!(in >> v)) throw InputError(where + ": header field " + key + " has no value");
        h[k] = v;
        data_start = in.tellg();
    }
    for (const char* req : {"ncols", "nrows"})
        if (!h.count(req)) throw InputError(where + ": header lacks " + std::string(req));
    GridSpec g;
    g.nx = parse_count(h["ncols"], where, "ncols");
    g.ny = parse_count(h["nrows"], where, "nrows");
    if (h.count("cellsize")) {
        g.cell_size_m = parse_number(h["cellsize"], where, "cellsize");
    } else if (h.count("dx") && h.count("dy")) {
        const double dx = parse_number(h["dx"], where, "dx"),
                     dy = parse_number(h["dy"], where, "dy");
        if (std::abs(dx - dy) > 1e-9 * std::abs(dx))
            throw InputError(where + ": non-square cells (dx " + h["dx"] + ", dy " + h["dy"] +
                             ") are not supported");
        g.cell_size_m = dx;
    } else {
        throw InputError(where + ": header lacks cellsize");
    }
    if (h.count("xllcorner"))
        g.origin_x_m = parse_number(h["xllcorner"], where, "xllcorner");
    else if (h.count("xllcenter"))
        g.origin_x_m = parse_number(h["xllcenter"], where, "xllcenter") - 0.5 * g.cell_size_m;
    else
        throw InputError(where + ": header lacks xllcorner or xllcenter");
    if (h.count("yllcorner"))
        g.origin_y_m = parse_number(h["yllcorner"], where, "yllcorner");
    else if (h.count("yllcenter"))
        g.origin_y_m = parse_number(h["yllcenter"], where, "yllcenter") - 0.5 * g.cell_size_m;
    else
        throw InputError(where + ": header lacks yllcorner or yllcenter");
    const double nodata = h.count("nodata_value")
                              ? parse_number(h["nodata_value"], where, "nodata_value")
                              : kDefaultNodata;
    g.validate(where);
    ensure_fits_in_memory(g.size(), 16.0, where);
    RasterD z(g, 0.0);
    in.clear();
    in.seekg(data_start);
    std::string tok;
    for (int r = 0; r < g.ny; ++r) {
        const int j = g.ny - 1 - r; // first data row is the north edge
        for (int i = 0; i < g.nx; ++i) {
            if (!(in >> tok))
                throw InputError(where + ": data ends early at row " + std::to_string(r + 1) +
                                 ", column " + std::to_string(i + 1) + " (expected " +
                                 std::to_string(g.nx) + " x " + std::to_string(g.ny) + " values)");
            const double v = parse_number(
                tok, where, "row " + std::to_string(r + 1) + " column " + std::to_string(i + 1));
            z(i, j) = (v == nodata) ? std::nan("") : v;
        }
    }
    if (in >> tok)
        throw InputError(where + ": more values than ncols x nrows = " + std::to_string(g.size()));
    return z;
}

void write_esri_ascii(const RasterD& z, const std::filesystem::path& path) {
    ecoterra::io::AtomicOutput out(path);
    {
        std::FILE* f = std::fopen(out.temp_path().c_str(), "wb");
        if (!f) throw IoError(path.string() + ": cannot open for writing");
        std::fprintf(f,
                     "ncols %d\nnrows %d\nxllcorner %.10g\nyllcorner %.10g\ncellsize %.10g\n"
                     "NODATA_value %.10g\n",
                     z.nx(), z.ny(), z.grid().origin_x_m, z.grid().origin_y_m, z.cell_size(),
                     kDefaultNodata);
        for (int j = z.ny() - 1; j >= 0; --j) {
            for (int i = 0; i < z.nx(); ++i) {
                const double v = z(i, j);
                std::fprintf(f, i ? " %.9g" : "%.9g", std::isnan(v) ? kDefaultNodata : v);
            }
            std::fputc('\n', f);
        }
        const bool bad = std::ferror(f) != 0;
        if (std::fclose(f) != 0 || bad)
            throw IoError(path.string() + ": write failed (disk full?)");
    }
    out.commit();
}

} // namespace ecoterra::terrain::io
