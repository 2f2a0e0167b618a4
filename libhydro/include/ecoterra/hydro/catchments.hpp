#pragma once
// Catchments: standing water bodies that form, grow, shrink, spill, merge and split (paper 002
// s4.3), resolved to equilibrium on the depression hierarchy of the DEM (depressions.hpp).
//
// A catchment is a water volume V (m3) held by one node of the hierarchy: a leaf depression (one
// pit) or a meta-depression (several pits under one surface). Its level h follows from
//   V = A sum_{cells below h} (h - z_c)      (A = cell area)
// over the node's cells, which is the priority-flood filling of Barnes, Lehman & Mulla (2014)
// taken in closed form: the catchment grows once V passes the volume at the next lowest
// unsubmerged cell and shrinks when V falls below the volume at its highest submerged cell, the
// two thresholds of the paper. When V exceeds the node's capacity (full to its outlet, the pass),
// the level stays at the pass and the excess runs over it to the leaf on the far side, joining
// the catchment there or forming a new one. A catchment full to a pass whose far side is full too
// merges with it into the parent node (a lake over the saddle). When a merged catchment falls
// below its children's saddle, it splits: the bodies under the saddle separate, each keeping the
// water above its own cells at the common level. A top-level depression (one that meets the set
// draining to the edge before it meets another depression) spills over its pass into the
// depression on the far side, which fills and spills on towards the edge in turn; only water over
// a pass straight onto the domain edge (or NODATA) is lost, and such a catchment stays at its
// pass and is reported as not dynamic. Updates repeat until nothing spills: the equilibrium.
//
// With water first routed to the pits along D8, the equilibrium is that of the Fill-Spill-Merge
// algorithm of Barnes, Callaghan & Wickert (2021, ESurf 9:105) with the domain edge as ocean.
#include "ecoterra/archive.hpp"
#include "ecoterra/hydro/depressions.hpp"
#include "ecoterra/hydro/routing.hpp"
#include "ecoterra/raster.hpp"

#include <cstdint>
#include <vector>

namespace ecoterra::hydro {

struct Catchment {
    std::int32_t id = 0;    ///< 1 + the hierarchy node it fills
    std::int32_t node = -1; ///< that node
    double volume_m3 = 0.0;
    // Derived by equilibrate():
    double level_m = 0.0;       ///< water surface elevation
    std::int64_t wet_cells = 0; ///< cells with level above the ground
    std::int64_t own_wet = 0;   ///< of which in the node's own band (its lowest cells)
    bool dynamic = true;        ///< false while it spills over the domain edge
    bool dirty = true;          ///< volume changed since its level was last computed
};

class Catchments {
public:
    explicit Catchments(const RasterD& dem, D8Rule rule = D8Rule::steepest);

    const FlowDirections& flow() const { return m_fd; }
    const DepressionHierarchy& hierarchy() const { return m_dh; }
    double cell_area_m2() const { return m_area; }

    /// Water arriving on the surface at a cell: joins the catchment covering it, or runs along D8
    /// to a pit (joining or creating that pit's catchment) or an outlet (lost).
    void add_water(std::int64_t cell, double volume_m3);
    /// Adds water at a pit (e.g. from route_to_pits); creates its catchment if needed. A cell
    /// that is not a pit passes the water on to the pit its D8 path ends in.
    void add_to_pit(std::int64_t pit, double volume_m3);
    /// Adds water already routed to the pits, counting what reached an outlet as lost.
    void add_routed(const RoutedWater& r);
    /// Adds water to a catchment by id (e.g. rain on its wet cells).
    void add_water_to(std::int32_t id, double volume_m3);
    /// Removes up to `volume_m3` from a catchment; returns what was removed.
    double remove_water(std::int32_t id, double volume_m3);

    /// Resolves spills, merges and splits until nothing changes. Returns the updates used.
    int equilibrate();

