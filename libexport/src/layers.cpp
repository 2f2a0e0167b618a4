// GeoTIFF layers of a snapshot on the terrain's grid (`ecoterra export layers`).
#include "ecoterra/export/formats.hpp"

#include "ecoterra/eco/deadwood.hpp"
#include "ecoterra/error.hpp"
#include "ecoterra/run/run_reader.hpp"
#include "ecoterra/terrain/io/raster_io.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>

namespace ecoterra::exporter {

namespace {

constexpr double kM2PerHa = 1e4;

} // namespace

VegetationLayers vegetation_layers(const Scene& s, const LayerOptions& opt) {
    if (!(opt.window_radius_m > 0))
        throw InputError("--window " + format_number(opt.window_radius_m) + ": must be above 0 m");
    const GridSpec& g = s.terrain.grid();
    VegetationLayers v{RasterD(g, 0.0), RasterD(g, 0.0), RasterD(g, 0.0),
                       RasterD(g, std::numeric_limits<double>::quiet_NaN()), RasterD(g, 0.0)};
    // Window area inside the terrain: the cells whose centres fall in it (so that edge cells are
    // not diluted by ground outside the terrain).
    RasterD window_cells(g, 0.0);
    for (int j = 0; j < g.ny; ++j)
        for (int i = 0; i < g.nx; ++i)
            cells_within(g, g.x_of(i), g.y_of(j), opt.window_radius_m,
                         [&](int, int) { window_cells(i, j) += 1; });
    std::vector<RasterD> ba_by_species(s.species.size(), RasterD(g, 0.0));
    for (const auto& t : s.trees) {
        const auto& sp = s.species[static_cast<std::size_t>(t.species)];
        cells_within(g, t.x_m, t.y_m, t.crown_radius_m, [&](int i, int j) {
            v.canopy_height_m(i, j) = std::max(v.canopy_height_m(i, j), t.height_m);
            v.leaf_area_m2(i, j) += sp.leaf_area_per_crown_area;
        });
        if (!(t.dbh_m > 0)) continue;
        const double ba = std::numbers::pi / 4 * t.dbh_m * t.dbh_m;
        cells_within(g, t.x_m, t.y_m, opt.window_radius_m, [&](int i, int j) {
            const double area_ha = window_cells(i, j) * g.cell_size_m * g.cell_size_m / kM2PerHa;
            v.stems_per_ha(i, j) += 1 / area_ha;
            v.basal_area_m2_per_ha(i, j) += ba / area_ha;
            ba_by_species[static_cast<std::size_t>(t.species)](i, j) += ba;
        });
    }
    for (int j = 0; j < g.ny; ++j)
        for (int i = 0; i < g.nx; ++i) {
            double best = 0;
            for (std::size_t k = 0; k < ba_by_species.size(); ++k)
                if (ba_by_species[k](i, j) > best) {
                    best = ba_by_species[k](i, j);
                    v.dominant_species(i, j) = static_cast<double>(k);
                }
            // Leaf area per cell: the crowns' leaf area index summed over the crowns covering it,
            // times the cell's area.
            v.leaf_area_m2(i, j) *= g.cell_size_m * g.cell_size_m;
        }
    return v;
}

namespace {

struct Layer {
    std::string file, unit, what;
    RasterD r;
};

/// The vegetation layers: elevation, canopy height, stems and basal area, dominant species, leaf
/// area.
std::vector<Layer> vegetation_layer_list(const Scene& s, const LayerOptions& opt) {
    const auto veg = vegetation_layers(s, opt);
    return {
        {"elevation_m.tif", "m", "terrain elevation", s.terrain},
        {"canopy_height_m.tif", "m",
         "height of the tallest tree whose crown covers the cell centre (0: open)",
         veg.canopy_height_m},
        {"stems_per_ha.tif", "1/ha",
         "stems with a DBH (height above 1.37 m) within " + format_number(opt.window_radius_m) +
             " m of the cell centre, per ha of that window inside the terrain",
         veg.stems_per_ha},
        {"basal_area_m2_per_ha.tif", "m2/ha",
         "basal area (pi DBH^2 / 4) in the same window, per ha", veg.basal_area_m2_per_ha},
        {"dominant_species.tif", "index",
         "species with the largest basal area in the window (0-based, as listed below; nodata: "
         "none)",
         veg.dominant_species},
        {"leaf_area_m2.tif", "m2",
         "leaf area above the cell: the leaf area index of every crown covering its centre, times "
         "the cell area",
         veg.leaf_area_m2},
    };
}

/// The snapshot's ground cover, soil water and surface water, cut to the scene's region.
void add_water_layers(const Scene& s, std::vector<Layer>& layers) {
    const GridSpec full = run::read_run_terrain(s.run).grid();
    auto cut = [&](RasterD r) {
        return s.region ? r.crop(s.cut_i0, s.cut_j0, s.terrain.nx(), s.terrain.ny()) : r;
    };
    if (run::snapshot_has_dataset(s.run, s.snapshot, "ground_cover")) {
        layers.push_back({"ground_cover.tif", "1",
                          "cover of the ground layer (grasses and herbs), fraction of the ground",
                          cut(run::read_snapshot_raster(s.run, s.snapshot, "ground_cover", full))});
    }
    // The snapshot holds the root zone's volumetric water content; the relative moisture follows
    // from the run's soil: (theta - theta_wp) / (theta_fc - theta_wp).
    const RasterD theta = cut(run::read_snapshot_raster(s.run, s.snapshot, "soil_moisture", full));
    const RasterD fc = cut(run::read_run_soil(s.run, "field_capacity", full));
    const RasterD wp = cut(run::read_run_soil(s.run, "wilting_point", full));
    RasterD relative(theta.grid(), std::numeric_limits<double>::quiet_NaN());
    for (Eigen::Index k = 0; k < theta.size(); ++k) {
        const double span = fc.data()[k] - wp.data()[k];
        if (span > 0) relative.data()[k] = (theta.data()[k] - wp.data()[k]) / span;
    }
    layers.push_back({"soil_water_content_m3_per_m3.tif", "m3/m3",
                      "volumetric water content of the root zone (the snapshot's soil_moisture)",
                      theta});
    layers.push_back({"relative_soil_moisture.tif", "1",
                      "relative soil moisture of the root zone: (theta - wilting point) / (field "
                      "capacity - wilting point), 0 at the wilting point, 1 at field capacity, "
                      "above 1 wetter (nodata: a soil with field capacity at the wilting point)",
                      relative});
    const std::vector<std::pair<std::string, std::string>> water = {
        {"surface_water_depth_m", "standing water depth, m"},
        {"water_table_depth_m", "depth of the water table below the surface, m"},
        {"catchment_id", "catchment the cell drains to (id)"}};
    for (const auto& [name, what] : water)
        layers.push_back({name + ".tif", name == "catchment_id" ? "id" : "m", what,
                          cut(run::read_snapshot_raster(s.run, s.snapshot, name, full))});
}

/// The snapshot's dead wood (none in runs without it): its volume per ha of each cell, logs and
/// slash spread along their length, snags and stumps at their base; and the highest top of a
/// lying piece or stump in the cell (what a wheel meets).
void add_deadwood_layers(const Scene& s, std::vector<Layer>& layers) {
    const GridSpec& g = s.terrain.grid();
    RasterD volume(g, 0.0), top(g, 0.0);
    const double cell_ha = g.cell_size_m * g.cell_size_m / kM2PerHa;
    auto add = [&](double x_run, double y_run, double v_m3, double h_m) {
        // Records are in the run's frame; the scene may be about a local origin.
        const double x = x_run - s.frame.origin_x_m, y = y_run - s.frame.origin_y_m;
        if (!g.contains_point(x, y)) return;
        const int i = std::clamp(static_cast<int>(std::floor(g.col_of(x) + 0.5)), 0, g.nx - 1);
        const int j = std::clamp(static_cast<int>(std::floor(g.row_of(y) + 0.5)), 0, g.ny - 1);
        volume(i, j) += v_m3 / cell_ha;
        top(i, j) = std::max(top(i, j), h_m);
    };
    const auto pieces = run::read_snapshot_deadwood(s.run, s.snapshot).pieces;
    for (const auto& p : pieces) {
        if (p.standing) {
            add(p.x_m, p.y_m, p.volume_m3, p.piece == 1 ? p.height_m : 0.0);
            continue;
        }
        // A lying piece in parts of at most a quarter cell, each at its middle.
        const int n = std::max(1, static_cast<int>(std::ceil(p.length_m / (0.25 * g.cell_size_m))));
        for (int k = 0; k < n; ++k) {
            const double t = (k + 0.5) / n;
            add(p.x_m + t * (p.end_x_m - p.x_m), p.y_m + t * (p.end_y_m - p.y_m), p.volume_m3 / n,
                p.height_m + t * (p.end_height_m - p.height_m));
        }
    }
    layers.push_back(
        {"deadwood_volume_m3_per_ha.tif", "m3/ha",
         "volume of the dead wood (snags, logs, stumps and slash) in the cell, per ha: "
         "lying pieces spread along their length (the part past the terrain's edge is "
         "left out), standing ones at their base",
         volume});
    layers.push_back({"deadwood_top_height_m.tif", "m",
                      "highest top above the ground of a log, piece of slash or stump in the cell "
                      "(0: none)",
                      top});
    layers.push_back({"windthrow_pit_depth_m.tif", "m",
                      "depth of the pit an uprooted tree's root plate left (0: none): a disc as "
                      "wide as the plate, windward of it, half the plate's thickness deep",
                      mobility::pit_depths(s.terrain.grid(), run::stand_deadwood(pieces).pits,
                                           s.frame.origin_x_m, s.frame.origin_y_m)});
}

void write_layers_readme(const Scene& s, OutputFolder& folder, const std::string& table) {
    std::string species;
    for (std::size_t k = 0; k < s.species.size(); ++k)
        species += "- " + std::to_string(k) + ": " + s.species[k].name + "\n";
    const std::string& wkt = s.terrain.crs_wkt();
    const std::string crs =
        wkt.empty() ? "No coordinate reference system: the run's terrain had none (a generated "
                      "terrain, or a DEM file without one), so x and y are local metres (x east, "
                      "y north)."
                    : "Coordinate reference system: the run's terrain's, carried from its DEM "
                      "file (WKT in every file; it begins " +
                          wkt.substr(0, std::min<std::size_t>(wkt.size(), 60)) + " ...).";
    const GridSpec& g = s.terrain.grid();
    char geo[256];
    std::snprintf(geo, sizeof geo,
                  "%d x %d cells of %.9g m; west edge x = %.9g m, south edge y = %.9g m (GDAL "
                  "geotransform %.9g, %.9g, 0, %.9g, 0, %.9g)",
                  g.nx, g.ny, g.cell_size_m, g.origin_x_m, g.origin_y_m, g.origin_x_m,
                  g.cell_size_m, g.origin_y_m + g.height_m(), -g.cell_size_m);
    folder.write("README.md", "# GeoTIFF layers from ecoterra\n\nRun: " + s.source + ", snapshot " +
                                  std::to_string(s.snapshot) + " (year " + std::to_string(s.year) +
                                  ").\n\nEvery layer: Float32, north-up, " + geo +
                                  ", nodata NaN. " + crs + "\n\n" + table +
                                  "\nSpecies indices:\n\n" + species +
                                  "\nLoad: `gdalinfo FILE.tif`; in Python `rasterio.open(FILE)` or "
                                  "`gdal.Open(FILE)`; in QGIS drag the files in.\n");
}

} // namespace

void write_layers(const Scene& s, OutputFolder& folder, const LayerOptions& opt) {
    std::vector<Layer> layers = vegetation_layer_list(s, opt);
    add_water_layers(s, layers);
    add_deadwood_layers(s, layers);
    std::string table = "| file | unit | what |\n|---|---|---|\n";
    for (auto& l : layers) {
        l.r.set_crs_wkt(s.terrain.crs_wkt()); // every layer georeferenced like the terrain
        terrain::io::write_geotiff(l.r, folder.staged_path(l.file), l.unit);
        table += "| " + l.file + " | " + l.unit + " | " + l.what + " |\n";
    }
    write_layers_readme(s, folder, table);
}

} // namespace ecoterra::exporter
