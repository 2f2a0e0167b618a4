#include "ecoterra/hydro/catchments.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ecoterra::hydro {

namespace {
/// Safety limit on catchment updates in one equilibrium, per node of the hierarchy (plus a few
/// nodes' worth, kMinUpdateNodes, for tiny hierarchies).
constexpr std::int64_t kMaxUpdatesPerNode = 64;
constexpr std::int64_t kMinUpdateNodes = 16;
/// Volumes within this of a threshold (m3) count as at it: an absolute part for small bodies and
/// a relative part for the rounding of large sums.
constexpr double kAbsoluteVolumeTolerance_m3 = 1e-12;
constexpr double kRelativeVolumeTolerance = 1e-13;
double tolerance_m3(double reference_m3) {
    return kAbsoluteVolumeTolerance_m3 + kRelativeVolumeTolerance * std::abs(reference_m3);
}
} // namespace

Catchments::Catchments(const RasterD& dem, D8Rule rule)
    : m_dem(dem), m_fd(dem, rule), m_dh(m_fd), m_area(dem.cell_size() * dem.cell_size()),
      m_pos(static_cast<std::size_t>(m_dh.node_count()), -1),
      m_cover(static_cast<std::size_t>(m_dh.node_count()), 0),
      m_owner(static_cast<std::size_t>(dem.size()), 0) {}

Catchment& Catchments::create(std::int32_t node, double volume_m3) {
    Catchment k;
    k.id = node + 1;
    k.node = node;
    k.volume_m3 = volume_m3;
    k.level_m = m_dh.min_z(node);
    m_pos[node] = static_cast<std::int32_t>(m_list.size());
    m_list.push_back(std::move(k));
    return m_list.back();
}

void Catchments::remove(std::int32_t node) {
    const std::int32_t p = m_pos[node];
    const std::int32_t last = static_cast<std::int32_t>(m_list.size()) - 1;
    if (p != last) {
        m_list[p] = std::move(m_list[last]);
        m_pos[m_list[p].node] = p;
    }
    m_list.pop_back();
    m_pos[node] = -1;
}

void Catchments::add_to_leaf(std::int32_t leaf, double v) {
    if (const std::int32_t id = m_cover[leaf]) {
        Catchment& k = at(id - 1);
        k.volume_m3 += v;
        k.dirty = true;
        return;
    }
    create(leaf, v);
    m_cover[leaf] = leaf + 1;
}

void Catchments::add_to_pit(std::int64_t pit, double v) {
    if (!(v > 0)) return;
    const std::int32_t leaf = m_dh.leaf_of(pit);
    if (leaf < 0) {
        m_lost_m3 += v;
        return;
    }
    add_to_leaf(leaf, v);
}

void Catchments::add_water(std::int64_t cell, double v) {
    if (!(v > 0)) return;
    if (const std::int32_t o = owner(cell)) {
        Catchment& k = at(o - 1);
        k.volume_m3 += v;
        k.dirty = true;
        return;
    }
    add_to_pit(cell, v);
}

void Catchments::add_routed(const RoutedWater& r) {
    m_lost_m3 += r.lost_m3;
    for (std::int64_t c = 0; c < static_cast<std::int64_t>(r.at_pit_m3.size()); ++c)
        if (r.at_pit_m3[c] > 0) add_to_pit(c, r.at_pit_m3[c]);
}

Catchments pond(const RasterD& dem, double depth_m, Routing routing) {
    if (!(depth_m >= 0) || !std::isfinite(depth_m))
        throw InputError("--depth-m must be >= 0 m, got " + std::to_string(depth_m));
    Catchments c(dem, d8_rule(routing));
    const double area = dem.cell_size() * dem.cell_size();
    std::vector<double> v(static_cast<std::size_t>(dem.size()));
    for (std::int64_t k = 0; k < dem.size(); ++k)
        v[k] = std::isnan(dem.data()[k]) ? 0.0 : depth_m * area;
    c.add_routed(route_to_pits(c.flow(), v, routing));
    c.equilibrate();
    return c;
}