    const std::vector<Catchment>& catchments() const { return m_list; }
    /// The pit cells under a catchment, in rising cell index.
    std::vector<std::int64_t> seeds(const Catchment& k) const;
    /// Calls f(cell) for every cell of a catchment under water or at its level (valid after
    /// equilibrate()): its descendants' cells and the lowest own_wet cells of its own band.
    template <class F>
    void for_each_wet_cell(const Catchment& k, F&& f) const {
        const auto own = m_dh.band(k.node);
        for (std::int64_t i = 0; i < k.own_wet; ++i) f(own[static_cast<std::size_t>(i)]);
        if (m_dh.is_leaf(k.node)) return;
        for (int side = 0; side < 2; ++side)
            m_dh.for_each_in_subtree(m_dh.child(k.node, side), [&](std::int32_t n) {
                for (const auto c : m_dh.band(n)) f(c);
            });
    }
    /// Catchment id per cell (0 = dry: owner() of every cell) and water depth per cell, m.
    Raster<std::int32_t> id_map() const;
    RasterD depth_map() const;
    /// Id of the catchment whose water covers a cell, 0 if none (valid after equilibrate()): a
    /// map kept by each equilibrium, holding owner_by_hierarchy's answers. Between equilibria the
    /// answers do not change (a catchment created by new water starts at its lowest cell, under
    /// which nothing lies).
    std::int32_t owner(std::int64_t cell) const { return m_owner[static_cast<std::size_t>(cell)]; }
    /// The definition of owner(): the cell's node, the catchment covering it, and the cell's
    /// elevation below that catchment's level (a walk through three tables; tests compare).
    std::int32_t owner_by_hierarchy(std::int64_t cell) const {
        const std::int32_t n = m_dh.node_of(cell);
        if (n < 0 || m_cover[n] == 0) return 0;
        const Catchment& k = m_list[static_cast<std::size_t>(m_pos[m_cover[n] - 1])];
        return m_fd.elevation(cell) < k.level_m ? k.id : 0;
    }
    double total_volume_m3() const;
    /// Volume that left the domain through outlets since construction.
    double lost_m3() const { return m_lost_m3; }
    /// Work counter (for benchmarks): catchment updates since construction.
    std::int64_t updates() const { return m_updates; }

    /// Checkpoint: every catchment, bit-exact (the hierarchy is rebuilt from the DEM).
    void save_state(ArchiveWriter& a) const;
    void load_state(ArchiveReader& a);

private:
    Catchment& create(std::int32_t node, double volume_m3);
    void remove(std::int32_t node);
    Catchment& at(std::int32_t node) { return m_list[static_cast<std::size_t>(m_pos[node])]; }
    /// The catchment with this id, or nullptr.
    Catchment* find(std::int32_t id);
    void add_to_leaf(std::int32_t leaf, double volume_m3);
    void set_full(Catchment& k);
    /// Pours spilled water into the catchment at or above `leaf` (below `stop`), creating one at
    /// the leaf if there is none; queues it for an update.
    void pour_into(std::int32_t leaf, std::int32_t stop, double v, std::vector<std::int32_t>& work);
    /// Splits the catchment at a node whose volume fell below its children's saddle; pushes the
    /// new catchments' nodes onto `work`.
    void split(std::int32_t node, std::vector<std::int32_t>& work);
    /// A catchment over its capacity: it spills past its pass (no parent), merges with a full
    /// sibling into one lake over the saddle, or pours the excess towards the sibling.
    void overflow(std::int32_t node, std::vector<std::int32_t>& work);
    /// After an equilibrium: list order, positions, cover map, wet counts and the owner map.
    void finish();
    /// The owner map from the catchments: for each, the lowest cells (below its level) of the
    /// bands of the nodes it covers; work in the cells under water, not in the grid.
    void map_owners();

    RasterD m_dem;
    FlowDirections m_fd;
    DepressionHierarchy m_dh;
    double m_area;
    std::vector<Catchment> m_list;
    std::vector<std::int32_t> m_pos;   ///< position in m_list of the catchment at a node, or -1
    std::vector<std::int32_t> m_cover; ///< id of the catchment covering a node (0 = none)
    std::vector<std::int32_t> m_owner; ///< owner() per cell, set by finish()
    std::vector<std::int64_t> m_owned; ///< the cells with an owner, to clear them next time
    double m_lost_m3 = 0.0;
    std::int64_t m_updates = 0;
};

/// Spreads a uniform depth (m) over every valid cell, routes it to the pits (D8, D8 to the lowest
/// neighbour, or MFD; the hierarchy's pits follow the same D8 rule), and
/// resolves the catchments to equilibrium, with no infiltration or evaporation.
Catchments pond(const RasterD& dem, double depth_m, Routing routing);

} // namespace ecoterra::hydro
