#include "ecoterra/eco/outputs.hpp"

#include <sstream>

namespace ecoterra::eco {

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

const std::vector<Column<YearRow>>& yearly_columns() {
    using R = YearRow;
    static const std::vector<Column<R>> c = {
        column("year", &R::year, "1", "completed simulation years", ColumnType::int64),
        column("basal_area_m2_per_ha", &R::basal_area_m2_per_ha, "m2/ha",
               "basal area of stems at breast height"),
        column("stems_per_ha", &R::stems_per_ha, "1/ha",
               "stems that reached breast height (1.3 m)"),
        column("mean_dbh_m", &R::mean_dbh_m, "m",
               "arithmetic mean trunk diameter at breast height"),
        column("quadratic_mean_dbh_m", &R::quadratic_mean_dbh_m, "m", "quadratic mean diameter Dq"),
        column("reineke_sdi_per_ha", &R::reineke_sdi_per_ha, "1/ha",
               "Reineke stand density index N (Dq/25.4 cm)^1.605"),
        column("live_plants", &R::live_plants, "1",
               "live plants, including those below breast height", ColumnType::int64),
        column("births", &R::births, "1", "recruits established this year", ColumnType::int64),
        column("deaths_starvation", &R::deaths_starvation, "1",
               "deaths by an exhausted carbohydrate reserve", ColumnType::int64),
        column("deaths_age", &R::deaths_age, "1", "deaths at the species' maximum age",
               ColumnType::int64),
        column("deaths_background", &R::deaths_background, "1", "deaths by the background rate",
               ColumnType::int64),
        column("deaths_suppression", &R::deaths_suppression, "1",
               "deaths by growth suppression (low growth efficiency)", ColumnType::int64),
        column("deaths_overlap", &R::deaths_overlap, "1", "light-only deaths by crown overlap",
               ColumnType::int64),
        column("seeds_dispersed", &R::seeds_dispersed, "1", "seeds produced and dispersed",
               ColumnType::int64),
        column("seeds_lost_outside", &R::seeds_lost_outside, "1",
               "seeds that landed outside the terrain", ColumnType::int64),
        column("production_kg", &R::production_kg, "kg", "carbohydrate produced"),
        column("maintenance_respiration_kg", &R::maintenance_respiration_kg, "kg",
               "maintenance respiration"),
        column("growth_respiration_kg", &R::growth_respiration_kg, "kg",
               "growth respiration of new wood"),
        column("recruit_carbon_kg", &R::recruit_carbon_kg, "kg",
               "carbohydrate of new recruits (from outside the balance)"),
        column("dead_carbon_kg", &R::dead_carbon_kg, "kg", "wood and reserve of plants that died"),
        column("wood_stock_kg", &R::wood_stock_kg, "kg",
               "stem dry mass of live plants at year end"),
        column("reserve_stock_kg", &R::reserve_stock_kg, "kg",
               "carbohydrate reserve of live plants at year end"),
        column("carbon_residual_kg", &R::carbon_residual_kg, "kg",
               "stock change - (production - respiration - turnover + recruits - dead); round-off "
               "only"),
        column("transpiration_demand_mm", &R::transpiration_demand_mm, "mm",
               "plant water demand over the domain"),
        column("transpiration_supplied_mm", &R::transpiration_supplied_mm, "mm",
               "plant water supplied by the soil"),
        column("turnover_kg", &R::turnover_kg, "kg",
               "carbohydrate turned over by plants at their maximum stem diameter"),
        column("shrubs_per_ha", &R::shrubs_per_ha, "1/ha", "live shrubs (not in the tree metrics)"),
        column("ground_cover_fraction", &R::ground_cover_fraction, "1",
               "mean cover of the ground layer (grasses and herbs) at year end, 0..1"),
        column("ground_transpiration_demand_mm", &R::ground_transpiration_demand_mm, "mm",
               "the ground layer's water demand over the domain"),
        column("ground_transpiration_supplied_mm", &R::ground_transpiration_supplied_mm, "mm",
               "the ground layer's water supplied (from above its roots)"),
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

} // namespace ecoterra::eco
