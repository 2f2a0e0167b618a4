#pragma once
// Species and ecosystem files.
//
// An ecosystem file is JSON with a "Species" array. Each entry carries the ten keys of a MAVS
// ecosystem species ("Mesh File", "Species Name", "Num New Per Area", "Growth Rate", "Max Height",
// "Min Height", "Mesh Height", "Height To Diameter Ratio", "Max Age", "Rotate Mesh"; MAVS
// data/ecosystem_files/*.json, reference mavs.md s2.3) and an optional "physiology" object. A MAVS
// file is read as it is: the MAVS top-level keys ("Texture Inputs", "Surface Mesh", ...) are
// accepted and ignored, and every physiology value that is not given takes a default derived from
// the MAVS keys or a documented literature value; the loader lists each such default in
// `notes`. docs/ecosystem.md gives every parameter's meaning, unit and source.
#include "ecoterra/catalog.hpp"
#include "ecoterra/hydro/soil.hpp"

#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace ecoterra::eco {

/// A desired state and a tolerance (the width of the Gaussian response), in the variable's unit.
struct Preference {
    double desired = 0.0;
    double tolerance = 1.0;
};

/// Two-part exponential dispersal kernel (Lischke & Loeffler 2006, iLand): the dispersal distance
/// is exponential with mean `mean_distance_m` with probability 1 - long_fraction, and with mean
/// `long_distance_m` otherwise.
struct DispersalKernel {
    double mean_distance_m = 20.0;
    double long_distance_m = 100.0;
    double long_fraction = 0.1;
};

/// What a species is (docs/ecosystem.md s1.1). Trees and shrubs are individual plants (trees
/// measured at breast height, shrubs at the ground); grasses and herbs form the ground layer, a
/// cover fraction per hydrology cell, not individuals; objects (MAVS's cubes and roadblocks) are
/// inert obstacles placed at their arrival rate.
enum class LifeForm : std::uint8_t { tree, shrub, grass, object };
/// The life forms by their names in species files and outputs.
inline constexpr std::array<std::pair<const char*, LifeForm>, 4> kLifeForms{
    {{"tree", LifeForm::tree},
     {"shrub", LifeForm::shrub},
     {"grass", LifeForm::grass},
     {"object", LifeForm::object}}};
const char* life_form_name(LifeForm f);

/// The outline of a crown: a cone (conifers), an ellipsoid (most broadleaves) or an umbrella (a
/// flat-topped spreading crown: acacia, mesquite).
enum class CrownShape { cone, ellipsoid, umbrella };

struct Species {
    // --- MAVS keys ---
    std::string mesh_file;           ///< "Mesh File": the species identity in MAVS
    std::string name;                ///< "Species Name" (falls back to the mesh file)
    double new_per_area_per_yr = 0;  ///< "Num New Per Area", arrivals m^-2 yr^-1
    double growth_rate_per_yr = 0.1; ///< "Growth Rate": r of H = Hmax (1 - exp(-r t)) (light-only)
    double max_height_m = 20;        ///< "Max Height": asymptotic height Hmax, m
    double min_height_m = 0;         ///< "Min Height": MAVS prunes plants below it, m
    double mesh_height = 1;          ///< "Mesh Height": unscaled mesh height, mesh units
    double height_to_diameter_ratio = 0.05; ///< "Height To Diameter Ratio" (MAVS competition)
    double max_age_yr = 100;                ///< "Max Age", yr
    bool rotate_mesh = false;               ///< "Rotate Mesh"

