#include "ecoterra/hydro/pond.hpp"

#include "ecoterra/io/hdf5_writer.hpp"

#include <cmath>

namespace ecoterra::hydro {

PondResult pond_with_budget(const RasterD& dem, double depth_m, Routing routing) {
    const Catchments c = pond(dem, depth_m, routing);
    PondResult p;
    p.depth_m = depth_m;
    p.routing = routing;
    p.water_depth_m = c.depth_map();
    p.catchment_id = c.id_map();
    p.catchments = c.catchments().size();
    for (std::int64_t k = 0; k < dem.size(); ++k) {
        if (std::isnan(dem.data()[k])) continue;
        ++p.valid_cells;
        p.wet_cells += p.water_depth_m.data()[k] > 0;
    }
    const double cell_area_m2 = dem.cell_size() * dem.cell_size();
    p.budget.input_m3 = depth_m * cell_area_m2 * static_cast<double>(p.valid_cells);
    p.budget.stored_m3 = c.total_volume_m3();
    p.budget.left_through_edges_m3 = c.lost_m3();
    return p;
}

void write_pond(const std::filesystem::path& path, const RasterD& dem, const PondResult& p,
                const std::string& provenance_json) {
    io::Hdf5Writer h5(path);
    h5.raster("/surface_water_depth_m", p.water_depth_m, "m",
              "standing water depth at equilibrium");
    h5.raster("/catchment_id", p.catchment_id, "1", "catchment holding the cell, 0 = dry");
    h5.raster("/elevation", dem, "m", "the DEM ponded");
    h5.attribute("/", "depth_m", p.depth_m);
    h5.attribute("/", "routing", routing_name(p.routing));
    h5.attribute("/budget", "input_m3", p.budget.input_m3);
    h5.attribute("/budget", "stored_m3", p.budget.stored_m3);
    h5.attribute("/budget", "left_through_edges_m3", p.budget.left_through_edges_m3);
    h5.attribute("/budget", "residual_m3", p.budget.residual_m3());
    h5.attribute("/provenance", "json", provenance_json);
    h5.commit();
}

} // namespace ecoterra::hydro
