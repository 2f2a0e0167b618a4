#pragma once
// Root-water competition on the grid (paper 002 s3: "each cell occupied by roots will uptake the
// required amount of water from the soil for that tree, as a fraction of the total occupied cells
// for each plant in the cell").
//
// A plant's daily demand T_p (m3) is split evenly over its root cells (root radius = crown radius).
// The requests of all plants are summed per hydrology cell and sent to the hydrology, which
// supplies S_h <= R_h without drawing the soil below the wilting point. Each cell's supply is
// shared among the plants rooted in it in proportion to their requests, so plant p receives
//   supplied_p = sum over its cells c of (T_p / n_p) * S_h(c) / R_h(c),
// and the fraction of its demand met is the mean of S_h/R_h over its root cells. The plant grid
// may be finer than the hydrology grid by an integer factor; a plant cell then draws on the
// hydrology cell that contains it.
#include "ecoterra/eco/canopy.hpp"

namespace ecoterra::eco {

struct CellMap {
    int factor = 1;   ///< plant cells per hydrology cell along a side
    int hydro_nx = 0; ///< hydrology grid columns
    std::int64_t hydro(int row, int col) const {
        return static_cast<std::int64_t>(row / factor) * hydro_nx + col / factor;
    }
};

/// Each plant's root cells gathered per hydrology cell: the cells it draws on and the share of its
/// root cells in each (the shares of a plant's cells sum to 1). Built at each canopy refresh, used
/// daily. With a plant grid k times finer than the hydrology grid an entry is one hydrology cell,
/// and a crown of n cells has about n / k^2 entries. With the plant grid equal to the hydrology
/// grid an entry is a run of `length` cells along a row (a crown's span), each with the entry's
/// share 1 / n: 20 B a span where one entry per cell took 16 B a cell.
struct RootCells {
    std::vector<std::uint32_t> offset{0}; ///< plant p's entries are [offset[p], offset[p + 1])
    std::vector<std::int64_t> cell;       ///< an entry's (first) hydrology cell
    std::vector<double> share; ///< fraction of the plant's root cells in each cell of an entry
    std::vector<std::int32_t> length; ///< cells of each entry; empty when every entry is one cell
    std::int64_t additions = 0;       ///< cells over all entries: the work of a scatter
    std::size_t size() const { return offset.size() - 1; }
    /// Cells of entry e.
    std::int32_t cells_of(std::uint32_t e) const { return length.empty() ? 1 : length[e]; }
};

RootCells root_cells(const CrownSet& roots, const CellMap& map);

/// Adds each plant's demand (m3/day) to `request_m3` (per hydrology cell). Serial: the order of
/// the sum per cell does not depend on the thread count.
void scatter_demand(const RootCells& roots, const std::vector<double>& demand_m3,
                    std::vector<double>& request_m3);

/// scatter_demand of two quantities: `a` into `a_cells` and `b` into `b_cells`, each with the
/// same bits as its own scatter_demand. From parallel_min_items() root entries, and with a second
/// thread, the two run side by side, one per thread; below, in one pass over the roots.
void scatter_pair(const RootCells& roots, const std::vector<double>& a,
                  const std::vector<double>& b, std::vector<double>& a_cells,
                  std::vector<double>& b_cells);

/// Fraction of demand met per plant: the mean of ratio[h] over each plant's root cells.
void gather_supply(const RootCells& roots, const std::vector<double>& ratio,
                   std::vector<double>& fraction);

} // namespace ecoterra::eco
