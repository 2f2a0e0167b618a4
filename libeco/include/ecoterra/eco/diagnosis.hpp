#pragma once
// Why a stand is what it is: per species, what happened to its seeds (the establishment tests of
// Seedbed::establishes), how its plants died, and the growth factors its plants met while in leaf
// (paper 002's light/shade, water and soil factors and the temperature factor). Kept over the
// whole run (and in its checkpoint), read at the end into a short diagnosis when the stand is
// empty, sparse or short of its target (docs/ecosystem.md s10).
#include "ecoterra/eco/species.hpp"
#include "ecoterra/eco/stand_metrics.hpp"

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

namespace ecoterra::eco {

/// One species' record over a run; every field a count or a sum (so records add).
struct SpeciesLedger {
    // Seeds: from the species' own mature plants (landed on the grid, or lost outside it) and
    // arrivals from outside at its per-area rate.
    double seeds_landed = 0, seeds_lost = 0, arrivals = 0;
    // Establishment attempts and where each failed, in the order of the tests: light at the
    // ground below the minimum, relative soil water below the minimum, standing water, too little
    // light to grow into a recruit (crown_profile shading; counted with the light's failures), and
    // the draw against germination probability x soil suitability. Objects (placed without a
    // test) count as attempts that established.
    double attempts = 0, failed_light = 0, failed_water = 0, failed_pond = 0, failed_draw = 0;
    double established = 0;
    // Sums over the attempts that reached the draw: the soil's texture and pH factors.
    double texture_factor_sum = 0, ph_factor_sum = 0, draws = 0;
    // Deaths by DeathCause (index 0 unused).
    double deaths[9] = {};
    // Growth factors met by living plants in leaf, sampled once a canopy interval.
    double samples = 0, light_sum = 0, water_sum = 0, soil_sum = 0, temperature_sum = 0;
};

/// What the diagnosis found about the stand as a whole.
enum class StandVerdict { ok, empty, sparse, missed_target };
const char* stand_verdict_name(StandVerdict v);

struct Diagnosis {
    StandVerdict verdict = StandVerdict::ok;
    std::string headline;           ///< one sentence; empty when all is well
    std::vector<std::string> lines; ///< per species, what limited it, with the numbers
    nlohmann::json json;            ///< everything, for the run file
};

/// Sparse: after at least `kSparseAfterYears`, fewer than `kSparseStemsPerHa` trees and shrubs,
/// or less than `kSparseBasalArea` of basal area where trees are at least half of the living
/// trees and shrubs (a shrubland, such as the desert's creosote scrub, is judged by its stems
/// alone). These are
/// ecoterra's thresholds for a warning (a tenth of the stem counts and basal areas the shipped
/// ecosystems grow by then), not measured figures.
inline constexpr int kSparseAfterYears = 20;
inline constexpr double kSparseStemsPerHa = 100;
inline constexpr double kSparseBasalArea = 2.0;
/// A target is missed when the basal area at the end is below this share of it.
inline constexpr double kTargetShare = 0.95;

/// What diagnose() reads; it refers to the species and ledgers (they must outlive it).
struct DiagnosisInput {
    const std::vector<Species>& species;
    const std::vector<SpeciesLedger>& ledger;
    std::vector<double> living; ///< living plants per species at the end
    StandMetrics stand;
    int years = 0;
    std::optional<double> target_basal_area_m2_per_ha;
    double basal_area_growth_m2_per_ha_per_yr = 0; ///< over the last 5 years (or fewer)
    bool light_only = false;
    double area_ha = 1;
    std::string soil_texture; ///< the terrain's most common USDA texture class
    double soil_ph = 0;       ///< the terrain's mean soil pH
};

Diagnosis diagnose(const DiagnosisInput& in);

} // namespace ecoterra::eco
