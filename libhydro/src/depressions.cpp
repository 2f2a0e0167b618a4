#include "ecoterra/hydro/depressions.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <numeric>

namespace ecoterra::hydro {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr std::int32_t kUnknown = -2;

/// Elevation for passes: NODATA is -infinity (the ocean).
double pass_z(double z) {
    return std::isnan(z) ? -kInf : z;
}

struct UnionFind {
    std::vector<std::int32_t> up;
    explicit UnionFind(std::int32_t n) : up(static_cast<std::size_t>(n)) {
        std::iota(up.begin(), up.end(), 0);
    }
    std::int32_t find(std::int32_t x) {
        while (up[x] != x) x = up[x] = up[up[x]];
        return x;
    }
};
} // namespace

DepressionHierarchy::DepressionHierarchy(const FlowDirections& fd) {
    find_leaves(fd);
    label_cells(fd);
    join_over_passes(fd, lowest_passes(fd));
    assign_bands(fd);
    subtree_totals();
}

void DepressionHierarchy::find_leaves(const FlowDirections& fd) {
    const auto& g = fd.grid();
    const std::int64_t n_cells = g.size();
    m_leaf.assign(static_cast<std::size_t>(n_cells), kUnknown);

    std::vector<std::int64_t> queue;
    m_pit_begin.push_back(0);
    for (std::int64_t c = 0; c < n_cells; ++c) {
        if (fd.is_outlet(c)) {
            m_leaf[c] = -1;
            continue;
        }
        if (!fd.is_pit(c) || m_leaf[c] != kUnknown) continue;
        const std::int32_t id = m_leaves++;
        const double z = fd.elevation(c);
        queue.assign(1, c);
        m_leaf[c] = id;
        for (std::size_t q = 0; q < queue.size(); ++q) {
            const std::int64_t x = queue[q];
            m_pits.push_back(x);
            const int i = static_cast<int>(x % g.nx), j = static_cast<int>(x / g.nx);
            for (const auto& o : kMooreOffsets) {
                if (!g.contains(i + o[0], j + o[1])) continue;
                const std::int64_t y = cell_index(g, i + o[0], j + o[1]);
                if (m_leaf[y] == kUnknown && fd.is_pit(y) && fd.elevation(y) == z) {
                    m_leaf[y] = id;
                    queue.push_back(y);
                }
            }
        }
        m_pit_begin.push_back(static_cast<std::int64_t>(m_pits.size()));
    }
}

void DepressionHierarchy::label_cells(const FlowDirections& fd) {
    const std::int64_t n_cells = fd.grid().size();
    std::vector<std::int64_t> path;
    for (std::int64_t c = 0; c < n_cells; ++c) {
        std::int64_t x = c;
        while (m_leaf[x] == kUnknown) {
            path.push_back(x);
            x = fd.receiver(x);
        }
        for (const auto p : path) m_leaf[p] = m_leaf[x];
        path.clear();
    }
}

std::vector<DepressionHierarchy::Pass>
DepressionHierarchy::lowest_passes(const FlowDirections& fd) const {
    const auto& g = fd.grid();
    const std::int32_t ocean = m_leaves;
    std::vector<std::vector<std::pair<std::int32_t, double>>> adj(
        static_cast<std::size_t>(m_leaves));
    constexpr int kForward[4][2] = {{1, 0}, {-1, 1}, {0, 1}, {1, 1}};
    for (int j = 0; j < g.ny; ++j)
        for (int i = 0; i < g.nx; ++i) {
            const std::int64_t c = cell_index(g, i, j);
            const std::int32_t lc = m_leaf[c] < 0 ? ocean : m_leaf[c];
            for (const auto& o : kForward) {
                if (!g.contains(i + o[0], j + o[1])) continue;
                const std::int64_t y = cell_index(g, i + o[0], j + o[1]);
                const std::int32_t ly = m_leaf[y] < 0 ? ocean : m_leaf[y];
                if (lc == ly) continue;
                const double z = std::max(pass_z(fd.elevation(c)), pass_z(fd.elevation(y)));
                const std::int32_t a = std::min(lc, ly), b = std::max(lc, ly);
                auto& list = adj[a];
                auto it = std::find_if(list.begin(), list.end(),
                                       [b](const auto& e) { return e.first == b; });
                if (it == list.end())
                    list.emplace_back(b, z);
                else
                    it->second = std::min(it->second, z);
            }
        }
    std::vector<Pass> passes;
    for (std::int32_t a = 0; a < m_leaves; ++a)
        for (const auto& [b, z] : adj[a]) passes.push_back({z, a, b});
    std::sort(passes.begin(), passes.end());
    return passes;
}

