#pragma once
// `hydro pond`: a uniform depth of water spread over a DEM, routed to the pits and resolved to
// equilibrium (catchments.hpp), with its water budget and its output file (docs/formats.md,
// "Pond output").
#include "ecoterra/hydro/catchments.hpp"
#include "ecoterra/hydro/routing.hpp"
#include "ecoterra/raster.hpp"

#include <cstdint>
#include <filesystem>
#include <string>

namespace ecoterra::hydro {

/// Where the water of a pond went, m3 over the whole DEM.
struct PondBudget {
    double input_m3 = 0;              ///< depth x cell area x valid cells
    double stored_m3 = 0;             ///< standing in the catchments at equilibrium
    double left_through_edges_m3 = 0; ///< overflow that left the DEM
    double residual_m3() const { return input_m3 - stored_m3 - left_through_edges_m3; }
};

struct PondResult {
    double depth_m = 0; ///< the depth spread over every valid cell
    Routing routing = Routing::d8;
    RasterD water_depth_m;             ///< standing water at equilibrium
    Raster<std::int32_t> catchment_id; ///< catchment holding each cell, 0 = dry
    std::size_t catchments = 0;        ///< number of catchments
    std::int64_t valid_cells = 0, wet_cells = 0;
    PondBudget budget;
};

/// Ponds `depth_m` of water over `dem` (see pond() in catchments.hpp) and accounts for it.
PondResult pond_with_budget(const RasterD& dem, double depth_m, Routing routing);

/// Writes the pond output file: /surface_water_depth_m, /catchment_id, /elevation, the root
/// attributes depth_m and routing, the /budget attributes, and /provenance (a JSON text).
void write_pond(const std::filesystem::path& path, const RasterD& dem, const PondResult& p,
                const std::string& provenance_json);

} // namespace ecoterra::hydro
