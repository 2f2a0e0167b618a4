#include "ecoterra/hydro/catchments.hpp"

#include <boost/graph/adjacency_list.hpp>
#include <boost/graph/breadth_first_search.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <queue>
#include <unordered_map>

namespace ecoterra::hydro {

namespace {
/// Volumes below this (m3) count as empty; spills below it are ignored.
constexpr double kVolumeEpsilon = 1e-12;
/// Safety limit on equilibrium passes.
constexpr int kMaxPasses = 1000000;
constexpr double kNegInf = -std::numeric_limits<double>::infinity();
} // namespace

Catchments::Catchments(const terrain::RasterD& dem)
    : m_dem(dem), m_fd(dem), m_area(dem.cell_size() * dem.cell_size()),
      m_owner(static_cast<std::size_t>(dem.size()), 0),
      m_seed_owner(static_cast<std::size_t>(dem.size()), 0), m_index(1, -1),
      m_stamp_queued(static_cast<std::size_t>(dem.size()), 0),
      m_stamp_region(static_cast<std::size_t>(dem.size()), 0) {}

Catchment* Catchments::find(std::int32_t id) {
    if (id <= 0 || id >= static_cast<std::int32_t>(m_index.size()) || m_index[id] < 0)
        return nullptr;
    return &m_list[static_cast<std::size_t>(m_index[id])];
}

std::int32_t Catchments::catchment_of_pit(std::int64_t pit) const {
    return m_seed_owner[pit];
}

void Catchments::reindex() {
    std::fill(m_index.begin(), m_index.end(), -1);
    m_index.resize(static_cast<std::size_t>(m_next_id), -1);
    for (std::size_t k = 0; k < m_list.size(); ++k) {
        m_index[m_list[k].id] = static_cast<std::int32_t>(k);
        for (const auto s : m_list[k].seeds) m_seed_owner[s] = m_list[k].id;
    }
}

void Catchments::add_to_pit(std::int64_t pit, double v) {
    if (!(v > 0)) return;
    if (const std::int32_t id = catchment_of_pit(pit)) {
        Catchment* k = find(id);
        k->volume_m3 += v;
        k->dirty = true;
        return;
    }
    Catchment k;
    k.id = m_next_id++;
    k.seeds = {pit};
    k.volume_m3 = v;
    k.level_m = m_fd.elevation(pit);
    k.cells = {pit};
    m_seed_owner[pit] = k.id;
    m_index.resize(static_cast<std::size_t>(m_next_id), -1);
    m_index[k.id] = static_cast<std::int32_t>(m_list.size());
    m_list.push_back(std::move(k));
}

void Catchments::deliver(std::int64_t cell, double v, std::int32_t from) {
    if (m_fd.is_outlet(cell)) {
        m_lost_m3 += v;
        if (Catchment* k = find(from)) k->dynamic = false;
        return;
    }
    const std::int32_t o = m_owner[cell];
    if (o != 0 && o != from) {
        Catchment* t = find(o);
        t->volume_m3 += v;
        t->dirty = true;
        return;
    }
    const std::int64_t t = m_fd.terminus(cell);
    if (m_fd.is_outlet(t)) {
        m_lost_m3 += v;
        if (Catchment* k = find(from)) k->dynamic = false;
        return;
    }
    add_to_pit(t, v);
}

void Catchments::add_water(std::int64_t cell, double v) {
    if (!(v > 0)) return;
    if (m_fd.is_outlet(cell)) {
        m_lost_m3 += v;
        return;
    }
    if (const std::int32_t o = m_owner[cell]) {
        Catchment* k = find(o);
        k->volume_m3 += v;
        k->dirty = true;
        return;
    }
    deliver(cell, v, 0);
}

void Catchments::add_routed(const RoutedWater& r) {
    m_lost_m3 += r.lost_m3;
    for (std::int64_t c = 0; c < static_cast<std::int64_t>(r.at_pit_m3.size()); ++c)
        if (r.at_pit_m3[c] > 0) add_to_pit(c, r.at_pit_m3[c]);
}

Catchments pond(const terrain::RasterD& dem, double depth_m, Routing routing) {
    if (!(depth_m >= 0) || !std::isfinite(depth_m))
        throw InputError("--depth-m must be >= 0 m, got " + std::to_string(depth_m));
    Catchments c(dem);
    const double area = dem.cell_size() * dem.cell_size();
    std::vector<double> v(static_cast<std::size_t>(dem.size()));
    for (std::int64_t k = 0; k < dem.size(); ++k)
        v[k] = std::isnan(dem.data()[k]) ? 0.0 : depth_m * area;
    c.add_routed(route_to_pits(c.flow(), v, routing));
    c.equilibrate();
    return c;
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

bool Catchments::drains_into_region(std::int64_t c) const {
    for (;;) {
        if (m_stamp_region[c] == m_stamp) return true;
        if (m_fd.is_outlet(c) || m_fd.is_pit(c)) return false;
        c = m_fd.receiver(c);
    }
}

namespace {
/// Queues the not-yet-queued Moore neighbours of c (NODATA as -infinity, i.e. an outlet).
template <class Queue>
void queue_neighbours(const FlowDirections& fd, std::int64_t c, std::vector<std::uint32_t>& queued,
                      std::uint32_t stamp, Queue& pq) {
    const auto& g = fd.grid();
    const int i = static_cast<int>(c % g.nx), j = static_cast<int>(c / g.nx);
    for (const auto& o : terrain::kMooreOffsets) {
        const int a = i + o[0], b = j + o[1];
        if (!g.contains(a, b)) continue;
        const std::int64_t q = cell_index(g, a, b);
        if (queued[q] == stamp) continue;
        queued[q] = stamp;
        const double zq = fd.elevation(q);
        pq.emplace(std::isnan(zq) ? -std::numeric_limits<double>::infinity() : zq, q);
    }
}
} // namespace

Catchments::Fill Catchments::fill(const Catchment& k) {
    ++m_stamp;
    Fill f;
    using Entry = std::pair<double, std::int64_t>;
    std::priority_queue<Entry, std::vector<Entry>, std::greater<>> pq;
    const double vd = k.volume_m3 / m_area; // volume as metres over one cell
    double n = 0, sum_z = 0, running_max = kNegInf;
    // Warm start: the flood takes cells in a fixed (elevation, index) order whatever the volume,
    // so with more water and the same seeds it passes through the previous region first. Take
    // that region at once and queue its boundary.
    const bool known =
        k.filled_volume_m3 >= 0 && k.filled_seeds == k.seeds.size() && !k.cells.empty();
    if (known && k.volume_m3 < k.filled_volume_m3) {
        // Less water: the region is a prefix of the last take sequence (k.cells is in take order).
        // Replay it with the flood's own checks; no queue is needed.
        for (const auto s : k.seeds) m_stamp_region[s] = m_stamp;
        for (const auto c : k.cells) {
            const double z = m_fd.elevation(c);
            if (n > 0 && z < running_max) {
                f.cells.push_back(c);
                n += 1;
                sum_z += z;
                if (vd < n * running_max - sum_z) {
                    f.separated = true;
                    f.max_z = running_max;
                    return f;
                }
                continue;
            }
            if (n > 0 && vd <= n * z - sum_z) {
                f.level = (vd + sum_z) / n;
                f.max_z = running_max;
                return f;
            }
            f.cells.push_back(c);
            n += 1;
            sum_z += z;
            running_max = z;
        }
        f.max_z = running_max;
        const double cap = k.last_spill_cell >= 0 ? n * k.last_spill_level - sum_z : 0.0;
        if (k.last_spill_cell >= 0 && vd > cap) {
            f.level = k.last_spill_level;
            f.excess = (vd - cap) * m_area;
            f.spill_cell = k.last_spill_cell;
        } else {
            f.level = (vd + sum_z) / n;
        }
        return f;
    }
    const bool warm = known && k.volume_m3 >= k.filled_volume_m3;
    if (warm) {
        for (const auto c : k.cells) {
            m_stamp_region[c] = m_stamp;
            m_stamp_queued[c] = m_stamp;
        }
        for (const auto c : k.cells) {
            f.cells.push_back(c);
            n += 1;
            sum_z += m_fd.elevation(c);
            queue_neighbours(m_fd, c, m_stamp_queued, m_stamp, pq);
        }
        running_max = k.fill_max_z;
        // Seeds the last fill did not reach are still this catchment's own, as in a cold start.
        for (const auto sd : k.seeds) {
            m_stamp_region[sd] = m_stamp;
            if (m_stamp_queued[sd] == m_stamp) continue;
            m_stamp_queued[sd] = m_stamp;
            pq.emplace(m_fd.elevation(sd), sd);
        }
    } else {
        for (const auto s : k.seeds) {
            pq.emplace(m_fd.elevation(s), s);
            m_stamp_queued[s] = m_stamp;
            m_stamp_region[s] = m_stamp;
        }
    }
    auto take = [&](std::int64_t c, double z) {
        m_stamp_region[c] = m_stamp;
        f.cells.push_back(c);
        n += 1;
        sum_z += z;
        queue_neighbours(m_fd, c, m_stamp_queued, m_stamp, pq);
    };
    auto spill_at = [&](double level, std::int64_t cell) {
        const double cap = n * level - sum_z;
        if (vd <= cap) {
            f.level = (vd + sum_z) / n;
        } else {
            f.level = level;
            f.excess = (vd - cap) * m_area;
            f.spill_cell = cell;
        }
    };
    while (!pq.empty()) {
        const auto [z, c] = pq.top();
        pq.pop();
        if (m_fd.is_outlet(c)) {
            spill_at(std::max(running_max, z), c);
            {
                f.max_z = running_max;
                return f;
            }
        }
        if (n > 0 && z < running_max) {
            if (drains_into_region(c)) {
                take(c, z);
                // Below the water already? Then the level must still reach the highest cell
                // taken; if it cannot, the bodies under this catchment have separated.
                if (vd < n * running_max - sum_z) {
                    f.separated = true;
                    {
                        f.max_z = running_max;
                        return f;
                    }
                }
                continue;
            }
            spill_at(running_max, c);
            {
                f.max_z = running_max;
                return f;
            }
        }
        if (n > 0 && vd <= n * z - sum_z) {
            f.level = (vd + sum_z) / n;
            {
                f.max_z = running_max;
                return f;
            }
        }
        take(c, z);
        running_max = z;
    }
    f.level = n > 0 ? (vd + sum_z) / n : 0.0;
    {
        f.max_z = running_max;
        return f;
    }
}

Catchments::Fill Catchments::fill_common_level(const Catchment& k) {
    ++m_stamp;
    Fill f;
    using Entry = std::pair<double, std::int64_t>;
    std::priority_queue<Entry, std::vector<Entry>, std::greater<>> pq;
    for (const auto s : k.seeds) {
        pq.emplace(m_fd.elevation(s), s);
        m_stamp_queued[s] = m_stamp;
    }
    const double vd = k.volume_m3 / m_area;
    double n = 0, sum_z = 0;
    while (!pq.empty()) {
        const auto [z, c] = pq.top();
        pq.pop();
        if (m_fd.is_outlet(c) || (n > 0 && vd <= n * z - sum_z)) break;
        f.cells.push_back(c);
        n += 1;
        sum_z += z;
        queue_neighbours(m_fd, c, m_stamp_queued, m_stamp, pq);
    }
    f.level = n > 0 ? (vd + sum_z) / n : 0.0;
    return f;
}

void Catchments::release_cells(const Catchment& k) {
    for (const auto c : k.cells)
        if (m_owner[c] == k.id) m_owner[c] = 0;
}

void Catchments::split_if_separated(std::size_t index) {
    Catchment k = m_list[index];
    // Submerged cells (depth > 0) and their Moore adjacency, as a Boost graph.
    std::unordered_map<std::int64_t, std::size_t> vid;
    std::vector<std::int64_t> wet;
    for (const auto c : k.cells)
        if (k.level_m - m_fd.elevation(c) > 0) {
            vid.emplace(c, wet.size());
            wet.push_back(c);
        }
    using Graph = boost::adjacency_list<boost::vecS, boost::vecS, boost::undirectedS>;
    Graph graph(wet.size());
    const auto& g = m_fd.grid();
    for (std::size_t v = 0; v < wet.size(); ++v) {
        const int i = static_cast<int>(wet[v] % g.nx), j = static_cast<int>(wet[v] / g.nx);
        for (const auto& o : terrain::kMooreOffsets) {
            if (!g.contains(i + o[0], j + o[1])) continue;
            const auto it = vid.find(cell_index(g, i + o[0], j + o[1]));
            if (it != vid.end() && it->second > v) boost::add_edge(v, it->second, graph);
        }
    }
    std::vector<int> component(wet.size(), -1);
    int count = 0;
    struct Labeler : boost::default_bfs_visitor {
        std::vector<int>* comp;
        int label;
        void discover_vertex(std::size_t v, const Graph&) const { (*comp)[v] = label; }
    };
    std::vector<boost::default_color_type> colour(wet.size(), boost::white_color);
    for (std::size_t v = 0; v < wet.size(); ++v) {
        if (component[v] >= 0) continue;
        Labeler lab;
        lab.comp = &component;
        lab.label = count++;
        boost::breadth_first_search(graph, v,
                                    boost::visitor(lab).color_map(boost::make_iterator_property_map(
                                        colour.begin(), boost::get(boost::vertex_index, graph))));
    }
    if (count <= 1) return;
    // Each body keeps the seeds inside it and the water above its own cells.
    std::vector<Catchment> parts(static_cast<std::size_t>(count));
    for (std::size_t v = 0; v < wet.size(); ++v)
        parts[component[v]].volume_m3 += (k.level_m - m_fd.elevation(wet[v])) * m_area;
    for (const auto s : k.seeds) {
        const auto it = vid.find(s);
        if (it != vid.end())
            parts[component[it->second]].seeds.push_back(s);
        else
            m_seed_owner[s] = 0; // a dry seed: a free pit again
    }
    release_cells(k);
    m_list[index].volume_m3 = 0.0; // retired; removed when the pass ends
    m_list[index].cells.clear();
    m_list[index].seeds.clear();
    bool first = true;
    for (auto& p : parts) {
        if (p.seeds.empty()) { // a body with no pit of its own: give it the deepest cell as seed
            double best = 1e300;
            std::int64_t seed = -1;
            for (std::size_t v = 0; v < wet.size(); ++v)
                if (&parts[component[v]] == &p && m_fd.elevation(wet[v]) < best)
                    best = m_fd.elevation(wet[v]), seed = wet[v];
            p.seeds.push_back(seed);
        }
        p.id = first ? k.id : m_next_id++;
        if (first) m_list[index].id = 0; // the retired entry gives up its id
        first = false;
        p.dynamic = k.dynamic;
        p.level_m = k.level_m;
        p.previous_level_m = k.level_m;
        p.dirty = true;
        for (const auto sd : p.seeds) m_seed_owner[sd] = p.id;
        m_index.resize(static_cast<std::size_t>(m_next_id), -1);
        m_index[p.id] = static_cast<std::int32_t>(m_list.size());
        m_list.push_back(std::move(p));
    }
}

int Catchments::equilibrate() {
    // A worklist of catchments whose volume changed, highest water level first: a spill runs from
    // a saddle down to a lower water body, so a catchment usually receives all its inflow before it
    // is filled. (New catchments have the level of their pit.)
    using Item = std::pair<double, std::int32_t>; // (level when last filled, id)
    std::priority_queue<Item> work;
    auto lowest_seed = [&](const Catchment& k) { return k.level_m; };
    auto push = [&](std::int32_t id) {
        if (const Catchment* k = find(id); k && k->dirty) work.emplace(lowest_seed(*k), id);
    };
    for (const auto& k : m_list)
        if (k.dirty) work.emplace(lowest_seed(k), k.id);
    int fills = 0;
    while (!work.empty()) {
        const std::int32_t id = work.top().second;
        work.pop();
        Catchment* kp = find(id);
        if (!kp || !kp->dirty) continue;
        if (kp->volume_m3 <= kVolumeEpsilon) {
            kp->dirty = false;
            continue;
        }
        if (++fills > kMaxPasses)
            throw Error("catchments: no equilibrium after " + std::to_string(kMaxPasses) +
                        " updates");
        const std::size_t idx = static_cast<std::size_t>(m_index[id]);
        Fill f = fill(m_list[idx]);
        if (f.separated) f = fill_common_level(m_list[idx]);
        ++m_fills;
        m_cells_filled += static_cast<std::int64_t>(f.cells.size());
        Catchment& k = m_list[idx];
        k.dirty = false;
        if (f.separated) {
            k.filled_volume_m3 = -1.0; // a common-level fill is no prefix of a flood
        } else {
            // After a spill the catchment keeps its capacity; any volume at or above it floods the
            // same region again.
            k.filled_volume_m3 = k.volume_m3 - std::max(0.0, f.excess);
            k.fill_max_z = f.max_z;
            k.last_spill_cell = f.excess > 0 ? f.spill_cell : -1;
            k.last_spill_level = f.level;
            k.filled_seeds = k.seeds.size();
        }
        // Ownership stays current: a catchment's cells are re-claimed whenever it is recomputed,
        // so spills find the water body that covers their cell.
        release_cells(k);
        k.level_m = f.level;
        k.cells = std::move(f.cells);
        for (const auto c : k.cells)
            if (m_owner[c] == 0) m_owner[c] = k.id;
        const bool fell = k.level_m < k.previous_level_m;
        k.previous_level_m = k.level_m;
        // A spilling catchment is full to its saddle, hence connected: only a catchment that
        // holds all its water can have separated.
        const bool spilling = f.excess > kVolumeEpsilon;
        if ((fell && k.seeds.size() > 1 && !spilling) || f.separated) {
            const std::size_t before = m_list.size();
            split_if_separated(idx);
            if (m_list.size() != before) {
                for (std::size_t n = before; n < m_list.size(); ++n) push(m_list[n].id);
                continue;
            }
        }
        if (f.excess <= kVolumeEpsilon) {
            m_list[idx].spills_into = 0;
            continue;
        }
        m_list[idx].volume_m3 -= f.excess;
        deliver(f.spill_cell, f.excess, id); // may append to m_list
        // The target: the owner of the spill cell, or the pit's catchment.
        std::int32_t target = m_owner[f.spill_cell];
        if (target == 0 && !m_fd.is_outlet(f.spill_cell)) {
            const auto t = m_fd.terminus(f.spill_cell);
            if (!m_fd.is_outlet(t)) target = catchment_of_pit(t);
        }
        m_list[idx].spills_into = target;
        if (target == 0 || target == id) continue;
        Catchment* b = find(target);
        if (b && b->spills_into == id && b->volume_m3 > kVolumeEpsilon) {
            // Mutual spill: the two are one body at the shared saddle. Merge them.
            Catchment& a = m_list[idx];
            a.seeds.insert(a.seeds.end(), b->seeds.begin(), b->seeds.end());
            for (const auto sd : b->seeds) m_seed_owner[sd] = a.id;
            a.volume_m3 += b->volume_m3;
            a.dynamic = a.dynamic && b->dynamic;
            a.dirty = true;
            a.spills_into = 0;
            release_cells(*b);
            b->volume_m3 = 0.0; // retired; removed below
            b->cells.clear();
            b->seeds.clear();
            b->dirty = false;
            push(id);
        } else {
            push(target);
        }
    }
    // Drop empty and retired catchments.
    std::erase_if(m_list, [&](const Catchment& k) {
        if (k.volume_m3 > kVolumeEpsilon) return false;
        release_cells(k);
        for (const auto s : k.seeds)
            if (m_seed_owner[s] == k.id) m_seed_owner[s] = 0;
        return true;
    });
    reindex();
    return fills;
}

terrain::Raster<std::int32_t> Catchments::id_map() const {
    terrain::Raster<std::int32_t> m(m_dem.grid(), 0);
    for (const auto& k : m_list)
        for (const auto c : k.cells)
            if (k.level_m - m_fd.elevation(c) > 0 && m.data()[c] == 0) m.data()[c] = k.id;
    return m;
}

terrain::RasterD Catchments::depth_map() const {
    terrain::RasterD d(m_dem.grid(), 0.0);
    for (const auto& k : m_list)
        for (const auto c : k.cells)
            d.data()[c] = std::max(d.data()[c], k.level_m - m_fd.elevation(c));
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
        a.put(k.id);
        a.put_vector(k.seeds);
        a.put(k.volume_m3);
        a.put(k.level_m);
        a.put_vector(k.cells);
        a.put(k.previous_level_m);
        a.put(k.dynamic);
        a.put(k.dirty);
        a.put(k.filled_volume_m3);
        a.put(k.fill_max_z);
        a.put(k.filled_seeds);
        a.put(k.last_spill_cell);
        a.put(k.last_spill_level);
        a.put(k.spills_into);
    }
    a.put_vector(m_owner);
    a.put_vector(m_seed_owner);
    a.put(m_next_id);
    a.put(m_lost_m3);
    a.put(m_fills);
    a.put(m_cells_filled);
}

void Catchments::load_state(ArchiveReader& a) {
    const auto n = a.get<std::uint64_t>();
    std::vector<Catchment> list(n);
    for (auto& k : list) {
        k.id = a.get<std::int32_t>();
        k.seeds = a.get_vector<std::int64_t>();
        k.volume_m3 = a.get<double>();
        k.level_m = a.get<double>();
        k.cells = a.get_vector<std::int64_t>();
        k.previous_level_m = a.get<double>();
        k.dynamic = a.get<bool>();
        k.dirty = a.get<bool>();
        k.filled_volume_m3 = a.get<double>();
        k.fill_max_z = a.get<double>();
        k.filled_seeds = a.get<std::size_t>();
        k.last_spill_cell = a.get<std::int64_t>();
        k.last_spill_level = a.get<double>();
        k.spills_into = a.get<std::int32_t>();
    }
    auto owner = a.get_vector<std::int32_t>();
    auto seed_owner = a.get_vector<std::int32_t>();
    if (owner.size() != m_owner.size() || seed_owner.size() != m_seed_owner.size())
        throw Error("catchment checkpoint: " + std::to_string(owner.size()) +
                    " cells, the terrain has " + std::to_string(m_owner.size()));
    m_list = std::move(list);
    m_owner = std::move(owner);
    m_seed_owner = std::move(seed_owner);
    m_next_id = a.get<std::int32_t>();
    m_lost_m3 = a.get<double>();
    m_fills = a.get<std::int64_t>();
    m_cells_filled = a.get<std::int64_t>();
    reindex();
}

} // namespace ecoterra::hydro
