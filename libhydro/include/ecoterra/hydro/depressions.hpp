#pragma once
// Depression hierarchy of a DEM (Barnes, Callaghan & Wickert 2020, ESurf 8:431, "Computing water
// flow through complex landscapes, Part 2").
//
// Leaves are the pits of the D8 flow directions (a pit is a cell with no strictly lower
// neighbour; adjacent pits of equal elevation form one leaf, so a flat floor is one leaf). Every
// interior cell belongs to the leaf its D8 path ends in, or to the ocean (the domain edge and
// NODATA) when that path leaves the domain. Two neighbouring depressions meet at a pass: the
// lowest max(z_a, z_b) over neighbouring cells a, b on either side (NODATA counts as -infinity).
// Taking passes in rising order (Kruskal), two depressions that meet form a meta-depression whose
// children both have the pass as their outlet; a depression that meets the set already joined to
// the ocean has its outlet there and no parent. Water overflowing a depression runs over its pass
// into the leaf on the far side (its overflow leaf). For a depression without a parent that leaf
// drains to the edge over lower passes, so the water fills it and spills on from there; only a
// pass whose far side is the edge (or NODATA) itself has no overflow leaf (as Fill-Spill-Merge's
// odep, Barnes et al. 2020 s2.3).
//
// Each cell with z below the outlet of its leaf's top ancestor lies in the elevation band
// [base, outlet) of exactly one node on its leaf's ancestor chain (base = the children's outlet,
// -infinity for a leaf). A node flooded to level h (base <= h <= outlet) covers all cells of its
// descendants and the cells of its own band with z < h, connected under water. Its volume
//   V(h) = h (N_d + k) - (Z_d + P_k)
// (N_d, Z_d: count and elevation sum of the descendants' cells; P_k: sum of the k lowest own-band
// elevations below h) is monotone in h, so the level for a volume is a binary search over the
// node's band, sorted once when the hierarchy is built (rising elevation, ties by cell index).
#include "ecoterra/hydro/routing.hpp"

#include <cstdint>
#include <span>
#include <vector>

namespace ecoterra::hydro {

class DepressionHierarchy {
public:
    explicit DepressionHierarchy(const FlowDirections& fd);

    std::int32_t node_count() const { return static_cast<std::int32_t>(m_parent.size()); }
    std::int32_t leaf_count() const { return m_leaves; }
    bool is_leaf(std::int32_t n) const { return n < m_leaves; }
    /// Leaf whose pit a cell's D8 path ends in; -1 if it ends at the domain edge or NODATA.
    std::int32_t leaf_of(std::int64_t cell) const { return m_leaf[cell]; }
    /// Node whose elevation band holds the cell; -1 if the cell can never be flooded.
    std::int32_t node_of(std::int64_t cell) const { return m_node[cell]; }
    /// Parent node (-1: the depression overflows to the domain edge).
    std::int32_t parent(std::int32_t n) const { return m_parent[n]; }
    std::int32_t child(std::int32_t n, int k) const { return m_child[2 * n + k]; }
    std::int32_t sibling(std::int32_t n) const {
        const std::int32_t p = m_parent[n];
        return m_child[2 * p] == n ? m_child[2 * p + 1] : m_child[2 * p];
    }
    /// Leaf over whose pass this node overflows (-1: the pass leads straight onto the domain edge).
    std::int32_t overflow_leaf(std::int32_t n) const { return m_odep[n]; }
    /// Outlet (pass) elevation, m; +infinity if the depression never overflows.
    double outlet_z(std::int32_t n) const { return m_outlet[n]; }
    /// Lowest elevation inside the node, m.
    double min_z(std::int32_t n) const { return m_minz[n]; }
    /// Elevation where the node's band starts (its children's outlet); -infinity for a leaf.
    double base_z(std::int32_t n) const;
    /// Volume (m x cells) the node holds when full to its outlet, and when full to its base.
    double capacity(std::int32_t n) const { return m_capacity[n]; }
    double base_capacity(std::int32_t n) const;
    /// Cells of the node and all its descendants (all below its outlet).
    std::int64_t cells_below_outlet(std::int32_t n) const { return m_cum_n[n]; }
    /// Pit cells of a leaf.
    std::span<const std::int64_t> pits(std::int32_t leaf) const;
    /// The cells of a node's own band, in rising elevation (ties by cell index).
    std::span<const std::int64_t> band(std::int32_t n) const;

    struct Level {
        double level_m = 0;       ///< water surface elevation
        std::int64_t own_wet = 0; ///< cells of the node's own band under water (its lowest ones)
    };
    /// Water level of the node holding `volume` (m x cells), base_capacity <= volume <= capacity.
    Level level_for(std::int32_t n, double volume) const;
    /// Volume (m x cells) below level h over the node and its descendants (any h).
    double volume_below(std::int32_t n, double h) const;

    /// Calls f(node) for n and every node under it.
    template <class F>
    void for_each_in_subtree(std::int32_t n, F&& f) const {
        std::vector<std::int32_t> stack{n};
        while (!stack.empty()) {
            const std::int32_t x = stack.back();
            stack.pop_back();
            f(x);
            if (!is_leaf(x)) {
                stack.push_back(m_child[2 * x]);
                stack.push_back(m_child[2 * x + 1]);
            }
        }
    }

private:
    /// The lowest pass between two neighbouring depressions (b == the leaf count: the ocean).
    struct Pass {
        double z;
        std::int32_t a, b; // a < b
        bool operator<(const Pass& o) const {
            if (z != o.z) return z < o.z;
            if (a != o.a) return a < o.a;
            return b < o.b;
        }
    };
    // The constructor's steps, in order.
    /// 1. Leaves: pits, with adjacent pits of equal elevation grouped.
    void find_leaves(const FlowDirections& fd);
    /// 2. Every other cell takes the leaf its D8 path ends in.
    void label_cells(const FlowDirections& fd);
    /// 3. The lowest pass between each pair of neighbouring depressions, sorted.
    std::vector<Pass> lowest_passes(const FlowDirections& fd) const;
    /// 4. Kruskal over the passes builds the hierarchy.
    void join_over_passes(const FlowDirections& fd, const std::vector<Pass>& passes);
    /// 5. Each cell's band: the lowest ancestor of its leaf whose outlet is above it.
    void assign_bands(const FlowDirections& fd);
    /// 6. Totals over each subtree (children come before their parent) and capacities.
    void subtree_totals();
    /// Puts a node's band in rising elevation (ties by cell index) with running sums.
    void sort_band(std::int32_t n, const FlowDirections& fd);

    std::int32_t m_leaves = 0;
    std::vector<std::int32_t> m_leaf, m_node;
    std::vector<std::int32_t> m_parent, m_child, m_odep;
    std::vector<double> m_outlet, m_minz, m_capacity;
    std::vector<std::int64_t> m_cum_n, m_own_n;
    std::vector<double> m_cum_z, m_own_z;
    std::vector<std::int64_t> m_pit_begin, m_pits;
    // Bands: node n's cells are m_band_cells[m_band_begin[n] .. m_band_begin[n + 1]).
    std::vector<std::int64_t> m_band_begin, m_band_cells;
    std::vector<double> m_band_z, m_band_prefix; ///< sorted elevations and their running sums
};

} // namespace ecoterra::hydro