void DepressionHierarchy::join_over_passes(const FlowDirections& fd,
                                           const std::vector<Pass>& passes) {
    const std::int32_t ocean = m_leaves; // the ocean is label L
    const std::size_t max_nodes = 2 * static_cast<std::size_t>(m_leaves);
    m_parent.reserve(max_nodes);
    m_parent.assign(static_cast<std::size_t>(m_leaves), -1);
    m_child.assign(2 * static_cast<std::size_t>(m_leaves), -1);
    m_odep.assign(static_cast<std::size_t>(m_leaves), -1);
    m_outlet.assign(static_cast<std::size_t>(m_leaves), kInf);
    m_minz.resize(static_cast<std::size_t>(m_leaves));
    for (std::int32_t l = 0; l < m_leaves; ++l) m_minz[l] = fd.elevation(m_pits[m_pit_begin[l]]);
    UnionFind uf(m_leaves + 1);
    std::vector<std::int32_t> top(static_cast<std::size_t>(m_leaves) + 1);
    std::iota(top.begin(), top.end(), 0);
    for (const Pass& p : passes) {
        const std::int32_t ra = uf.find(p.a), rb = uf.find(p.b);
        if (ra == rb) continue;
        const std::int32_t ro = uf.find(ocean);
        if (ra == ro || rb == ro) {
            // The depression meets the set that drains to the edge: no parent. Its overflow runs
            // over the pass into the leaf on the far side (which fills and spills on towards the
            // edge over lower passes), or off the domain when that side is the edge itself.
            const std::int32_t land = ra == ro ? rb : ra;
            const std::int32_t far = ra == ro ? p.a : p.b;
            m_outlet[top[land]] = p.z;
            m_odep[top[land]] = far == ocean ? -1 : far;
            uf.up[land] = ro;
            continue;
        }
        const std::int32_t ta = top[ra], tb = top[rb];
        const auto node = static_cast<std::int32_t>(m_parent.size());
        m_parent.push_back(-1);
        m_child.push_back(ta);
        m_child.push_back(tb);
        m_odep.push_back(-1);
        m_outlet.push_back(kInf);
        m_minz.push_back(std::min(m_minz[ta], m_minz[tb]));
        m_parent[ta] = m_parent[tb] = node;
        m_outlet[ta] = m_outlet[tb] = p.z;
        m_odep[ta] = p.b; // the leaf on the far side of the pass
        m_odep[tb] = p.a;
        uf.up[rb] = ra;
        top[ra] = node;
    }
}

void DepressionHierarchy::assign_bands(const FlowDirections& fd) {
    const std::int64_t n_cells = fd.grid().size();
    const auto n_nodes = static_cast<std::int32_t>(m_parent.size());
    const int levels =
        std::max(1, static_cast<int>(std::bit_width(static_cast<unsigned>(n_nodes))));
    std::vector<std::vector<std::int32_t>> up(static_cast<std::size_t>(levels));
    up[0] = m_parent;
    for (int k = 1; k < levels; ++k) {
        up[k].resize(static_cast<std::size_t>(n_nodes));
        for (std::int32_t n = 0; n < n_nodes; ++n)
            up[k][n] = up[k - 1][n] < 0 ? -1 : up[k - 1][up[k - 1][n]];
    }
    m_node.assign(static_cast<std::size_t>(n_cells), -1);
    m_own_n.assign(static_cast<std::size_t>(n_nodes), 0);
    m_own_z.assign(static_cast<std::size_t>(n_nodes), 0.0);
    for (std::int64_t c = 0; c < n_cells; ++c) {
        std::int32_t x = m_leaf[c];
        if (x < 0) continue;
        const double z = fd.elevation(c);
        if (!(z < m_outlet[x])) {
            for (int k = levels - 1; k >= 0; --k) {
                const std::int32_t y = up[k][x];
                if (y >= 0 && m_outlet[y] <= z) x = y;
            }
            x = m_parent[x];
            if (x < 0) continue;
        }
        m_node[c] = x;
        ++m_own_n[x];
        m_own_z[x] += z;
    }
    m_band_begin.assign(static_cast<std::size_t>(n_nodes) + 1, 0);
    for (std::int32_t n = 0; n < n_nodes; ++n) m_band_begin[n + 1] = m_band_begin[n] + m_own_n[n];
    m_band_cells.resize(static_cast<std::size_t>(m_band_begin[n_nodes]));
    {
        std::vector<std::int64_t> fill(m_band_begin.begin(), m_band_begin.end() - 1);
        for (std::int64_t c = 0; c < n_cells; ++c)
            if (m_node[c] >= 0) m_band_cells[fill[m_node[c]]++] = c;
    }
    m_band_z.resize(m_band_cells.size());
    m_band_prefix.resize(m_band_cells.size());
    // Every band in rising elevation, ties by cell index, with running sums: one canonical order,
    // whatever the history of the run (the daily update walks wet cells in this order, so a
    // resumed run must see the same order as an unbroken one).
#pragma omp parallel for schedule(dynamic, 64)
    for (std::int32_t n = 0; n < n_nodes; ++n) sort_band(n, fd);
}

