#pragma once
// Surface flow directions on a DEM.
//
// D8 (O'Callaghan & Mark 1984): each cell drains to the Moore neighbour with the steepest downward
// slope (z_c - z_n) / distance; ties go to the first neighbour in the fixed order of
// kMooreOffsets. A cell with no lower neighbour is a pit.
// D8, lowest neighbour (`d8-lowest`): each cell drains to its lowest Moore neighbour, whatever the
// distance, as the flow directions of Barnes et al.'s depression hierarchy and Fill-Spill-Merge
// (a priority flood from the pits reaches a cell first from its lowest neighbour). The two rules
// differ only where a diagonal neighbour is lowest but an edge neighbour is steeper.
// MFD (Freeman 1991, Quinn et al. 1991): each cell drains to all lower neighbours in proportion to
// (slope^p * L), p = 1.1, L = 0.5 for edge neighbours and 0.354 for diagonals (Quinn's contour
// lengths in cells).
// Edge cells are outlets (as the ocean in Barnes et al.'s Fill-Spill-Merge): water that reaches one
// leaves the domain. NODATA cells are outlets too.
#include "ecoterra/raster.hpp"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace ecoterra::hydro {

enum class Routing { d8, mfd, d8_lowest };
/// Which neighbour a D8 cell drains to.
enum class D8Rule { steepest, lowest };
/// The D8 rule of the flow directions a routing builds on (MFD's pits are D8's).
inline D8Rule d8_rule(Routing r) {
    return r == Routing::d8_lowest ? D8Rule::lowest : D8Rule::steepest;
}
Routing parse_routing(const std::string& s);
std::string routing_name(Routing r);

inline constexpr std::int32_t kNoReceiver = -1;

/// Flat index j * nx + i.
inline std::int64_t cell_index(const GridSpec& g, int i, int j) {
    return static_cast<std::int64_t>(j) * g.nx + i;
}

class FlowDirections {
public:
    explicit FlowDirections(const RasterD& dem, D8Rule rule = D8Rule::steepest);
    const GridSpec& grid() const { return m_grid; }
    /// True for edge and NODATA cells: water there leaves the domain.
    bool is_outlet(std::int64_t c) const { return m_outlet[c] != 0; }
    /// The D8 receiver of an interior cell, or kNoReceiver for a pit (and for outlets).
    std::int32_t receiver(std::int64_t c) const { return m_receiver[c]; }
    bool is_pit(std::int64_t c) const { return !is_outlet(c) && m_receiver[c] == kNoReceiver; }
    double elevation(std::int64_t c) const { return m_z[c]; }
    /// Follows D8 from c to the first outlet or pit; returns that cell.
    std::int64_t terminus(std::int64_t c) const;
    std::int64_t size() const { return m_grid.size(); }

private:
    GridSpec m_grid;
    std::vector<double> m_z;
    std::vector<std::int32_t> m_receiver;
    std::vector<std::uint8_t> m_outlet;
};

/// MFD shares of a cell's outflow: up to 8 (neighbour cell, fraction) pairs summing to 1, for the
/// strictly lower neighbours. Returns the count (0 for a pit or a cell next to NODATA, whose
/// water leaves the domain as in D8).
int mfd_shares(const FlowDirections& fd, std::int64_t c,
               std::array<std::pair<std::int64_t, double>, 8>& shares);

struct RoutedWater {
    std::vector<double> at_pit_m3; ///< per cell: volume arriving at that pit (0 elsewhere)
    double lost_m3 = 0.0;          ///< volume that reached an outlet
};

/// Moves a volume on every cell (m3, NaN = none) down to the pits along D8 (fd's rule) or MFD.
RoutedWater route_to_pits(const FlowDirections& fd, const std::vector<double>& volume_m3,
                          Routing routing);

} // namespace ecoterra::hydro
