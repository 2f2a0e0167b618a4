#include "ecoterra/raster.hpp"

#include <fstream>
#include <sstream>

namespace ecoterra {

namespace {
std::string fmt(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
}

/// MemAvailable from /proc/meminfo in bytes, or a large value where it cannot be read.
double available_memory_bytes() {
    std::ifstream in("/proc/meminfo");
    std::string key;
    double value = 0;
    std::string unit;
    while (in >> key >> value >> unit)
        if (key == "MemAvailable:") return value * 1024.0;
    return 1024.0 * 1024.0 * 1024.0 * 1024.0;
}
} // namespace

void GridSpec::validate(const std::string& what) const {
    if (nx <= 0 || ny <= 0)
        throw InputError(what + ": grid size must be positive, got nx=" + std::to_string(nx) +
                         " ny=" + std::to_string(ny));
    if (!(cell_size_m > 0.0) || !std::isfinite(cell_size_m))
        throw InputError(what + ": cell size must be positive, got " + fmt(cell_size_m) + " m");
    if (!std::isfinite(origin_x_m) || !std::isfinite(origin_y_m))
        throw InputError(what + ": grid origin must be finite");
}

void ensure_fits_in_memory(std::int64_t cells, double bytes_per_cell, const std::string& what) {
    const double need = static_cast<double>(cells) * bytes_per_cell;
    const double have = available_memory_bytes();
    // Leave a quarter of what is free for everything else.
    if (need > 0.75 * have)
        throw InputError(what + ": needs about " + fmt(need / (1u << 30)) + " GiB for " +
                         std::to_string(cells) + " cells, but only " + fmt(have / (1u << 30)) +
                         " GiB of memory is available");
}

RasterStats stats(const RasterD& r) {
    RasterStats s;
    double sum = 0.0;
    double mn = std::numeric_limits<double>::infinity();
    double mx = -mn;
    const double* d = r.data();
    for (std::int64_t k = 0; k < r.size(); ++k) {
        if (std::isnan(d[k])) continue;
        ++s.valid;
        sum += d[k];
        mn = std::min(mn, d[k]);
        mx = std::max(mx, d[k]);
    }
    if (s.valid == 0) return s;
    s.min = mn;
    s.max = mx;
    s.mean = sum / static_cast<double>(s.valid);
    double ss = 0.0;
    for (std::int64_t k = 0; k < r.size(); ++k)
        if (!std::isnan(d[k])) ss += (d[k] - s.mean) * (d[k] - s.mean);
    s.stddev = std::sqrt(ss / static_cast<double>(s.valid));
    return s;
}

void require_valid_cells(const RasterD& r, const std::string& what) {
    bool any = false;
    for (std::int64_t k = 0; k < r.size(); ++k) {
        const double v = r.data()[k];
        if (std::isinf(v)) {
            const auto& g = r.grid();
            throw InputError(
                what + ": cell (" + std::to_string(k % g.nx) + ", " + std::to_string(k / g.nx) +
                ") holds " + (v > 0 ? "+inf" : "-inf") +
                "; elevations must be finite (NODATA is NaN or the file's nodata value)");
        }
        any = any || !std::isnan(v);
    }
    if (!any) throw InputError(what + ": the raster holds no valid cell (all NODATA)");
}

} // namespace ecoterra