Catchment* Catchments::find(std::int32_t id) {
    if (id <= 0 || id > m_dh.node_count() || m_pos[id - 1] < 0) return nullptr;
    return &at(id - 1);
}

void Catchments::add_water_to(std::int32_t id, double v) {
    Catchment* k = find(id);
    if (!k || !(v > 0)) return;
    k->volume_m3 += v;
    k->dirty = true;
}

double Catchments::remove_water(std::int32_t id, double v) {
    Catchment* k = find(id);
    if (!k || !(v > 0)) return 0.0;
    const double taken = std::min(v, k->volume_m3);
    if (taken <= 0) return 0.0;
    k->volume_m3 -= taken;
    k->dirty = true;
    return taken;
}

void Catchments::set_full(Catchment& k) {
    k.level_m = m_dh.outlet_z(k.node);
    k.own_wet = static_cast<std::int64_t>(m_dh.band(k.node).size());
}

void Catchments::split(std::int32_t node, std::vector<std::int32_t>& work) {
    const double vd = at(node).volume_m3 / m_area;
    remove(node);
    // The common level of the bodies under the saddle (bisection on the monotone volume).
    double lo = m_dh.min_z(node), hi = m_dh.base_z(node);
    for (int it = 0; it < 200; ++it) {
        const double mid = 0.5 * (lo + hi);
        if (!(mid > lo && mid < hi)) break;
        (m_dh.volume_below(node, mid) < vd ? lo : hi) = mid;
    }
    const double h = 0.5 * (lo + hi);
    // Each body (the highest nodes whose band holds h) keeps the water above its own cells.
    std::vector<std::pair<std::int32_t, double>> parts;
    std::vector<std::int32_t> stack{m_dh.child(node, 0), m_dh.child(node, 1)};
    while (!stack.empty()) {
        const std::int32_t x = stack.back();
        stack.pop_back();
        if (!(h > m_dh.min_z(x))) continue;
        if (m_dh.is_leaf(x) || h >= m_dh.base_z(x)) {
            parts.emplace_back(x, m_dh.volume_below(x, h));
        } else {
            stack.push_back(m_dh.child(x, 0));
            stack.push_back(m_dh.child(x, 1));
        }
    }
    if (parts.empty()) { // a film: give it to the lowest leaf
        std::int32_t x = node;
        while (!m_dh.is_leaf(x)) {
            const std::int32_t a = m_dh.child(x, 0), b = m_dh.child(x, 1);
            x = m_dh.min_z(a) <= m_dh.min_z(b) ? a : b;
        }
        parts.emplace_back(x, vd);
    }
    // Conservation: the rounding of the parts goes to the largest.
    double sum = 0;
    std::size_t largest = 0;
    for (std::size_t i = 0; i < parts.size(); ++i) {
        sum += parts[i].second;
        if (parts[i].second > parts[largest].second) largest = i;
    }
    parts[largest].second += vd - sum;
    for (const auto& [x, v] : parts) {
        if (!(v > 0)) continue;
        create(x, v * m_area);
        work.push_back(x);
    }
}

void Catchments::pour_into(std::int32_t leaf, std::int32_t stop, double v,
                           std::vector<std::int32_t>& work) {
    // The catchment on the far side: the one at or above the leaf, up to `stop` (the spilling
    // node's sibling) or the top of the leaf's tree (stop = -1). Catchments never nest, so the
    // first one met is the only one.
    std::int32_t x = leaf;
    while (x != stop && m_pos[x] < 0 && m_dh.parent(x) >= 0) x = m_dh.parent(x);
    if (m_pos[x] >= 0) {
        at(x).volume_m3 += v;
        work.push_back(x);
    } else {
        create(leaf, v);
        work.push_back(leaf);
    }
}

