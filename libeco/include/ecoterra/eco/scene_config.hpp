#pragma once
// The ecosystem scene: the hydrology scene (terrain, soil, climate, hydrology) grown with a
// "vegetation" block and extra "simulation" keys. docs/formats.md lists every key, its unit,
// default and range; unknown keys are errors.
#include "ecoterra/eco/canopy.hpp"
#include "ecoterra/eco/deadwood.hpp"
#include "ecoterra/eco/growth.hpp"
#include "ecoterra/eco/management.hpp"
#include "ecoterra/eco/species.hpp"
#include "ecoterra/eco/windthrow.hpp"
#include "ecoterra/hydro/scene.hpp"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <optional>

namespace ecoterra::eco {

enum class Competition { coupled, light_only };
/// The radius of the light-only overlap test: MAVS's competitive radius 0.5 x "Height To
/// Diameter Ratio" x H (MAVS plant.cpp; reference mavs.md s1.2), or the allometric crown radius.
enum class LightOnlyRadius { mavs, crown };
/// The light-only yearly step: ecoterra's diameter curve with Poisson arrivals and largest-first
/// overlap thinning (light_only_radius picks its circle), or MAVS's own ecosystem step (height
/// curve, arrivals at floor(A n) plus one with the remainder's probability, every overlapping pair
/// tested at once: MAVS ecosystem.cpp, reference mavs.md s1.2-1.4; docs/ecosystem.md s7).
enum class LightOnlyModel { diameter_curve, mavs };
std::string competition_name(Competition c);

struct InitialPlants {
    enum class Kind { bare, random, file } kind = Kind::bare;
    double stems_per_ha = 500;  ///< random: stem density
    double max_dbh_m = 0.3;     ///< random: diameters uniform in [recruit dbh, max]
    std::filesystem::path file; ///< file: CSV with x_m,y_m,species,dbh_cm[,age_yr]
};

/// The order the plants are kept in (vegetation.plant_order): by their stem's cell, row by row
/// (sort_by_stem_cell; the default since 2026-11-28, faster at landscape scale), or by birth
/// (the order before: runs and checkpoints of earlier versions continue bit for bit).
enum class PlantOrder { stem_cell, birth };

struct EcoScene {
    hydro::HydroScene hydro;
    EcosystemDef ecosystem;
    Competition competition = Competition::coupled;
    ShadingMode shading = ShadingMode::crown_profile;
    GrowthModel growth = GrowthModel::light_and_turnover;
    DeadWoodOptions deadwood;
    ManagementOptions management; ///< vegetation.management (management.hpp)
    WindthrowOptions windthrow;   ///< vegetation.windthrow (windthrow.hpp)
    double extinction = 0.5;      ///< Beer-Lambert k
    LightOnlyRadius light_only_radius = LightOnlyRadius::crown;
    LightOnlyModel light_only_model = LightOnlyModel::diameter_curve;
    /// MAVS's "Plant Density" (its random scene's growth factor): multiplies every species'
    /// arrivals in the mavs light-only model.
    double mavs_plant_density = 1.0;
    double plant_cell_m = 1.0;     ///< plant (crown/root) grid cell, divides the terrain cell
    int canopy_interval_days = 14; ///< structure, crowns and shading refresh cadence
    PlantOrder plant_order = PlantOrder::stem_cell;
    InitialPlants initial;
    int years = 1;
    std::optional<double> target_basal_area_m2_per_ha;
    int snapshot_interval_years = 5;
    bool snapshot_checkpoints = false; ///< every snapshot keeps the state (fast season replays)
    std::uint64_t seed = 1;
    nlohmann::json resolved;
};

/// The scene keys of sections "vegetation" and "simulation" of an ecosystem scene (the
/// hydrology sections are hydro::*_catalog(); simulation.years and .seed are
/// hydro::hydro_simulation_catalog()'s), and of vegetation.initial.random.
const ParamCatalog<EcoScene>& vegetation_catalog();
const ParamCatalog<EcoScene>& eco_simulation_catalog();
const ParamCatalog<InitialPlants>& initial_random_catalog();

EcoScene load_eco_scene(const nlohmann::json& scene, const std::filesystem::path& base_dir);

/// The memory a run of the scene needs at its peak: the hydrology's (hydro::memory_estimate) and,
/// per plant cell and per plant, the plant model's. The plants counted are the more of the initial
/// stems and kStemCeilingPerHa over the area (stands in the shipped ecosystems stay below ~1,500
/// stems/ha once they close). Measured peaks: ~20 B per plant cell; per plant ~810 B before issue
/// 27 (a 1-year 500 x 500 run with 75,000 stems against one without), and on 2026-11-27 1.5 kB
/// over 3 years and 1.77 kB in the first year (1 km2 at 1 m, 1e5 stems against 3,600-6,900; what
/// issues 27 and 29 added per plant, not split by cause); the constants carry margin.
MemoryEstimate memory_estimate(const EcoScene& scene);
inline constexpr double kBytesPerPlantCell = 24;
inline constexpr double kBytesPerPlant = 2000;
inline constexpr double kStemCeilingPerHa = 3000;

/// The published methods an ecosystem scene uses: its hydrology's (hydro::scene_methods) and the
/// plant model's, for the run's provenance and log.
Methods scene_methods(const EcoScene& scene);

} // namespace ecoterra::eco
