#pragma once
// The fastest route over a mobility map (docs/mobility.md s10.3): a least-time path over the map's
// cells (Dijkstra), moving to the 8 neighbours; a move from cell A to its neighbour B along
// heading h takes half the step at A's speed for h and half at B's, the step being the cell side
// (or its diagonal). NO-GO (speed 0) cells in a heading cannot be crossed in it.
#include "ecoterra/mobility/smg.hpp"
#include "ecoterra/raster.hpp"

#include <vector>

namespace ecoterra::mobility {

struct Route {
    bool found = false;
    std::vector<Point> path; ///< cell centres from the start's cell to the goal's
    double time_s = 0;
    double length_m = 0;   ///< along the path
    double straight_m = 0; ///< from the start's cell centre to the goal's
    double smg_m_per_s() const { return time_s > 0 ? straight_m / time_s : 0.0; }
};

/// The fastest route from `from` to `to` over the per-heading speed layers of a map (m/s, one
/// raster per heading in `headings_deg`, clockwise from north; the eight neighbour directions
/// 0, 45, ..., 315 must be among them). InputError for a point off the map or missing headings.
Route fastest_route(const std::vector<RasterD>& speed_m_per_s,
                    const std::vector<double>& headings_deg, Point from, Point to);

} // namespace ecoterra::mobility