void Catchments::overflow(std::int32_t n, std::vector<std::int32_t>& work) {
    Catchment& k = at(n);
    const double cap = m_dh.capacity(n) * m_area;
    const std::int32_t parent = m_dh.parent(n);
    const std::int32_t t = m_dh.overflow_leaf(n);
    if (parent < 0) { // no saddle to merge over: spill past the pass
        const double excess = k.volume_m3 - cap;
        k.volume_m3 = cap;
        set_full(k);
        k.dynamic = t >= 0;
        if (t < 0)
            m_lost_m3 += excess; // straight off the domain
        else
            pour_into(t, -1, excess, work); // into a depression that drains to the edge
        return;
    }
    const std::int32_t s = m_dh.sibling(n);
    const double cap_s = m_dh.capacity(s) * m_area;
    const bool s_full = cap_s <= tolerance_m3(0.0) ||
                        (m_pos[s] >= 0 && at(s).volume_m3 >= cap_s - tolerance_m3(cap_s));
    if (s_full) { // both sides full to the saddle: one lake over it
        double v = k.volume_m3;
        remove(n);
        if (m_pos[s] >= 0) { // the usual case: one catchment fills the sibling
            v += at(s).volume_m3;
            remove(s);
        } else { // a sibling of no capacity: gather whatever lies under it
            m_dh.for_each_in_subtree(s, [&](std::int32_t x) {
                if (m_pos[x] < 0) return;
                v += at(x).volume_m3;
                remove(x);
            });
        }
        create(parent, v);
        work.push_back(parent);
        return;
    }
    const double excess = k.volume_m3 - cap;
    k.volume_m3 = cap;
    set_full(k);
    k.dynamic = true;
    pour_into(t, s, excess, work);
}

int Catchments::equilibrate() {
    std::vector<std::int32_t> work;
    for (const auto& k : m_list)
        if (k.dirty) work.push_back(k.node);
    std::reverse(work.begin(), work.end()); // the stack takes them in list order
    const std::int64_t limit = kMaxUpdatesPerNode * (m_dh.node_count() + kMinUpdateNodes);
    std::int64_t updates = 0;
    while (!work.empty()) {
        const std::int32_t n = work.back();
        work.pop_back();
        if (m_pos[n] < 0) continue;
        if (++updates > limit)
            throw Error("catchments: no equilibrium after " + std::to_string(limit) + " updates");
        Catchment& k = at(n);
        k.dirty = false;
        if (!(k.volume_m3 > 0)) {
            remove(n);
            continue;
        }
        const double cap = m_dh.capacity(n) * m_area;
        const std::int32_t parent = m_dh.parent(n);
        if (k.volume_m3 - cap > tolerance_m3(cap)) {
            overflow(n, work);
            continue;
        }
        const double base = m_dh.base_capacity(n) * m_area;
        if (base - k.volume_m3 > tolerance_m3(base)) {
            split(n, work);
            continue;
        }
        if (k.volume_m3 >= cap - tolerance_m3(cap)) {
            set_full(k);
            k.dynamic = parent >= 0 || m_dh.overflow_leaf(n) >= 0;
            continue;
        }
        const auto lv = m_dh.level_for(n, k.volume_m3 / m_area);
        k.level_m = std::min(lv.level_m, m_dh.outlet_z(n));
        k.own_wet = lv.own_wet;
        k.dynamic = true;
    }
    m_updates += updates;
    finish();
    return static_cast<int>(std::min<std::int64_t>(updates, std::numeric_limits<int>::max()));
}

void Catchments::finish() {
    std::sort(m_list.begin(), m_list.end(),
              [](const Catchment& a, const Catchment& b) { return a.id < b.id; });
    for (std::size_t p = 0; p < m_list.size(); ++p)
        m_pos[m_list[p].node] = static_cast<std::int32_t>(p);
    // Cover: parents have higher node numbers than their children, so one downward pass.
    for (std::int32_t n = m_dh.node_count() - 1; n >= 0; --n) {
        const std::int32_t p = m_dh.parent(n);
        m_cover[n] = m_pos[n] >= 0 ? n + 1 : (p >= 0 ? m_cover[p] : 0);
    }
    for (auto& k : m_list)
        k.wet_cells = m_dh.cells_below_outlet(k.node) -
                      static_cast<std::int64_t>(m_dh.band(k.node).size()) + k.own_wet;
    map_owners();
}

