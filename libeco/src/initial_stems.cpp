// The initial stems of a scene (vegetation.initial): random stems or a stem file (processes.hpp).
#include "ecoterra/csv.hpp"
#include "ecoterra/eco/processes.hpp"
#include "ecoterra/error.hpp"
#include "ecoterra/units.hpp"

#include <algorithm>
#include <cmath>

namespace ecoterra::eco {

namespace {
/// Stem files: the age and diameter a listed stem may have.
constexpr double kMaxStemAgeYr = 10000;
constexpr double kMaxStemDbhCm = 500;

/// Random stems of the trees and shrubs (the ground layer starts bare; objects arrive), uniform
/// over the plant grid, diameters uniform in [recruit dbh, max dbh].
std::vector<Plant> random_stems(const EcoScene& scene, const GridSpec& g, const Nursery& nursery) {
    const auto& species = scene.ecosystem.species;
    const auto& ini = scene.initial;
    Rng rng(scene.seed, "eco.initial");
    const double area_ha = g.width_m() * g.height_m() / kM2PerHa;
    const std::int64_t n = std::llround(ini.stems_per_ha * area_ha);
    std::vector<std::uint16_t> plants;
    for (std::size_t k = 0; k < species.size(); ++k)
        if (is_individual_plant(species[k])) plants.push_back(static_cast<std::uint16_t>(k));
    if (n > 0 && plants.empty())
        throw InputError("vegetation.initial: random stems need a tree or shrub species in " +
                         scene.ecosystem.source.string());
    std::vector<Plant> out;
    for (std::int64_t k = 0; k < n; ++k) {
        const auto sp = plants[static_cast<std::size_t>(rng.below(plants.size()))];
        const double x = g.origin_x_m + rng.uniform() * g.width_m();
        const double y = g.origin_y_m + rng.uniform() * g.height_m();
        const Species& s = species[sp];
        const double d = rng.uniform(s.recruit_dbh_m, std::max(ini.max_dbh_m, s.recruit_dbh_m));
        Plant p = nursery.make(sp, x, y, d);
        if (scene.competition == Competition::light_only &&
            scene.light_only_model == LightOnlyModel::mavs) {
            allometry::apply(s, p); // the height of this diameter, and its age on MAVS's curve
            p.age_yr = std::floor(mavs_age_yr(s, p.height_m));
        } else if (scene.competition == Competition::light_only) {
            // Age that gives this diameter on the light-only growth curve.
            p.age_yr = light_only_age_yr(s, d);
            p.dbh_m = light_only_dbh_m(s, p.age_yr);
            allometry::apply(s, p);
        }
        out.push_back(p);
    }
    return out;
}

/// The species a stem file names (by name or mesh file), a tree or a shrub.
std::uint16_t stem_species(const EcosystemDef& eco, const std::string& name,
                           const std::string& where) {
    int sp = -1;
    for (std::size_t k = 0; k < eco.species.size(); ++k)
        if (eco.species[k].name == name || eco.species[k].mesh_file == name)
            sp = static_cast<int>(k);
    if (sp < 0)
        throw InputError(where + ": species '" + name + "' is not in " + eco.source.string());
    const Species& s = eco.species[static_cast<std::size_t>(sp)];
    if (!is_individual_plant(s))
        throw InputError(where + ": species '" + name + "' is a " + life_form_name(s.life_form) +
                         ", not a tree or shrub: it has no stem to list");
    return static_cast<std::uint16_t>(sp);
}

/// A stem file: CSV with columns x_m, y_m, species, dbh_cm and optionally age_yr, in any order.
std::vector<Plant> listed_stems(const EcoScene& scene, const GridSpec& g, const Nursery& nursery) {
    const auto& file = scene.initial.file;
    CsvReader csv(file, "initial plant list");
    const int cx = csv.require("x_m"), cy = csv.require("y_m"), cs = csv.require("species"),
              cd = csv.require("dbh_cm"), ca = csv.column("age_yr");
    std::vector<Plant> out;
    while (csv.next()) {
        const std::string where = csv.where();
        const double x = csv.number(cx, "x_m"), y = csv.number(cy, "y_m");
        const double dcm = csv.number(cd, "dbh_cm");
        // age_yr may be left out of a row (0: a stem without a known age).
        const double age = ca >= 0 && ca < csv.fields() ? csv.number(ca, "age_yr") : 0.0;
        if (age < 0 || age > kMaxStemAgeYr)
            throw InputError(where + ": age_yr = " + csv.text(ca) + " is outside [0, " +
                             format_number(kMaxStemAgeYr) + "]");
        if (!g.contains_point(x, y))
            throw InputError(where + ": position (" + format_number(x) + ", " + format_number(y) +
                             ") m is outside the terrain");
        if (!(dcm > 0 && dcm < kMaxStemDbhCm))
            throw InputError(where + ": dbh_cm = " + csv.text(cd) + " is outside (0, " +
                             format_number(kMaxStemDbhCm) + ")");
        const std::uint16_t sp = stem_species(scene.ecosystem, csv.text(cs), where);
        Plant p = nursery.make(sp, x, y, dcm / kCmPerM);
        p.age_yr = age;
        if (scene.competition == Competition::light_only) {
            p.dbh_m = dcm / kCmPerM;
            allometry::apply(scene.ecosystem.species[sp], p);
        }
        out.push_back(p);
    }
    return out;
}
} // namespace

std::vector<Plant> initial_stems(const EcoScene& scene, const GridSpec& plant_grid,
                                 const Nursery& nursery) {
    switch (scene.initial.kind) {
    case InitialPlants::Kind::random:
        return random_stems(scene, plant_grid, nursery);
    case InitialPlants::Kind::file:
        return listed_stems(scene, plant_grid, nursery);
    case InitialPlants::Kind::bare:
        break;
    }
    return {};
}

} // namespace ecoterra::eco
