#include "ecoterra/eco/diagnosis.hpp"

#include "ecoterra/eco/deadwood.hpp"
#include "ecoterra/error.hpp"
#include "ecoterra/hydro/soil.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

namespace ecoterra::eco {

namespace {

using nlohmann::json;

std::string fmt(const char* f, double a) {
    char b[64];
    std::snprintf(b, sizeof b, f, a);
    return b;
}

std::string pct(double part, double whole) {
    return fmt("%.0f %%", whole > 0 ? 100.0 * part / whole : 0.0);
}

struct Factors {
    double light = 1, water = 1, soil = 1, temperature = 1;
};

Factors mean_factors(const SpeciesLedger& l) {
    if (l.samples <= 0) return {};
    return {l.light_sum / l.samples, l.water_sum / l.samples, l.soil_sum / l.samples,
            l.temperature_sum / l.samples};
}

/// The smallest growth factor: its hint key (hint()) and its value.
struct Weakest {
    const char* key;
    double value;
};
Weakest weakest(const Factors& f) {
    const std::array<Weakest, 4> a{
        {{"light", f.light}, {"water", f.water}, {"soil", f.soil}, {"temperature", f.temperature}}};
    return *std::min_element(a.begin(), a.end(),
                             [](const auto& x, const auto& y) { return x.value < y.value; });
}

/// What a user can change for a limit: "soil", "water", "temperature", "light" or "pond".
std::string hint(const std::string& key, const Species& s) {
    if (key == "soil")
        return ". Try a soil near " + hydro::texture_name(s.texture) + " at pH " +
               fmt("%.1f", s.ph.desired) +
               " (soil.uniform or soil.random) or a wider physiology.texture_tolerance_pct";
    if (key == "water")
        return ". Try a wetter climate or soil, or a lower physiology.water.desired";
    if (key == "temperature") return ". Try a warmer climate";
    if (key == "light")
        return ". Try a more shade-tolerant physiology.shade, or gaps by management";
    return "";
}

/// The soil's fit for a species, from the factors met at the establishment draws (or, without
/// draws, from its plants' soil factor).
std::string soil_text(const Species& s, const SpeciesLedger& l, const DiagnosisInput& in) {
    std::string t;
    if (l.draws > 0)
        t = "texture factor " + fmt("%.2g", l.texture_factor_sum / l.draws) + ", pH factor " +
            fmt("%.2g", l.ph_factor_sum / l.draws);
    else
        t = "soil factor " + fmt("%.2g", mean_factors(l).soil);
    return t + " (it wants " + hydro::texture_name(s.texture) + " within " +
           fmt("%.0f", s.texture_tolerance_pct) + " points at pH " + fmt("%.1f", s.ph.desired) +
           " +- " + fmt("%.1f", s.ph.tolerance) + "; the soil is mostly " + in.soil_texture +
           " at pH " + fmt("%.1f", in.soil_ph) + ")";
}

/// The limit named by `key`, with its numbers and what a user can change.
std::string limit_text(const std::string& key, const Species& s, const SpeciesLedger& l,
                       const DiagnosisInput& in) {
    const Factors f = mean_factors(l);
    std::string t;
    if (key == "soil") t = "the soil: " + soil_text(s, l, in);
    if (key == "light")
        t = l.failed_light > 0 ? "light: " + pct(l.failed_light, l.attempts) +
                                     " of its seeds landed below its germination minimum of " +
                                     fmt("%.2g", s.germination_min_light) +
                                     " of full light or in too little light to grow into a "
                                     "recruit"
                               : "light: its plants' light factor averaged " + fmt("%.2f", f.light);
    if (key == "water")
        t = l.failed_water > 0
                ? "soil water: " + pct(l.failed_water, l.attempts) +
                      " of its seeds landed on soil drier than its germination "
                      "minimum of " +
                      fmt("%.2g", s.germination_min_soil_water)
                : "soil water: its plants' water factor averaged " + fmt("%.2f", f.water);
    if (key == "pond")
        t = "standing water under " + pct(l.failed_pond, l.attempts) + " of its seeds";
    if (key == "temperature")
        t = "temperature: its factor averaged " + fmt("%.2f", f.temperature) +
            " (growth starts at " + fmt("%.3g", s.temperature_base_c) + " C, full at " +
            fmt("%.3g", s.temperature_optimum_c) + " C)";
    return t + hint(key, s);
}

/// The establishment test that stopped most seeds: "light", "water", "pond" or "soil".
std::string establishment_key(const SpeciesLedger& l) {
    const std::array<std::pair<double, const char*>, 4> f{{{l.failed_light, "light"},
                                                           {l.failed_water, "water"},
                                                           {l.failed_pond, "pond"},
                                                           {l.failed_draw, "soil"}}};
    return std::max_element(f.begin(), f.end(), [](auto& a, auto& b) { return a.first < b.first; })
        ->second;
}

std::string deaths_text(const SpeciesLedger& l) {
    double total = 0;
    int top = 0;
    for (int c = 1; c < 9; ++c) {
        total += l.deaths[c];
        if (l.deaths[c] > l.deaths[top]) top = c;
    }
    if (total <= 0) return "";
    return "; " + grouped(total) + " died (" + pct(l.deaths[top], total) + " " +
           death_cause_name(static_cast<DeathCause>(top)) + ")";
}

/// One species in a line: its seeds, recruits and survivors, and its tightest limit.
std::string species_limit(const DiagnosisInput& in, std::size_t k) {
    const Species& s = in.species[k];
    const SpeciesLedger& l = in.ledger[k];
    if (l.attempts <= 0 && l.established <= 0)
        return s.name + ": no seed reached the ground (arrivals " +
               fmt("%.3g", s.new_per_area_per_yr * 1e4) +
               " per ha a year; none of its plants matured at " + fmt("%.0f", s.maturity_age_yr) +
               " years)";
    std::string t = s.name + ": " + grouped(l.seeds_landed + l.arrivals) + " seeds (" +
                    grouped(l.arrivals) + " from outside), " + grouped(l.established) +
                    " established, " + grouped(in.living[k]) + " alive" + deaths_text(l);
    const Factors f = mean_factors(l);
    const Weakest tightest = weakest(f);
    std::string key;
    if (l.established < 0.05 * l.attempts)
        key = establishment_key(l);
    else if (l.samples > 0 && tightest.value < 0.5)
        key = tightest.key;
    if (!key.empty()) t += ". Limit: " + limit_text(key, s, l, in);
    if (l.samples > 0)
        t += ". Growth factors in leaf (1 = no limit): light " + fmt("%.2f", f.light) + ", water " +
             fmt("%.2f", f.water) + ", soil " + fmt("%.2f", f.soil) + ", temperature " +
             fmt("%.2f", f.temperature);
    return t;
}

json ledger_json(const Species& s, const SpeciesLedger& l, double living) {
    json d = json::object();
    for (int c = 1; c < 9; ++c) d[death_cause_name(static_cast<DeathCause>(c))] = l.deaths[c];
    const Factors f = mean_factors(l);
    return {{"species", s.name},
            {"living_at_end", living},
            {"seeds_landed", l.seeds_landed},
            {"seeds_lost_outside", l.seeds_lost},
            {"arrivals", l.arrivals},
            {"establishment_attempts", l.attempts},
            {"failed_light", l.failed_light},
            {"failed_soil_water", l.failed_water},
            {"failed_standing_water", l.failed_pond},
            {"failed_draw", l.failed_draw},
            {"established", l.established},
            {"mean_texture_factor", l.draws > 0 ? json(l.texture_factor_sum / l.draws) : json()},
            {"mean_ph_factor", l.draws > 0 ? json(l.ph_factor_sum / l.draws) : json()},
            {"deaths", d},
            {"growth_factor_samples", l.samples},
            {"mean_light_factor", l.samples > 0 ? json(f.light) : json()},
            {"mean_water_factor", l.samples > 0 ? json(f.water) : json()},
            {"mean_soil_factor", l.samples > 0 ? json(f.soil) : json()},
            {"mean_temperature_factor", l.samples > 0 ? json(f.temperature) : json()}};
}

} // namespace

const char* stand_verdict_name(StandVerdict v) {
    switch (v) {
    case StandVerdict::ok:
        return "ok";
    case StandVerdict::empty:
        return "empty";
    case StandVerdict::sparse:
        return "sparse";
    case StandVerdict::missed_target:
        return "missed_target";
    }
    return "?";
}

Diagnosis diagnose(const DiagnosisInput& in) {
    Diagnosis d;
    double woody = 0, living_trees = 0;
    for (std::size_t k = 0; k < in.species.size(); ++k)
        if (is_individual_plant(in.species[k])) {
            woody += in.living[k];
            if (in.species[k].life_form == LifeForm::tree) living_trees += in.living[k];
        }
    // Basal area measures a stand of trees; a shrubland (more shrubs alive than trees, as in the
    // desert) is judged by its stems alone.
    const bool tree_stand = living_trees > 0 && living_trees >= woody - living_trees;
    const double ba = in.stand.basal_area_m2_per_ha;
    const std::string after = " after " + std::to_string(in.years) + " years";
    if (in.target_basal_area_m2_per_ha && ba < kTargetShare * *in.target_basal_area_m2_per_ha) {
        d.verdict = StandVerdict::missed_target;
        const double target = *in.target_basal_area_m2_per_ha;
        const double g = in.basal_area_growth_m2_per_ha_per_yr;
        d.headline = "the target basal area of " + fmt("%.3g", target) +
                     " m2/ha was not reached: " + fmt("%.3g", ba) + " m2/ha" + after + "; ";
        d.headline += g > 0
                          ? "at the last years' " + fmt("%.2g", g) + " m2/ha a year it is about " +
                                fmt("%.0f", std::ceil((target - ba) / g)) +
                                " more years away (simulation.years)"
                          : "the basal area is not growing";
    }
    if (woody <= 0) {
        d.verdict = StandVerdict::empty;
        d.headline = "the stand is empty" + after + ": no tree or shrub is alive" +
                     (d.headline.empty() ? "" : "; " + d.headline);
    } else if (d.verdict == StandVerdict::ok && in.years >= kSparseAfterYears &&
               (woody / in.area_ha < kSparseStemsPerHa || (tree_stand && ba < kSparseBasalArea))) {
        d.verdict = StandVerdict::sparse;
        d.headline = "the stand is sparse" + after + ": " + fmt("%.0f", in.stand.stems_per_ha) +
                     " trees a hectare, basal area " + fmt("%.2f", ba) + " m2/ha";
    }
    json per = json::array();
    for (std::size_t k = 0; k < in.species.size(); ++k) {
        const Species& s = in.species[k];
        if (!is_individual_plant(s))
            continue; // grasses live in the ground layer, objects do not grow
        per.push_back(ledger_json(s, in.ledger[k], in.living[k]));
        if (d.verdict != StandVerdict::ok && !in.light_only)
            d.lines.push_back(species_limit(in, k));
    }
    d.json = {{"verdict", stand_verdict_name(d.verdict)},
              {"headline", d.headline},
              {"years", in.years},
              {"basal_area_m2_per_ha", ba},
              {"stems_per_ha", in.stand.stems_per_ha},
              {"target_basal_area_m2_per_ha",
               in.target_basal_area_m2_per_ha ? json(*in.target_basal_area_m2_per_ha) : json()},
              {"soil_texture", in.soil_texture},
              {"soil_ph", in.soil_ph},
              {"lines", d.lines},
              {"species", per}};
    return d;
}

} // namespace ecoterra::eco