void Catchments::map_owners() {
    for (const auto c : m_owned) m_owner[static_cast<std::size_t>(c)] = 0;
    m_owned.clear();
    for (const auto& k : m_list) {
        // The nodes whose cover is this catchment: its own and those of its subtree not covered
        // by another. A band is in rising elevation, so its cells below the level come first.
        m_dh.for_each_in_subtree(k.node, [&](std::int32_t n) {
            if (m_cover[n] != k.node + 1) return;
            for (const auto c : m_dh.band(n)) {
                if (!(m_fd.elevation(c) < k.level_m)) break;
                m_owner[static_cast<std::size_t>(c)] = k.id;
                m_owned.push_back(c);
            }
        });
    }
}

std::vector<std::int64_t> Catchments::seeds(const Catchment& k) const {
    std::vector<std::int64_t> out;
    m_dh.for_each_in_subtree(k.node, [&](std::int32_t x) {
        if (m_dh.is_leaf(x))
            for (const auto p : m_dh.pits(x)) out.push_back(p);
    });
    std::sort(out.begin(), out.end());
    return out;
}

Raster<std::int32_t> Catchments::id_map() const {
    Raster<std::int32_t> m(m_dem.grid(), 0);
    std::copy(m_owner.begin(), m_owner.end(), m.data());
    return m;
}

RasterD Catchments::depth_map() const {
    RasterD d(m_dem.grid(), 0.0);
    for (const auto& k : m_list)
        for_each_wet_cell(
            k, [&](std::int64_t c) { d.data()[c] = std::max(0.0, k.level_m - m_fd.elevation(c)); });
    return d;
}

double Catchments::total_volume_m3() const {
    double v = 0;
    for (const auto& k : m_list) v += k.volume_m3;
    return v;
}

} // namespace ecoterra::hydro

namespace ecoterra::hydro {

void Catchments::save_state(ArchiveWriter& a) const {
    a.put<std::uint64_t>(m_list.size());
    for (const auto& k : m_list) {
        a.put(k.node);
        a.put(k.volume_m3);
        a.put(k.level_m);
        a.put(k.own_wet);
        a.put(k.dynamic);
        a.put(k.dirty);
    }
    a.put<std::int32_t>(m_dh.node_count());
    a.put(m_lost_m3);
    a.put(m_updates);
}

void Catchments::load_state(ArchiveReader& a) {
    const auto n = a.get<std::uint64_t>();
    std::vector<Catchment> list(n);
    for (auto& k : list) {
        k.node = a.get<std::int32_t>();
        k.id = k.node + 1;
        k.volume_m3 = a.get<double>();
        k.level_m = a.get<double>();
        k.own_wet = a.get<std::int64_t>();
        k.dynamic = a.get<bool>();
        k.dirty = a.get<bool>();
    }
    const auto nodes = a.get<std::int32_t>();
    if (nodes != m_dh.node_count())
        throw CheckpointError("catchment checkpoint: " + std::to_string(nodes) +
                              " depressions, the terrain has " + std::to_string(m_dh.node_count()));
    std::fill(m_pos.begin(), m_pos.end(), -1);
    for (const auto& k : list) {
        if (k.node < 0 || k.node >= nodes || m_pos[k.node] >= 0)
            throw CheckpointError("catchment checkpoint: bad depression " + std::to_string(k.node));
        m_pos[k.node] = 0;
    }
    m_list = std::move(list);
    m_lost_m3 = a.get<double>();
    m_updates = a.get<std::int64_t>();
    finish();
}

} // namespace ecoterra::hydro
