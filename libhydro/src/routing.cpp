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
