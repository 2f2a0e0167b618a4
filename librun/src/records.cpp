#include "ecoterra/run/records.hpp"

#include <sstream>

namespace ecoterra::run {

using eco::LifeForm;

PlantRecord plant_record(const Plant& p, const Species& s) {
    PlantRecord r;
    r.id = p.id;
    r.species = p.species;
    r.life_form = static_cast<std::int32_t>(s.life_form);
    r.x_m = p.x_m;
    r.y_m = p.y_m;
    r.z_m = p.z_m;
    r.height_m = p.height_m;
    r.dbh_m = measured_at_breast_height(s) ? p.dbh_m : 0.0;
    r.stem_diameter_m = p.dbh_m;
    r.crown_radius_m = p.crown_radius_m;
    r.age_yr = p.age_yr;
    r.carbohydrate_kg = p.reserve_kg;
    return r;
}

const std::vector<Column<PlantRecord>>& plant_columns() {
    using R = PlantRecord;
    static const std::vector<Column<R>> c = {
        column("id", &R::id, "1", "plant id, unique within the run", ColumnType::int64),
        column("species", &R::species, "1", "index into /species of the run file",
               ColumnType::int32),
        column("x_m", &R::x_m, "m", "stem position, east"),
        column("y_m", &R::y_m, "m", "stem position, north"),
        column("z_m", &R::z_m, "m", "ground elevation at the stem"),
        column("height_m", &R::height_m, "m", "plant height"),
        column("life_form", &R::life_form, "1",
               "0 tree, 1 shrub, 3 object (grasses are the ground layer, not plants); "
               "/species/life_form names them",
               ColumnType::int32),
        column("dbh_m", &R::dbh_m, "m",
               "trunk diameter at breast height (1.3 m) of a tree; 0 below it and for shrubs and "
               "objects"),
        column("stem_diameter_m", &R::stem_diameter_m, "m",
               "stem diameter: a tree's at breast height, a shrub's at the ground, an object's "
               "footprint"),
        column("crown_radius_m", &R::crown_radius_m, "m", "crown (and root) radius"),
        column("age_yr", &R::age_yr, "yr", "age"),
        column("carbohydrate_kg", &R::carbohydrate_kg, "kg", "carbohydrate reserve"),
    };
    return c;
}

namespace {
std::string number_text(double v) {
    std::ostringstream s;
    s.precision(10);
    s << v;
    return s.str();
}
} // namespace

const std::vector<StemCsvColumn>& stem_csv_columns() {
    using R = PlantRecord;
    using N = std::vector<std::string>;
    static const std::vector<StemCsvColumn> c = {
        {"id", "", "plant id (joins the row to the snapshot's plants/id)", ColumnType::int64,
         [](const R& r, const N&) { return std::to_string(r.id); }},
        {"x_m", "m", "stem position, east", ColumnType::float64,
         [](const R& r, const N&) { return number_text(r.x_m); }},
        {"y_m", "m", "stem position, north", ColumnType::float64,
         [](const R& r, const N&) { return number_text(r.y_m); }},
        {"z_m", "m", "ground elevation at the stem", ColumnType::float64,
         [](const R& r, const N&) { return number_text(r.z_m); }},
        {"species", "", "species name (the ecosystem's Species Name)", ColumnType::text,
         [](const R& r, const N& names) {
             const auto sp = static_cast<std::size_t>(r.species);
             return sp < names.size() ? names[sp] : std::to_string(sp);
         }},
        {"species_index", "", "0-based index of the species in the run (plants/species)",
         ColumnType::int32, [](const R& r, const N&) { return std::to_string(r.species); }},
        {"life_form", "", "tree, shrub or object (grasses are the ground layer, not listed)",
         ColumnType::text,
         [](const R& r, const N&) {
             return std::string(life_form_name(static_cast<LifeForm>(r.life_form)));
         }},
        {"dbh_cm", "cm", "trunk diameter at breast height (0 below it, and for shrubs and objects)",
         ColumnType::float64, [](const R& r, const N&) { return number_text(r.dbh_m * 100.0); }},
        {"stem_diameter_cm", "cm",
         "stem diameter: a tree's at breast height, a shrub's or an object's at the ground",
         ColumnType::float64,
         [](const R& r, const N&) { return number_text(r.stem_diameter_m * 100.0); }},
        {"height_m", "m", "plant height", ColumnType::float64,
         [](const R& r, const N&) { return number_text(r.height_m); }},
        {"crown_radius_m", "m", "crown radius", ColumnType::float64,
         [](const R& r, const N&) { return number_text(r.crown_radius_m); }},
    };
    return c;
}

std::string stem_csv(const std::vector<PlantRecord>& plants,
                     const std::vector<std::string>& species) {
    const auto& cols = stem_csv_columns();
    std::string out;
    for (std::size_t k = 0; k < cols.size(); ++k) out.append(k ? "," : "").append(cols[k].name);
    out += '\n';
    for (const auto& p : plants) {
        for (std::size_t k = 0; k < cols.size(); ++k)
            out.append(k ? "," : "").append(cols[k].text(p, species));
        out += '\n';
    }
    return out;
}

} // namespace ecoterra::run
