#include "ecoterra/hydro/routing.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

namespace ecoterra::hydro {

namespace {
/// Freeman's exponent and Quinn's contour lengths (in cells) for MFD.
constexpr double kMfdExponent = 1.1;
constexpr double kContourEdge = 0.5;
constexpr double kContourDiagonal = 0.354;
} // namespace

Routing parse_routing(const std::string& s) {
    if (s == "d8") return Routing::d8;
    if (s == "mfd") return Routing::mfd;
    if (s == "d8-lowest") return Routing::d8_lowest;
    throw InputError("--routing must be d8, d8-lowest or mfd, got '" + s + "'");
}

std::string routing_name(Routing r) {
    switch (r) {
    case Routing::d8:
        return "d8";
    case Routing::mfd:
        return "mfd";
    case Routing::d8_lowest:
        return "d8-lowest";
    }
    return "?";
}

FlowDirections::FlowDirections(const RasterD& dem, D8Rule rule)
    : m_grid(dem.grid()), m_z(dem.data(), dem.data() + dem.size()),
      m_receiver(static_cast<std::size_t>(dem.size()), kNoReceiver),
      m_outlet(static_cast<std::size_t>(dem.size()), 0) {
    const int nx = m_grid.nx, ny = m_grid.ny;
    const double h = m_grid.cell_size_m;
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            const std::int64_t c = cell_index(m_grid, i, j);
            if (i == 0 || j == 0 || i == nx - 1 || j == ny - 1 || std::isnan(m_z[c])) {
                m_outlet[c] = 1;
                continue;
            }
            double best = 0.0;
            for (const auto& o : kMooreOffsets) {
                const std::int64_t n = cell_index(m_grid, i + o[0], j + o[1]);
                const double zn =
                    std::isnan(m_z[n]) ? -std::numeric_limits<double>::infinity() : m_z[n];
                const double d = rule == D8Rule::lowest     ? 1.0
                                 : (o[0] != 0 && o[1] != 0) ? h * std::numbers::sqrt2
                                                            : h;
                const double s = (m_z[c] - zn) / d;
                if (s > best) {
                    best = s;
                    m_receiver[c] = static_cast<std::int32_t>(n);
                }
            }
        }
}

std::int64_t FlowDirections::terminus(std::int64_t c) const {
    while (!is_outlet(c) && m_receiver[c] != kNoReceiver) c = m_receiver[c];
    return c;
}

int mfd_shares(const FlowDirections& fd, std::int64_t c,
               std::array<std::pair<std::int64_t, double>, 8>& shares) {
    const auto& g = fd.grid();
    const double h = g.cell_size_m;
    const int i = static_cast<int>(c % g.nx), j = static_cast<int>(c / g.nx);
    int count = 0;
    double sum = 0;
    for (const auto& o : kMooreOffsets) {
        if (!g.contains(i + o[0], j + o[1])) continue;
        const std::int64_t n = cell_index(g, i + o[0], j + o[1]);
        const double zn = fd.elevation(n);
        if (std::isnan(zn)) return 0;
        const double drop = fd.elevation(c) - zn;
        if (!(drop > 0)) continue;
        const bool diag = o[0] != 0 && o[1] != 0;
        const double slope = drop / (diag ? h * std::numbers::sqrt2 : h);
        const double w = std::pow(slope, kMfdExponent) * (diag ? kContourDiagonal : kContourEdge);
        shares[count++] = {n, w};
        sum += w;
    }
    for (int k = 0; k < count; ++k) shares[k].second /= sum;
    return count;
}

