#pragma once
// Hydrology scenes: the JSON file `ecoterra hydro run` reads, and the run itself.
// Every key, its unit, default and range: docs/formats.md. Unknown keys are errors.
#include "ecoterra/hydro/hydrology.hpp"
#include "ecoterra/hydro/soil.hpp"
#include "ecoterra/memory.hpp"
#include "ecoterra/methods.hpp"

#include "ecoterra/io/hdf5_writer.hpp"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <functional>
#include <optional>

namespace ecoterra::hydro {

/// The files of a soil given as rasters on the terrain's grid (scene section soil.rasters).
struct SoilRasterFiles {
    std::string sand_pct, silt_pct, clay_pct;
    std::string ph; ///< optional: "" = the uniform default pH
};
const ParamCatalog<SoilRasterFiles>& soil_rasters_catalog();

/// How a scene gives its soil: `kind` is uniform, random or rasters, and the matching member holds
/// its keys.
struct SoilSpec {
    std::string kind = "uniform";
    SoilComposition uniform;
    RandomSoilParams random;
    SoilRasterFiles rasters;
};

/// The vegetation cover of a hydrology scene (section vegetation; ecosystem runs compute it from
/// their plants): a uniform density, or a raster of densities on the terrain's grid.
struct VegetationCover {
    double density = 0.5;
    std::string density_file; ///< "" = uniform `density`
};
const ParamCatalog<VegetationCover>& vegetation_cover_catalog();

struct HydroScene {
    RasterD dem;
    SoilSpec soil_spec;
    SoilMap soil;
    VegetationCover cover;
    RasterD vegetation_density;
    Climate climate;
    std::optional<WeatherSeries> observed; ///< a CSV series instead of the generator
    HydrologyOptions options;
    int years = 1;
    std::uint64_t seed = 1;
    int snapshot_interval_days = 365;
    nlohmann::json resolved; ///< the scene with defaults filled in
    /// Where the terrain came from: a DEM's file, window, resampling and coordinate systems
    /// (terrain::io::DemRead::record); empty for a generated terrain.
    nlohmann::json terrain_source = nlohmann::json::object();
    std::vector<std::string> notes; ///< what the loader did that the user should know
};

/// The scene keys of section "simulation" of a hydrology scene.
const ParamCatalog<HydroScene>& hydro_simulation_catalog();

/// The published methods a hydrology scene uses (terrain, soil, weather, ET, runoff, routing,
/// catchments, groundwater), for the run's provenance and log.
Methods scene_methods(const HydroScene& scene);

/// The memory a run of the scene needs at its peak: per terrain cell (rasters of the terrain, soil,
/// water state, flow order, catchments, output staging) and, with groundwater, the solver's arrays
/// per cell. Measured peak resident sizes (/usr/bin/time -v) of 1-year runs from 62,500 to
/// 1,000,000 cells fit 51 MB + 478 B per cell (plant grid included), + 150 B per cell with
/// groundwater; the constants carry some margin (docs/scaling.md). The soil-water processes of
/// issue 27 added 76 B per cell (surface layer, drainage exponent, today's leaves and cover, the
/// interception and the ecosystem's leaf rasters): a 1 km2 year at 1 m peaked at 456 MB, 75 MB
/// more than before. On 2026-11-27 (the catchments' owner map adds 4 B per cell; the ground
/// layer's two grids exist only with one) `ecoterra run` of a 1 km2 year at 1 m with 300 stems/ha
/// and its output peaked at 615 MiB, under the run's estimate of 1.2 GiB (plants included).
MemoryEstimate memory_estimate(const HydroScene& scene);
inline constexpr double kFixedBytes = 60e6;
inline constexpr double kBytesPerTerrainCell = 580;
inline constexpr double kBytesPerGroundwaterCell = 170;

/// Reads a scene; relative file paths are taken from `base_dir`. Throws InputError naming the key.
HydroScene load_hydro_scene(const nlohmann::json& scene, const std::filesystem::path& base_dir);

struct HydroRunSummary {
    int days = 0;
    double rain_mm = 0, evaporation_mm = 0, transpiration_mm = 0, interception_mm = 0,
           runoff_out_mm = 0, drainage_out_mm = 0, groundwater_out_mm = 0;
    double residual_relative = 0; ///< |cumulative residual| / cumulative throughput
    double seconds = 0;
};

/// Runs the scene and writes the HDF5 output (atomically). `progress(day, total_days, seconds)`
/// is called once per simulated month. With `png_dir`, pictures of the final state go there:
/// hillshade.png, soil_moisture.png, surface_water_depth.png.
/// Writes the soil maps under /soil/.
void write_soil_maps(io::Hdf5Writer& h5, const SoilMap& soil);
/// The soil maps written under /soil of hydrology and ecosystem runs.
const std::vector<RasterLayer<SoilMap>>& soil_map_layers();
/// The water state written in every snapshot of hydrology and ecosystem runs.
const std::vector<RasterLayer<HydrologyModel>>& water_state_layers();

/// Writes each column of a table as a dataset group/NAME with its units and description.
void write_table(io::Hdf5Writer& h5, const std::string& group, const Table& t);

/// Where a hydrology run is, for its progress line: the day's calendar (the weather's year and
/// day of year: observed years have 365 or 366 days) and the seconds so far.
struct HydroProgress {
    int day = 0, days = 0; ///< days done, of the run's total
    int year = 0, doy = 0; ///< the day's weather year and day of year
    double seconds = 0;
};
HydroRunSummary run_hydro_scene(const HydroScene& scene, const std::filesystem::path& output,
                                const nlohmann::json& provenance,
                                const std::filesystem::path& png_dir = {},
                                const std::function<void(const HydroProgress&)>& progress = {});

} // namespace ecoterra::hydro