void DepressionHierarchy::subtree_totals() {
    const auto n_nodes = static_cast<std::int32_t>(m_parent.size());
    m_cum_n = m_own_n;
    m_cum_z = m_own_z;
    m_capacity.resize(static_cast<std::size_t>(n_nodes));
    for (std::int32_t n = 0; n < n_nodes; ++n) {
        if (!is_leaf(n))
            for (int k = 0; k < 2; ++k) {
                m_cum_n[n] += m_cum_n[m_child[2 * n + k]];
                m_cum_z[n] += m_cum_z[m_child[2 * n + k]];
            }
        m_capacity[n] = std::isfinite(m_outlet[n])
                            ? m_outlet[n] * static_cast<double>(m_cum_n[n]) - m_cum_z[n]
                            : kInf;
    }
}

double DepressionHierarchy::base_z(std::int32_t n) const {
    return is_leaf(n) ? -kInf : m_outlet[m_child[2 * n]];
}

double DepressionHierarchy::base_capacity(std::int32_t n) const {
    return is_leaf(n) ? 0.0 : m_capacity[m_child[2 * n]] + m_capacity[m_child[2 * n + 1]];
}

std::span<const std::int64_t> DepressionHierarchy::pits(std::int32_t leaf) const {
    return {m_pits.data() + m_pit_begin[leaf],
            static_cast<std::size_t>(m_pit_begin[leaf + 1] - m_pit_begin[leaf])};
}

std::span<const std::int64_t> DepressionHierarchy::band(std::int32_t n) const {
    return {m_band_cells.data() + m_band_begin[n],
            static_cast<std::size_t>(m_band_begin[n + 1] - m_band_begin[n])};
}

void DepressionHierarchy::sort_band(std::int32_t n, const FlowDirections& fd) {
    const std::int64_t b = m_band_begin[n], e = m_band_begin[n + 1];
    std::vector<std::pair<double, std::int64_t>> v;
    v.reserve(static_cast<std::size_t>(e - b));
    for (std::int64_t k = b; k < e; ++k)
        v.emplace_back(fd.elevation(m_band_cells[k]), m_band_cells[k]);
    std::sort(v.begin(), v.end());
    double sum = 0;
    for (std::int64_t k = b; k < e; ++k) {
        m_band_cells[k] = v[k - b].second;
        m_band_z[k] = v[k - b].first;
        sum += v[k - b].first;
        m_band_prefix[k] = sum;
    }
}

DepressionHierarchy::Level DepressionHierarchy::level_for(std::int32_t n, double volume) const {
    const std::int64_t b = m_band_begin[n], m = m_own_n[n];
    const double nd = static_cast<double>(m_cum_n[n] - m), zd = m_cum_z[n] - m_own_z[n];
    auto prefix = [&](std::int64_t k) { return k == 0 ? 0.0 : m_band_prefix[b + k - 1]; };
    // First k whose level z_k needs at least `volume`.
    std::int64_t lo = 0, hi = m;
    while (lo < hi) {
        const std::int64_t mid = (lo + hi) / 2;
        const double need = (nd + static_cast<double>(mid)) * m_band_z[b + mid] - zd - prefix(mid);
        if (need >= volume)
            hi = mid;
        else
            lo = mid + 1;
    }
    Level out;
    out.own_wet = lo;
    const double wet = nd + static_cast<double>(lo);
    out.level_m = wet > 0 ? (volume + zd + prefix(lo)) / wet : m_minz[n];
    return out;
}

double DepressionHierarchy::volume_below(std::int32_t n, double h) const {
    if (!(h > m_minz[n])) return 0.0;
    if (!is_leaf(n) && h < base_z(n))
        return volume_below(m_child[2 * n], h) + volume_below(m_child[2 * n + 1], h);
    const std::int64_t b = m_band_begin[n], m = m_own_n[n];
    const auto k = static_cast<std::int64_t>(
        std::lower_bound(m_band_z.begin() + b, m_band_z.begin() + b + m, h) -
        (m_band_z.begin() + b));
    const double nd = static_cast<double>(m_cum_n[n] - m), zd = m_cum_z[n] - m_own_z[n];
    return (nd + static_cast<double>(k)) * h - zd - (k == 0 ? 0.0 : m_band_prefix[b + k - 1]);
}

} // namespace ecoterra::hydro
