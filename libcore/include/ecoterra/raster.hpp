#pragma once
// The raster core every part of ecoterra stands on.
//
// Conventions (also in docs/formats.md):
// - A GridSpec is nx columns (x, east) by ny rows (y, north) of square cells of side
//   cell_size_m. (origin_x_m, origin_y_m) is the south-west corner of the grid, i.e. the lower-left
//   corner of cell (0, 0). Cell (i, j) has its centre at
//   (origin_x_m + (i + 0.5) * cell_size_m, origin_y_m + (j + 0.5) * cell_size_m).
// - Raster<T> stores rows south to north: row 0 is the southern edge. Storage is an Eigen row-major
//   array of shape (ny, nx), so a row is contiguous in memory.
// - NODATA is NaN for floating-point rasters.
#include "ecoterra/error.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

namespace ecoterra {

struct GridSpec {
    int nx = 0;               ///< columns (x, east)
    int ny = 0;               ///< rows (y, north)
    double cell_size_m = 1.0; ///< side of a square cell, m
    double origin_x_m = 0.0;  ///< x of the grid's south-west corner, m
    double origin_y_m = 0.0;  ///< y of the grid's south-west corner, m

    std::int64_t size() const { return static_cast<std::int64_t>(nx) * ny; }
    double width_m() const { return nx * cell_size_m; }
    double height_m() const { return ny * cell_size_m; }
    /// x of the centre of column i, m.
    double x_of(double i) const { return origin_x_m + (i + 0.5) * cell_size_m; }
    /// y of the centre of row j, m.
    double y_of(double j) const { return origin_y_m + (j + 0.5) * cell_size_m; }
    /// Continuous column coordinate of x (cell centres are at integers).
    double col_of(double x) const { return (x - origin_x_m) / cell_size_m - 0.5; }
    /// Continuous row coordinate of y (cell centres are at integers).
    double row_of(double y) const { return (y - origin_y_m) / cell_size_m - 0.5; }
    bool contains(int i, int j) const { return i >= 0 && j >= 0 && i < nx && j < ny; }
    /// True if (x, y) lies inside the grid's extent.
    bool contains_point(double x, double y) const {
        return x >= origin_x_m && y >= origin_y_m && x <= origin_x_m + width_m() &&
               y <= origin_y_m + height_m();
    }
    /// The cell holding (x, y), clamped into the grid (points on the far edges belong to the
    /// last row or column).
    std::array<int, 2> clamped_cell(double x, double y) const {
        const auto clamp = [](double v, int n) {
            return std::clamp(static_cast<int>(std::floor(v)), 0, n - 1);
        };
        return {clamp((x - origin_x_m) / cell_size_m, nx),
                clamp((y - origin_y_m) / cell_size_m, ny)};
    }
    bool operator==(const GridSpec& o) const = default;
    /// The same cells to a relative `tol` of the cell side (files store sides and origins with
    /// fewer digits than they were computed with).
    bool matches(const GridSpec& o, double tol = 1e-6) const {
        const double t = tol * cell_size_m;
        return nx == o.nx && ny == o.ny && std::abs(cell_size_m - o.cell_size_m) <= t &&
               std::abs(origin_x_m - o.origin_x_m) <= t * std::max(nx, 1) &&
               std::abs(origin_y_m - o.origin_y_m) <= t * std::max(ny, 1);
    }