    // --- allometry ---
    double height_dbh_slope_per_cm = 0.03;    ///< b of H = 1.3 + (Hmax - 1.3)(1 - exp(-b D_cm))
    double crown_radius_coefficient_m = 0.25; ///< c1 of R = c1 D_cm^c2, m
    double crown_radius_exponent = 0.7;       ///< c2
    double max_crown_radius_m = 10.0;
    /// Diameter at which wood growth ends (growth.hpp's w(D)); 0 = none. Default Max Height / 20.
    double max_stem_diameter_m = 0.0;
    double wood_density_kg_per_m3 = 600.0; ///< dry wood mass per fresh volume
    double leaf_area_per_crown_area = 4.0; ///< leaf area index of the crown, m2/m2
    /// light_and_turnover: the leaf area index of a crown in full shade as a fraction of
    /// leaf_area_per_crown_area (1: every crown keeps it; growth.hpp's crown_leaf_factor).
    double shaded_crown_leaf_fraction = 1.0;
    /// Outline of the crown in scene exports (geometry only; growth uses the crown radius).
    CrownShape crown_shape = CrownShape::ellipsoid;
    LifeForm life_form = LifeForm::tree;
    /// Depth the roots of a ground-layer species reach (grass: the water it can take), m.
    double root_depth_m = 0.4;

    // --- carbon ---
    double max_production_kg_per_m2_leaf_per_day = 0.004;   ///< carbohydrate, full conditions
    double respiration_kg_per_m2_leaf_per_m_per_yr = 0.015; ///< maintenance at 20 degC, per m2
                                                            ///< leaf per m of height
    /// light_and_turnover's maintenance (of the sapwood alone: the tissue cost carries leaves and
    /// fine roots), same units; default respiration_kg_per_m2_leaf_per_m_per_yr.
    double sapwood_respiration_kg_per_m2_leaf_per_m_per_yr = 0.015;
    double reserve_capacity_kg_per_m2_leaf = 0.4;
    double initial_reserve_fraction = 0.5; ///< of capacity, for recruits
    double temperature_base_c = 5.0;       ///< production starts above it
    double temperature_optimum_c = 20.0;   ///< production is full above it
    bool evergreen = false;
    int leaf_on_doy = 90, leaf_off_doy = 305; ///< deciduous leaf season (northern hemisphere)

    // --- environment preferences (paper 002 s3: shade, water, soil type, pH) ---
    Preference shade{0.0, 0.5}; ///< shade fraction, 0..1 (more shade than desired hurts)
    /// Light response (vegetation.growth = light_and_turnover, growth.hpp's light_factor): the
    /// light, as a fraction of full sun, at which production is half its light-saturated rate.
    double light_half_saturation = 0.3;
    // Tissue turnover (vegetation.growth = light_and_turnover, growth.hpp's tissue cost).
    double leaf_lifespan_yr = 1.0;              ///< default 2 evergreen, 1 deciduous
    double leaf_mass_per_area_kg_per_m2 = 0.05; ///< default from leaf longevity (Reich 1997)
    double fine_root_to_leaf_mass = 1.0;        ///< LPJ-GUESS ltor_max
    double fine_root_turnover_per_yr = 0.7;     ///< LPJ-GUESS turnover_root
    Preference water{1.0, 0.3}; ///< fraction of the transpiration demand met (less hurts)
    Preference ph{6.5, 1.0};    ///< soil pH (two-sided)
    hydro::Texture texture = hydro::Texture::silt_loam; ///< desired USDA class
    double texture_tolerance_pct = 30.0; ///< distance in the texture triangle, percentage points

    // --- water ---
    double transpiration_per_leaf_area = 0.2; ///< m3 water per m2 leaf per m of reference ET

