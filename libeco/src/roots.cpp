#include "ecoterra/eco/roots.hpp"
#include "ecoterra/parallel.hpp"

#include <algorithm>

namespace ecoterra::eco {

namespace {

/// The entries by cell: a counting sort, stable, so each cell's entries keep their order.
void index_by_cell(RootCells& r) {
    const std::size_t entries = r.cell.size();
    r.plant_of.resize(entries);
    for (std::size_t p = 0; p < r.size(); ++p)
        for (std::uint32_t e = r.offset[p]; e < r.offset[p + 1]; ++e)
            r.plant_of[e] = static_cast<std::uint32_t>(p);
    std::int64_t cells = 0;
    for (std::int64_t c : r.cell) cells = std::max(cells, c + 1);
    std::vector<std::uint32_t> count(static_cast<std::size_t>(cells) + 1, 0);
    for (std::int64_t c : r.cell) ++count[static_cast<std::size_t>(c) + 1];
    r.touched.clear();
    r.by_cell_offset.assign(1, 0);
    std::vector<std::uint32_t> slot(static_cast<std::size_t>(cells), 0);
    for (std::int64_t c = 0; c < cells; ++c) {
        const std::uint32_t n = count[static_cast<std::size_t>(c) + 1];
        if (n == 0) continue;
        slot[static_cast<std::size_t>(c)] = r.by_cell_offset.back();
        r.touched.push_back(c);
        r.by_cell_offset.push_back(r.by_cell_offset.back() + n);
    }
    r.by_cell.resize(entries);
    for (std::uint32_t e = 0; e < entries; ++e)
        r.by_cell[slot[static_cast<std::size_t>(r.cell[e])]++] = e;
}

} // namespace

RootCells root_cells(const CrownSet& roots, const CellMap& map) {
    RootCells r;
    r.offset.reserve(roots.size() + 1);
    std::vector<std::int32_t> count; // per hydrology cell of the crown's bounding box
    for (std::size_t p = 0; p < roots.size(); ++p) {
        const double inv_n = 1.0 / roots.cells[p];
        const std::uint32_t s0 = roots.offset[p], s1 = roots.offset[p + 1];
        if (map.factor == 1) {
            for (std::uint32_t s = s0; s < s1; ++s) {
                const Span& sp = roots.spans[s];
                for (int x = sp.x0; x <= sp.x1; ++x) {
                    r.cell.push_back(map.hydro(sp.row, x));
                    r.share.push_back(inv_n);
                }
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
                }
        }
        r.offset.push_back(static_cast<std::uint32_t>(r.cell.size()));
    }
    index_by_cell(r);
    return r;
}

void scatter_demand(const RootCells& roots, const std::vector<double>& demand,
                    std::vector<double>& request) {
    const auto n = static_cast<std::int64_t>(roots.touched.size());
#pragma omp parallel for schedule(static) if (n >= parallel_min_items())
    for (std::int64_t t = 0; t < n; ++t) {
        double& acc = request[static_cast<std::size_t>(roots.touched[static_cast<std::size_t>(t)])];
        for (std::uint32_t k = roots.by_cell_offset[static_cast<std::size_t>(t)];
             k < roots.by_cell_offset[static_cast<std::size_t>(t) + 1]; ++k) {
            const std::uint32_t e = roots.by_cell[k];
            const double d = demand[roots.plant_of[e]];
            if (d > 0) acc += d * roots.share[e];
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
             e < roots.offset[static_cast<std::size_t>(p) + 1]; ++e)
            acc += roots.share[e] * ratio[static_cast<std::size_t>(roots.cell[e])];
        fraction[static_cast<std::size_t>(p)] = acc;
    }
}

} // namespace ecoterra::eco