    /// Throws InputError naming `what` if the grid is empty or its cell size is not positive.
    void validate(const std::string& what) const;
};

/// Calls f(i, j) for every cell of `g` whose centre lies within `radius` of (x, y).
template <class F>
void cells_within(const GridSpec& g, double x, double y, double radius, F&& f) {
    const int i0 = std::max(0, static_cast<int>(std::ceil(g.col_of(x - radius))));
    const int i1 = std::min(g.nx - 1, static_cast<int>(std::floor(g.col_of(x + radius))));
    const int j0 = std::max(0, static_cast<int>(std::ceil(g.row_of(y - radius))));
    const int j1 = std::min(g.ny - 1, static_cast<int>(std::floor(g.row_of(y + radius))));
    for (int j = j0; j <= j1; ++j)
        for (int i = i0; i <= i1; ++i)
            if (std::hypot(g.x_of(i) - x, g.y_of(j) - y) <= radius) f(i, j);
}

/// Refuses (InputError) before allocating `bytes_per_cell * cells` bytes if that is more than this
/// machine can hold (MemAvailable from /proc/meminfo, or 1 TiB when unknown), naming `what`.
void ensure_fits_in_memory(std::int64_t cells, double bytes_per_cell, const std::string& what);

/// Offsets of the 8 Moore neighbours (shared edge or vertex), edge neighbours first.
inline constexpr std::array<std::array<int, 2>, 8> kMooreOffsets{
    {{{1, 0}}, {{-1, 0}}, {{0, 1}}, {{0, -1}}, {{1, 1}}, {{-1, 1}}, {{1, -1}}, {{-1, -1}}}};
/// Offsets of the 4 von Neumann neighbours (shared edge).
inline constexpr std::array<std::array<int, 2>, 4> kVonNeumannOffsets{
    {{{1, 0}}, {{-1, 0}}, {{0, 1}}, {{0, -1}}}};

template <class T>
class Raster {
public:
    using Array = Eigen::Array<T, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

    Raster() = default;
    explicit Raster(const GridSpec& grid, T fill = T{}) : m_grid(grid) {
        grid.validate("raster grid");
        m_data.setConstant(grid.ny, grid.nx, fill);
    }
    Raster(const GridSpec& grid, Array data) : m_grid(grid), m_data(std::move(data)) {
        if (m_data.rows() != grid.ny || m_data.cols() != grid.nx)
            throw Error("raster data shape " + std::to_string(m_data.rows()) + "x" +
                        std::to_string(m_data.cols()) + " does not match grid " +
                        std::to_string(grid.ny) + "x" + std::to_string(grid.nx));
    }

    const GridSpec& grid() const { return m_grid; }
    /// The coordinate reference system of the grid's x and y as OGC WKT, empty when unknown (a
    /// generated terrain, a file without one). Carried from a GeoTIFF through run files to the
    /// GeoTIFFs ecoterra writes; crop() keeps it.
    const std::string& crs_wkt() const { return m_crs_wkt; }
    void set_crs_wkt(std::string wkt) { m_crs_wkt = std::move(wkt); }
    int nx() const { return m_grid.nx; }
    int ny() const { return m_grid.ny; }
    std::int64_t size() const { return m_grid.size(); }
    double cell_size() const { return m_grid.cell_size_m; }

    /// Value of column i, row j (row 0 = south).
    T& operator()(int i, int j) { return m_data(j, i); }
    const T& operator()(int i, int j) const { return m_data(j, i); }
    T* row(int j) { return m_data.data() + static_cast<std::int64_t>(j) * m_grid.nx; }
    const T* row(int j) const { return m_data.data() + static_cast<std::int64_t>(j) * m_grid.nx; }
    T* data() { return m_data.data(); }
    const T* data() const { return m_data.data(); }
    Array& array() { return m_data; }
    const Array& array() const { return m_data; }

    bool is_nodata(int i, int j) const {
        if constexpr (std::is_floating_point_v<T>) return std::isnan((*this)(i, j));
        return false;
    }

