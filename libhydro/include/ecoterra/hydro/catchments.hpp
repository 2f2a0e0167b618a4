#pragma once
// Catchments: standing water bodies that form, grow, shrink, spill, merge and split (paper 002
// s4.3), resolved to equilibrium.
//
// A catchment is a set of seed pits and a water volume V (m3). Its state follows from filling the
// DEM from its seeds by priority flood (Barnes, Lehman & Mulla 2014): cells are taken in order of
// elevation; the water level h over the n cells taken so far satisfies
//   V = A sum_{cells} (h - z_c)      (A = cell area)
// so the catchment grows (takes the next lowest neighbouring cell) once V exceeds the volume at
// that cell's elevation, and shrinks (gives up its highest submerged cell) when V falls below the
// volume at the highest submerged cell's elevation, exactly the two thresholds of the paper.
// A neighbouring cell lower than the highest cell taken, whose D8 path leaves the catchment, is a
// spill point: the level stays at that highest cell (the saddle) and the excess runs down the D8
// path to the pit it reaches. There it joins the catchment holding that pit, or forms a new one.
// Edge cells are outlets: water reaching one leaves the domain. Two catchments that spill into each
// other are merged (one catchment with both seeds). When the level of a catchment with several
// seeds falls, its submerged cells are checked for connection by breadth-first search
// (Boost.Graph); separated bodies become catchments of their own, each keeping the water above its
// own cells. Updates repeat until nothing
// spills: the equilibrium. Catchments that spill out of the domain stay at their spill level and
// are reported as not dynamic.
//
// With water first routed to the pits along D8, the equilibrium is that of the Fill-Spill-Merge
// algorithm of Barnes, Callaghan & Wickert (2021, ESurf 9:105) with the domain edge as ocean.
#include "ecoterra/archive.hpp"
#include "ecoterra/hydro/routing.hpp"
#include "ecoterra/terrain/raster.hpp"

#include <cstdint>
#include <vector>

namespace ecoterra::hydro {

struct Catchment {
    std::int32_t id = 0;             ///< stable id, >= 1
    std::vector<std::int64_t> seeds; ///< pit cells
    double volume_m3 = 0.0;
    // Derived by equilibrate():
    double level_m = 0.0;            ///< water surface elevation
    std::vector<std::int64_t> cells; ///< cells with water depth >= 0 (the region)
    double previous_level_m = 1e300; ///< level at the previous pass (a fall triggers a split check)
    bool dynamic = true;             ///< false once it spills out of the domain
    bool dirty = true;               ///< volume changed since its region was last computed
    double filled_volume_m3 = -1.0;  ///< volume at the last fill (-1 = none; warm-start check)
    double fill_max_z = 0.0;         ///< highest elevation taken by the last fill
    std::size_t filled_seeds = 0;    ///< seed count at the last fill
    std::int64_t last_spill_cell = -1; ///< where the last fill spilled (-1: it did not)
    double last_spill_level = 0.0;     ///< and at which level
    std::int32_t spills_into = 0;      ///< id it spilled into when last computed (0 = none)
};

class Catchments {
public:
    explicit Catchments(const terrain::RasterD& dem);

    const FlowDirections& flow() const { return m_fd; }
    double cell_area_m2() const { return m_area; }

    /// Water arriving on the surface at a cell: joins the catchment covering it, or runs along D8
    /// to a pit (joining or creating that pit's catchment) or an outlet (lost).
    void add_water(std::int64_t cell, double volume_m3);
    /// Adds water directly to a pit (e.g. from route_to_pits); creates its catchment if needed.
    void add_to_pit(std::int64_t pit, double volume_m3);
    /// Adds water already routed to the pits, counting what reached an outlet as lost.
    void add_routed(const RoutedWater& r);
    /// Removes up to `volume_m3` from a catchment; returns what was removed.
    double remove_water(std::int32_t id, double volume_m3);

    /// Resolves spills, merges and splits until nothing changes. Returns the iterations used.
    int equilibrate();

    const std::vector<Catchment>& catchments() const { return m_list; }
    /// Catchment id per cell (0 = dry) and water depth per cell, m.
    terrain::Raster<std::int32_t> id_map() const;
    terrain::RasterD depth_map() const;
    /// Id of the catchment covering a cell, 0 if none (valid after equilibrate()).
    std::int32_t owner(std::int64_t cell) const { return m_owner[cell]; }
    double total_volume_m3() const;
    /// Volume that left the domain through outlets since construction.
    double lost_m3() const { return m_lost_m3; }
    /// Work counters (for benchmarks): catchment fills and cells taken by them, since construction.
    std::int64_t fills() const { return m_fills; }
    std::int64_t cells_filled() const { return m_cells_filled; }

    /// Checkpoint: every catchment and the owner maps, bit-exact.
    void save_state(ArchiveWriter& a) const;
    void load_state(ArchiveReader& a);

private:
    struct Fill {
        double level = 0, excess = 0;
        std::int64_t spill_cell = -1; ///< where the excess goes (an outlet or a cell outside)
        bool separated = false;       ///< the level fell below a saddle inside the region
        double max_z = 0;             ///< highest elevation taken
        std::vector<std::int64_t> cells;
    };
    Fill fill(const Catchment& k);
    /// The common water level of a catchment's volume over all its seeds, taking cells in order
    /// of elevation only (used when its bodies have separated below a saddle).
    Fill fill_common_level(const Catchment& k);
    bool drains_into_region(std::int64_t c) const;
    Catchment* find(std::int32_t id);
    std::int32_t catchment_of_pit(std::int64_t pit) const;
    void deliver(std::int64_t cell, double volume_m3, std::int32_t from);
    void split_if_separated(std::size_t index);
    void release_cells(const Catchment& k);

    terrain::RasterD m_dem;
    FlowDirections m_fd;
    double m_area;
    std::vector<Catchment> m_list;
    std::vector<std::int32_t> m_owner;      ///< catchment id per cell after equilibrate()
    std::vector<std::int32_t> m_seed_owner; ///< catchment id whose seeds include the cell
    std::vector<std::int32_t> m_index;      ///< position in m_list by id (-1 = none)
    void reindex();
    std::int32_t m_next_id = 1;
    double m_lost_m3 = 0.0;
    std::int64_t m_fills = 0, m_cells_filled = 0;
    // Scratch for fill(): stamps avoid clearing per call.
    std::vector<std::uint32_t> m_stamp_queued, m_stamp_region;
    std::uint32_t m_stamp = 0;
};

/// Spreads a uniform depth (m) over every valid cell, routes it to the pits (D8 or MFD), and
/// resolves the catchments to equilibrium, with no infiltration or evaporation.
Catchments pond(const terrain::RasterD& dem, double depth_m, Routing routing);

} // namespace ecoterra::hydro