    // --- reproduction and death ---
    double maturity_age_yr = 15;
    double seeds_per_yr_at_30cm = 10; ///< established-seedling potential of a 30 cm tree per yr
    DispersalKernel dispersal;
    double germination_min_light = 0.05;     ///< fraction of full light at the ground
    double germination_min_soil_water = 0.2; ///< relative extractable soil water, 0..1
    double germination_probability = 0.5;    ///< of a seed landing on a suitable cell
    double recruit_dbh_m = 0.01;             ///< a recruit enters with this diameter
    double background_mortality_per_yr = 0.005;
    /// Size-related mortality, the rising arm of the U-shaped mortality against stem diameter that
    /// Lines, Coomes & Purves (2010, PLoS ONE 5:e13212) found in all 21 eastern US species they
    /// fitted: a plant of stem diameter D also dies with probability
    /// senescence_mortality_per_yr (D / senescence_diameter_m)^senescence_exponent per year
    /// (0 = none, the default).
    double senescence_mortality_per_yr = 0.0;
    double senescence_diameter_m = 0.5;
    double senescence_exponent = 3.0;
    /// Growth-suppression mortality (after LPJ-GUESS's greff_min, reference forest.md s1): a plant
    /// whose mean yearly growth efficiency (net dry-mass increment of wood and reserve per m2 of
    /// leaf) falls below `suppression_growth_efficiency` dies with probability
    /// suppression_mortality_per_yr * (1 - efficiency / threshold) per year.
    double suppression_growth_efficiency_kg_per_m2_leaf_per_yr = 0.15;
    double suppression_mortality_per_yr = 0.3;
    // Dead wood (deadwood.hpp): exponential mass loss of logs and of snags, per year, and FVS-FFE's
    // snag fall-rate multiplier (FALLX).
    double deadwood_decay_rate_per_yr = 0.045;
    double snag_decay_rate_per_yr = 0.015;
    double snag_fall_multiplier = 1.0;
    // Wind (windthrow.hpp): ForestGALES' species parameters (fgr species_parameters; the
    // defaults are its oak's, Creg on free-draining mineral soil with medium rooting).
    double wind_creg_n_m_per_kg = 202.4;
    double wind_mor_pa = 59e6;
    double wind_green_density_kg_per_m3 = 1158;
    double wind_knot_factor = 1.0;
    double wind_drag_c = 2.6575, wind_drag_n = 0.846;
    double wind_crown_depth_intercept_m = 1.41, wind_crown_depth_per_height = 0.4;

    /// Physiology keys that took their default (for the report).
    std::vector<std::string> defaulted;
};

/// Leaf mass per area (kg/m2) from leaf longevity (yr): Reich, Walters & Ellsworth 1997 (PNAS
/// 94:13730, Fig 1f), SLA = exp(6.15) (12 L)^-0.46 cm2/g, as LPJ and LPJ-GUESS derive it.
inline double leaf_mass_per_area_from_longevity(double longevity_yr) {
    const double sla_cm2_per_g = std::exp(6.15 - 0.46 * std::log(12.0 * longevity_yr));
    return 10.0 / sla_cm2_per_g; // 1 g/cm2 = 10 kg/m2
}

struct EcosystemDef {
    std::string name;
    std::filesystem::path source;
    std::vector<Species> species;
    std::vector<std::string> notes; ///< defaults taken, MAVS keys ignored
};

/// The diameter the allometry uses: the trunk at breast height for trees, the stem at the ground
/// for shrubs (docs/ecosystem.md s2).
inline bool measured_at_breast_height(const Species& s) {
    return s.life_form == LifeForm::tree;
}
/// Individual plants: trees and shrubs (grasses are a cover, objects are not alive).
inline bool is_individual_plant(const Species& s) {
    return s.life_form == LifeForm::tree || s.life_form == LifeForm::shrub;
}

/// The life form MAVS's keys imply (docs/ecosystem.md s1.1): a mesh under MAVS's non-plant folders
/// (buildings, misc, urban, vehicles) is an object; a plant below 0.5 m is grass or herb; below
/// 5 m a broad plant (Height To Diameter Ratio >= 0.2) is a shrub and a slender one grass; taller
/// plants are trees. `why` receives the rule that decided.
LifeForm mavs_life_form(const std::string& mesh_file, double max_height_m, double ratio,
                        std::string* why = nullptr);

/// Reads an ecosystem file. Throws InputError naming the file, the species and the key for
/// missing, out-of-range or unknown values, and for files that are not JSON.
EcosystemDef load_ecosystem(const std::filesystem::path& path);
EcosystemDef parse_ecosystem(const nlohmann::json& j, const std::string& source);

/// The species as JSON with every parameter (the resolved form stored in outputs).
nlohmann::json species_to_json(const Species& s);

/// The keys of a species entry: MAVS's own (top level, with spaces) and ecoterra's
/// "physiology" block (every key, unit, default and range).
const ParamCatalog<Species>& mavs_species_catalog();
const ParamCatalog<Species>& physiology_catalog();

} // namespace ecoterra::eco