    /// A rectangular window (i0, j0, w, h) as an Eigen block; rows are still south to north.
    auto view(int i0, int j0, int w, int h) { return m_data.block(j0, i0, h, w); }
    auto view(int i0, int j0, int w, int h) const { return m_data.block(j0, i0, h, w); }
    /// The GridSpec of such a window.
    GridSpec view_grid(int i0, int j0, int w, int h) const {
        return GridSpec{w, h, m_grid.cell_size_m, m_grid.origin_x_m + i0 * m_grid.cell_size_m,
                        m_grid.origin_y_m + j0 * m_grid.cell_size_m};
    }
    /// A copy of a window as its own raster, georeferenced.
    Raster crop(int i0, int j0, int w, int h) const {
        if (i0 < 0 || j0 < 0 || w <= 0 || h <= 0 || i0 + w > nx() || j0 + h > ny())
            throw InputError("crop window outside the raster");
        Raster out(view_grid(i0, j0, w, h), Array(view(i0, j0, w, h)));
        out.m_crs_wkt = m_crs_wkt;
        return out;
    }

    /// Bilinear interpolation between cell centres at world point (x, y). Points between the
    /// outermost cell centres and the grid edge take the nearest edge values. NaN outside the
    /// grid or where any of the four cells is NODATA.
    double sample_bilinear(double x, double y) const {
        if (!m_grid.contains_point(x, y)) return std::numeric_limits<double>::quiet_NaN();
        const double fc = std::clamp(m_grid.col_of(x), 0.0, nx() - 1.0);
        const double fr = std::clamp(m_grid.row_of(y), 0.0, ny() - 1.0);
        const int i0 = std::min(static_cast<int>(fc), nx() - 2 < 0 ? 0 : nx() - 2);
        const int j0 = std::min(static_cast<int>(fr), ny() - 2 < 0 ? 0 : ny() - 2);
        const int i1 = std::min(i0 + 1, nx() - 1);
        const int j1 = std::min(j0 + 1, ny() - 1);
        const double tx = fc - i0;
        const double ty = fr - j0;
        const double v00 = (*this)(i0, j0), v10 = (*this)(i1, j0);
        const double v01 = (*this)(i0, j1), v11 = (*this)(i1, j1);
        return (1 - ty) * ((1 - tx) * v00 + tx * v10) + ty * ((1 - tx) * v01 + tx * v11);
    }

    /// The cell holding world point (x, y), or {-1, -1} outside.
    std::array<int, 2> cell_at(double x, double y) const {
        const int i = static_cast<int>(std::floor((x - m_grid.origin_x_m) / m_grid.cell_size_m));
        const int j = static_cast<int>(std::floor((y - m_grid.origin_y_m) / m_grid.cell_size_m));
        if (!m_grid.contains(i, j)) return {-1, -1};
        return {i, j};
    }

    /// Calls f(ni, nj) for each Moore neighbour of (i, j) inside the grid.
    template <class F>
    void for_moore(int i, int j, F&& f) const {
        for (const auto& o : kMooreOffsets)
            if (m_grid.contains(i + o[0], j + o[1])) f(i + o[0], j + o[1]);
    }
    /// Calls f(ni, nj) for each von Neumann neighbour of (i, j) inside the grid.
    template <class F>
    void for_von_neumann(int i, int j, F&& f) const {
        for (const auto& o : kVonNeumannOffsets)
            if (m_grid.contains(i + o[0], j + o[1])) f(i + o[0], j + o[1]);
    }

private:
    GridSpec m_grid;
    Array m_data;
    std::string m_crs_wkt;
};

using RasterD = Raster<double>;
using RasterF = Raster<float>;
using RasterU8 = Raster<std::uint8_t>;

/// Summary statistics over the valid (non-NaN) cells.
struct RasterStats {
    std::int64_t valid = 0;
    double min = std::numeric_limits<double>::quiet_NaN();
    double max = std::numeric_limits<double>::quiet_NaN();
    double mean = std::numeric_limits<double>::quiet_NaN();
    double stddev = std::numeric_limits<double>::quiet_NaN();
};
RasterStats stats(const RasterD& r);

/// Throws InputError naming `what` if the raster has no valid cell.
void require_valid_cells(const RasterD& r, const std::string& what);

} // namespace ecoterra
