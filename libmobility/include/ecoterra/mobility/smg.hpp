#pragma once
// Speed made good along a straight A-to-B line through a stand (docs/mobility.md s4), NRMM-style:
// stems thinner than the critical diameter are overridden, the forces of those in each
// vehicle-width cell ahead adding up; thicker stems, and the stems of a cell whose cluster force
// the thrust cannot overcome, are avoided on the shortest collision-free path (stems inflated by
// half the vehicle width); the vehicle drives that path at the steady-state speed of each cell.
// SMG = straight-line length / time; a line with no path, or with a cell the vehicle cannot
// climb, is NOGO (SMG 0).
#include "ecoterra/mobility/vehicle.hpp"
#include "ecoterra/raster.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace ecoterra::mobility {

struct Stem {
    double x_m = 0, y_m = 0;
    double diameter_m = 0; ///< at the vehicle's push height
    bool rigid = false;    ///< an object (a roadblock): never pushed over, always avoided
};

struct Point {
    double x_m = 0, y_m = 0;
};

struct LineResult {
    double straight_m = 0; ///< |B - A|
    double path_m = 0;     ///< length of the path driven
    double time_s = 0;
    double smg_m_per_s = 0;
    bool nogo = false;
    std::string nogo_reason;
    double override_m = 0;                    ///< path length with a stem force to push
    std::int64_t overridden = 0, avoided = 0; ///< stems pushed over, stems avoided
    std::vector<Point> path;                  ///< the path driven, A to B (empty when NOGO)
    std::vector<std::int64_t> pushed_stems;   ///< indices (in the StemIndex) of stems pushed over
};

struct SmgOptions {
    /// Resolution of the planning grid, as a fraction of the vehicle width.
    double grid_fraction_of_width = 0.125;
    /// The planning area reaches this far beyond the line's bounding box, m (a detour wider than
    /// it counts as no path).
    double margin_m = 25;
    /// When set, the planning area is also kept inside [x0, x1] x [y0, y1] (the terrain), m.
    std::optional<std::array<double, 4>> bounds_m;
};

/// Stems in buckets of a fixed size, for queries by rectangle and disk.
class StemIndex {
public:
    StemIndex(std::vector<Stem> stems, double bucket_m);
    const std::vector<Stem>& stems() const { return m_stems; }
    /// The largest diameter of the stems, m (0 without stems).
    double max_diameter_m() const { return m_max_d; }
    /// Calls f(k) for every stem k within the axis-aligned box [x0, x1] x [y0, y1].
    template <class F>
    void for_each_in_box(double x0, double y0, double x1, double y1, F&& f) const {
        const int i0 = bucket(x0, m_x0), i1 = bucket(x1, m_x0);
        const int j0 = bucket(y0, m_y0), j1 = bucket(y1, m_y0);
        for (int j = std::max(j0, 0); j <= std::min(j1, m_ny - 1); ++j)
            for (int i = std::max(i0, 0); i <= std::min(i1, m_nx - 1); ++i)
                for (const std::int64_t k : m_buckets[static_cast<std::size_t>(j) * m_nx + i]) {
                    const Stem& s = m_stems[static_cast<std::size_t>(k)];
                    if (s.x_m >= x0 && s.x_m <= x1 && s.y_m >= y0 && s.y_m <= y1) f(k);
                }
    }

private:
    int bucket(double v, double origin) const {
        return static_cast<int>(std::floor((v - origin) / m_size));
    }
    std::vector<Stem> m_stems;
    double m_size = 1, m_x0 = 0, m_y0 = 0, m_max_d = 0;
    int m_nx = 0, m_ny = 0;
    std::vector<std::vector<std::int64_t>> m_buckets;
};

/// Time to drive cells of lengths `len_m` (m) whose boundaries (one more than cells) may be
/// passed at most at `node_cap_m_per_s`, speeding up at `acc` and braking at `dec` (m/s2) between
/// them: the speed profile of the forward and backward passes, with v^2 linear in distance in
/// each cell, t = 2 len / (u_in + u_out).
double profile_time_s(const std::vector<double>& len_m, std::vector<double> node_cap_m_per_s,
                      double acc, double dec);

/// Drives from `a` to `b` through the stems of `index` over `dem` (nullptr: flat ground).
LineResult drive_line(const Vehicle& v, const StemIndex& index, const RasterD* dem, Point a,
                      Point b, const SmgOptions& opt = {});

} // namespace ecoterra::mobility