std::vector<std::int64_t> upstream_first_order(const RasterD& dem) {
    const auto& g = dem.grid();
    const double* z = dem.data();
    constexpr std::uint8_t kDone = 255;
    std::vector<std::uint8_t> higher(static_cast<std::size_t>(g.size()), 0);
    for (int j = 0; j < g.ny; ++j)
        for (int i = 0; i < g.nx; ++i)
            dem.for_moore(i, j, [&](int a, int b) {
                higher[cell_index(g, i, j)] += z[cell_index(g, a, b)] > z[cell_index(g, i, j)];
            });
    std::vector<std::int64_t> order, stack;
    order.reserve(static_cast<std::size_t>(g.size()));
    for (std::int64_t c = 0; c < g.size(); ++c) {
        if (higher[c] != 0) continue;
        higher[c] = kDone;
        stack.push_back(c);
        while (!stack.empty()) {
            const std::int64_t x = stack.back();
            stack.pop_back();
            order.push_back(x);
            const int i = static_cast<int>(x % g.nx), j = static_cast<int>(x / g.nx);
            dem.for_moore(i, j, [&](int a, int b) {
                const std::int64_t y = cell_index(g, a, b);
                if (z[y] < z[x] && --higher[y] == 0) {
                    higher[y] = kDone;
                    stack.push_back(y);
                }
            });
        }
    }
    return order;
}
RoutingParts split_by_basin(const FlowDirections& fd, const std::vector<std::int64_t>& order) {
    const auto cells = static_cast<std::size_t>(fd.size());
    if (order.size() != cells)
        throw Error("split_by_basin: the order holds " + std::to_string(order.size()) +
                    " cells of " + std::to_string(cells));
    // Each cell's basin (its pit or outlet): the order puts a cell before the cells below it, so
    // backwards a receiver's basin is known before its donors'.
    std::vector<std::int32_t> basin(cells, -1), size(cells, 0);
    for (auto it = order.rbegin(); it != order.rend(); ++it) {
        const std::int64_t k = *it;
        const std::int32_t r = fd.is_outlet(k) ? kNoReceiver : fd.receiver(k);
        basin[k] = r == kNoReceiver ? static_cast<std::int32_t>(k) : basin[r];
        ++size[static_cast<std::size_t>(basin[k])];
    }
    std::vector<std::int32_t> roots;
    for (std::size_t c = 0; c < cells; ++c)
        if (size[c] > 0) roots.push_back(static_cast<std::int32_t>(c));
    std::stable_sort(roots.begin(), roots.end(),
                     [&](std::int32_t a, std::int32_t b) { return size[a] > size[b]; });
    // The part of each basin, kept in `size` (reused): the largest first to the smaller part.
    std::array<std::int64_t, 2> load{0, 0};
    for (const std::int32_t b : roots) {
        const int part = load[1] < load[0] ? 1 : 0;
        load[part] += size[b];
        size[b] = part;
    }
    RoutingParts parts;
    for (int p = 0; p < 2; ++p) {
        parts.cell[p].reserve(static_cast<std::size_t>(load[p]));
        parts.pos[p].reserve(static_cast<std::size_t>(load[p]));
    }
    for (std::size_t i = 0; i < cells; ++i) {
        const std::int64_t k = order[i];
        const int p = size[static_cast<std::size_t>(basin[k])];
        parts.cell[p].push_back(static_cast<std::int32_t>(k));
        parts.pos[p].push_back(static_cast<std::uint32_t>(i));
    }
    return parts;
}

RoutedWater route_to_pits(const FlowDirections& fd, const std::vector<double>& volume,
                          Routing routing) {
    const auto& g = fd.grid();
    RoutedWater out;
    out.at_pit_m3.assign(static_cast<std::size_t>(g.size()), 0.0);
    if (routing != Routing::mfd) {
        for (std::int64_t c = 0; c < g.size(); ++c) {
            const double v = volume[c];
            if (!(v > 0)) continue;
            const std::int64_t t = fd.terminus(c);
            if (fd.is_outlet(t))
                out.lost_m3 += v;
            else
                out.at_pit_m3[t] += v;
        }
        return out;
    }
    // MFD: pass accumulated volume down in order of decreasing elevation.
    std::vector<std::int64_t> order(static_cast<std::size_t>(g.size()));
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](std::int64_t a, std::int64_t b) {
        const double za = fd.elevation(a), zb = fd.elevation(b);
        if (std::isnan(za) || std::isnan(zb)) return !std::isnan(za) && std::isnan(zb);
        return za > zb;
    });
    std::vector<double> acc(static_cast<std::size_t>(g.size()), 0.0);
    for (std::int64_t c = 0; c < g.size(); ++c) acc[c] = volume[c] > 0 ? volume[c] : 0.0;
    for (const std::int64_t c : order) {
        const double v = acc[c];
        if (v <= 0) continue;
        if (fd.is_outlet(c)) {
            out.lost_m3 += v;
            continue;
        }
        if (fd.is_pit(c)) {
            out.at_pit_m3[c] += v;
            continue;
        }
        std::array<std::pair<std::int64_t, double>, 8> shares;
        const int k = mfd_shares(fd, c, shares);
        if (k == 0) { // next to NODATA: an outlet, as in D8
            out.lost_m3 += v;
            continue;
        }
        for (int q = 0; q < k; ++q) acc[shares[q].first] += v * shares[q].second;
    }
    return out;
}

} // namespace ecoterra::hydro
