#include "ecoterra/eco/roots.hpp"
#include "ecoterra/parallel.hpp"

#include <algorithm>
#include <omp.h>

namespace ecoterra::eco {

namespace {
/// Appends the root cells of plants [p0, p1) to r.
void add_root_cells(const CrownSet& roots, const CellMap& map, std::size_t p0, std::size_t p1,
                    RootCells& r) {
    std::vector<std::int32_t> count; // per hydrology cell of the crown's bounding box
    for (std::size_t p = p0; p < p1; ++p) {
        const double inv_n = 1.0 / roots.cells[p];
        const std::uint32_t s0 = roots.offset[p], s1 = roots.offset[p + 1];
        if (map.factor == 1) {
            for (std::uint32_t s = s0; s < s1; ++s) {
                const Span& sp = roots.spans[s];
                r.cell.push_back(map.hydro(sp.row, sp.x0));
                r.share.push_back(inv_n);
                r.length.push_back(sp.x1 - sp.x0 + 1);
                r.additions += sp.x1 - sp.x0 + 1;
            }
        } else {
            // Count the root cells falling in each hydrology cell of the bounding box.
            int hx0 = 1 << 30, hx1 = -1, hy0 = 1 << 30, hy1 = -1;
            for (std::uint32_t s = s0; s < s1; ++s) {
                const Span& sp = roots.spans[s];
                hy0 = std::min(hy0, sp.row / map.factor);
                hy1 = std::max(hy1, sp.row / map.factor);
                hx0 = std::min(hx0, sp.x0 / map.factor);
                hx1 = std::max(hx1, sp.x1 / map.factor);
            }
            const int w = hx1 - hx0 + 1;
            count.assign(static_cast<std::size_t>(w) * static_cast<std::size_t>(hy1 - hy0 + 1), 0);
            for (std::uint32_t s = s0; s < s1; ++s) {
                const Span& sp = roots.spans[s];
                std::int32_t* row = count.data() + (sp.row / map.factor - hy0) * w - hx0;
                for (int x = sp.x0; x <= sp.x1; ++x) ++row[x / map.factor];
            }
            for (int j = hy0; j <= hy1; ++j)
                for (int i = hx0; i <= hx1; ++i) {
                    const std::int32_t c = count[static_cast<std::size_t>((j - hy0) * w + i - hx0)];
                    if (c == 0) continue;
                    r.cell.push_back(static_cast<std::int64_t>(j) * map.hydro_nx + i);
                    r.share.push_back(c * inv_n);
                    ++r.additions;
                }
        }
        r.offset.push_back(static_cast<std::uint32_t>(r.cell.size()));
    }
}

/// Appends `o`'s plants to r.
void append(RootCells& r, const RootCells& o) {
    const auto base = static_cast<std::uint32_t>(r.cell.size());
    for (std::size_t i = 1; i < o.offset.size(); ++i) r.offset.push_back(base + o.offset[i]);
    r.cell.insert(r.cell.end(), o.cell.begin(), o.cell.end());
    r.share.insert(r.share.end(), o.share.begin(), o.share.end());
    r.length.insert(r.length.end(), o.length.begin(), o.length.end());
    r.additions += o.additions;
}
} // namespace

RootCells root_cells(const CrownSet& roots, const CellMap& map) {
    // In fixed blocks of plants in parallel, joined in order: the entries of one pass.
    const std::size_t n = roots.size();
    std::vector<RootCells> part(plant_blocks(n));
    for_each_plant_block(n, [&](std::size_t b, std::size_t first, std::size_t end) {
        add_root_cells(roots, map, first, end, part[b]);
    });
    RootCells r;
    std::size_t entries = 0;
    for (const RootCells& o : part) entries += o.cell.size();
    r.offset.reserve(n + 1);
    r.cell.reserve(entries);
    r.share.reserve(entries);
    if (map.factor == 1) r.length.reserve(entries);
    for (RootCells& o : part) {
        append(r, o);
        o = RootCells{}; // each part freed once joined
    }
    return r;
}

namespace {
/// The plants lie scattered over the grid, so an entry's cells are most often a cache miss: the
/// cells of the entry this many ahead are fetched early (a few plants of a dense stand ahead).
constexpr std::uint32_t kPrefetchAhead = 16;
/// Asks for the first and last cell of entry e, if there is one, for reading (rw 0) or writing.
template <int rw>
inline void prefetch_entry(const RootCells& roots, std::uint32_t e, const double* base) {
    if (e >= roots.cell.size()) return;
    __builtin_prefetch(base + roots.cell[e], rw);
    __builtin_prefetch(base + roots.cell[e] + roots.cells_of(e) - 1, rw);
}
} // namespace

void scatter_demand(const RootCells& roots, const std::vector<double>& demand,
                    std::vector<double>& request) {
    for (std::size_t p = 0; p < roots.size(); ++p) {
        const double d = demand[p];
        if (!(d > 0)) continue;
        for (std::uint32_t e = roots.offset[p]; e < roots.offset[p + 1]; ++e) {
            prefetch_entry<1>(roots, e + kPrefetchAhead, request.data());
            const double v = d * roots.share[e];
            double* r = request.data() + roots.cell[e];
            for (std::int32_t k = 0, n = roots.cells_of(e); k < n; ++k) r[k] += v;
        }
    }
}

void scatter_pair(const RootCells& roots, const std::vector<double>& a,
                  const std::vector<double>& b, std::vector<double>& a_cells,
                  std::vector<double>& b_cells) {
    // Each quantity's scatter is serial in plant order (the bits of scatter_demand); on large
    // stands the two run side by side, one per thread, where a single thread did both in one pass.
    if (roots.additions >= parallel_min_items() && omp_get_max_threads() > 1 &&
        !omp_in_parallel()) {
#pragma omp parallel num_threads(2)
        {
            // A team of one (a thread limit) does both.
            const int t = omp_get_thread_num(), team = omp_get_num_threads();
            if (t == 0) scatter_demand(roots, a, a_cells);
            if (t == 1 || team == 1) scatter_demand(roots, b, b_cells);
        }
        return;
    }
    for (std::size_t p = 0; p < roots.size(); ++p) {
        const double x = a[p], y = b[p];
        const bool add_x = x > 0, add_y = y > 0;
        if (!add_x && !add_y) continue;
        for (std::uint32_t e = roots.offset[p]; e < roots.offset[p + 1]; ++e) {
            const double u = x * roots.share[e], v = y * roots.share[e];
            double *ra = a_cells.data() + roots.cell[e], *rb = b_cells.data() + roots.cell[e];
            for (std::int32_t k = 0, n = roots.cells_of(e); k < n; ++k) {
                if (add_x) ra[k] += u;
                if (add_y) rb[k] += v;
            }
        }
    }
}

void gather_supply(const RootCells& roots, const std::vector<double>& ratio,
                   std::vector<double>& fraction) {
    const auto n = static_cast<std::int64_t>(roots.size());
    fraction.resize(static_cast<std::size_t>(n));
#pragma omp parallel for schedule(static) if (n >= parallel_min_items())
    for (std::int64_t p = 0; p < n; ++p) {
        double acc = 0;
        for (std::uint32_t e = roots.offset[static_cast<std::size_t>(p)];
             e < roots.offset[static_cast<std::size_t>(p) + 1]; ++e) {
            prefetch_entry<0>(roots, e + kPrefetchAhead, ratio.data());
            const double s = roots.share[e];
            const double* q = ratio.data() + roots.cell[e];
            for (std::int32_t k = 0, m = roots.cells_of(e); k < m; ++k) acc += s * q[k];
        }
        fraction[static_cast<std::size_t>(p)] = acc;
    }
}

} // namespace ecoterra::eco
