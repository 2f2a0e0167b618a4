#include "ecoterra/mobility/route.hpp"

#include "ecoterra/error.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <queue>

namespace ecoterra::mobility {

namespace {
/// The eight moves, clockwise from north: (di, dj) and their compass heading.
constexpr std::array<std::array<int, 2>, 8> kMoves{
    {{0, 1}, {1, 1}, {1, 0}, {1, -1}, {0, -1}, {-1, -1}, {-1, 0}, {-1, 1}}};
} // namespace

Route fastest_route(const std::vector<RasterD>& speed, const std::vector<double>& headings_deg,
                    Point from, Point to) {
    if (speed.empty() || speed.size() != headings_deg.size())
        throw InputError("route: the map has no speed layers");
    const GridSpec& g = speed.front().grid();
    // The layer of each move's heading.
    std::array<const RasterD*, 8> layer{};
    for (int m = 0; m < 8; ++m) {
        for (std::size_t h = 0; h < headings_deg.size(); ++h)
            if (std::abs(std::remainder(headings_deg[h] - 45.0 * m, 360.0)) < 1e-6)
                layer[static_cast<std::size_t>(m)] = &speed[h];
        if (!layer[static_cast<std::size_t>(m)])
            throw InputError("route: the map has no speed layer for heading " +
                             format_number(45.0 * m) +
                             " deg (a route needs the 8 neighbour "
                             "directions: map with --headings 8 or a multiple of it)");
    }
    auto cell_of = [&](Point p, const char* what) {
        if (!g.contains_point(p.x_m, p.y_m))
            throw InputError(
                std::string("route: ") + what + " (" + format_number(p.x_m) + ", " +
                format_number(p.y_m) + ") is off the map [" + format_number(g.origin_x_m) + ", " +
                format_number(g.origin_x_m + g.width_m()) + "] x [" + format_number(g.origin_y_m) +
                ", " + format_number(g.origin_y_m + g.height_m()) + "] m");
        return g.clamped_cell(p.x_m, p.y_m);
    };
    const auto [i0, j0] = cell_of(from, "--from");
    const auto [i1, j1] = cell_of(to, "--to");
    const std::int64_t n = g.size(), start = std::int64_t{j0} * g.nx + i0,
                       goal = std::int64_t{j1} * g.nx + i1;
    std::vector<double> best(static_cast<std::size_t>(n), std::numeric_limits<double>::infinity());
    std::vector<std::int64_t> prev(static_cast<std::size_t>(n), -1);
    using Item = std::pair<double, std::int64_t>; // time, cell (ties: the lower cell first)
    std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
    best[static_cast<std::size_t>(start)] = 0;
    open.push({0.0, start});
    while (!open.empty()) {
        const auto [t, c] = open.top();
        open.pop();
        if (t > best[static_cast<std::size_t>(c)]) continue;
        if (c == goal) break;
        const int i = static_cast<int>(c % g.nx), j = static_cast<int>(c / g.nx);
        for (int m = 0; m < 8; ++m) {
            const int ii = i + kMoves[static_cast<std::size_t>(m)][0];
            const int jj = j + kMoves[static_cast<std::size_t>(m)][1];
            if (!g.contains(ii, jj)) continue;
            const RasterD& sp = *layer[static_cast<std::size_t>(m)];
            const double va = sp(i, j), vb = sp(ii, jj);
            if (!(va > 0) || !(vb > 0)) continue;
            const double step = (m % 2 ? std::sqrt(2.0) : 1.0) * g.cell_size_m;
            const double tt = t + 0.5 * step / va + 0.5 * step / vb;
            const std::int64_t d = std::int64_t{jj} * g.nx + ii;
            if (tt < best[static_cast<std::size_t>(d)]) {
                best[static_cast<std::size_t>(d)] = tt;
                prev[static_cast<std::size_t>(d)] = c;
                open.push({tt, d});
            }
        }
    }
    Route r;
    r.straight_m = std::hypot(g.x_of(i1) - g.x_of(i0), g.y_of(j1) - g.y_of(j0));
    if (!std::isfinite(best[static_cast<std::size_t>(goal)])) return r;
    r.found = true;
    r.time_s = best[static_cast<std::size_t>(goal)];
    for (std::int64_t c = goal; c >= 0; c = prev[static_cast<std::size_t>(c)]) {
        r.path.push_back(
            {g.x_of(static_cast<double>(c % g.nx)), g.y_of(static_cast<double>(c / g.nx))});
        if (c == start) break;
    }
    std::reverse(r.path.begin(), r.path.end());
    for (std::size_t k = 1; k < r.path.size(); ++k)
        r.length_m +=
            std::hypot(r.path[k].x_m - r.path[k - 1].x_m, r.path[k].y_m - r.path[k - 1].y_m);
    return r;
}

} // namespace ecoterra::mobility
