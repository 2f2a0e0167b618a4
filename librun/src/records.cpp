#include "ecoterra/run/records.hpp"

#include "ecoterra/csv.hpp"

#include <cmath>
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

DeadWoodRecord deadwood_record(const eco::DeadStem& d, const Species& s) {
    namespace dw = eco::deadwood;
    DeadWoodRecord r;
    const bool plate = d.piece == static_cast<std::uint8_t>(eco::PieceKind::root_plate);
    // A root plate has no wood: it stays whole (class 1) until it goes.
    const int cls = plate ? 1 : dw::decay_class(d.mass0_kg > 0 ? d.mass_kg / d.mass0_kg : 0.0);
    r.id = d.id;
    r.species = d.species;
    r.standing = d.standing;
    r.piece = d.piece;
    r.cause = d.cause;
    r.decay_class = cls;
    r.year_died = d.year_died;
    r.year_down = d.year_down;
    r.x_m = d.x_m;
    r.y_m = d.y_m;
    r.z_m = d.z_m;
    r.dbh_m = d.dbh_m;
    r.tree_height_m = d.tree_height_m;
    r.length_m = d.length_m;
    r.azimuth_rad = d.standing ? 0.0 : d.azimuth_rad;
    r.end_x_m = d.x_m + (d.standing ? 0.0 : d.length_m * std::cos(d.azimuth_rad));
    r.end_y_m = d.y_m + (d.standing ? 0.0 : d.length_m * std::sin(d.azimuth_rad));
    // A lying piece's top above the ground: the stem's diameter where the piece starts along it
    // (slash: the cut top) and at its end, sunk with the class.
    r.height_m = d.standing ? d.length_m
                            : dw::stem_diameter_m(d.dbh_m, d.tree_height_m, d.offset_m) *
                                  dw::log_collapse(cls);
    r.end_height_m = d.standing
                         ? d.length_m
                         : dw::stem_diameter_m(d.dbh_m, d.tree_height_m, d.offset_m + d.length_m) *
                               dw::log_collapse(cls);
    if (plate) r.height_m = r.end_height_m = eco::root_plate_diameter_m(d.dbh_m); // on edge
    r.mass_kg = d.mass_kg;
    r.volume_m3 = dw::volume_m3(s, d);
    return r;
}

const std::vector<Column<DeadWoodRecord>>& deadwood_columns() {
    using R = DeadWoodRecord;
    using T = ColumnType;
    static const std::vector<Column<R>> c = {
        column("id", &R::id, "1", "plant id of the tree that died", T::int64),
        column("species", &R::species, "1", "index into /species of the run file", T::int32),
        column("standing", &R::standing, "1",
               "1 standing (a snag or stump), 0 lying (a log or slash)", T::int32),
        column("piece", &R::piece, "1",
               "0 a whole stem (snag, then log), 1 the stump of a cut tree, 2 a top lying apart "
               "(the slash of a cut tree, the top of a storm-broken one), 3 the standing lower "
               "stem of a storm-broken tree (a snag, then a log), 4 the root plate of an "
               "uprooted tree (on edge at the stem base, toward the wind; no wood mass)",
               T::int32),
        column("cause", &R::cause, "1",
               "cause of death: 1 starvation, 2 age, 3 background, 4 suppression, 5 overlap, 6 "
               "harvest, 7 uprooted by a storm, 8 broken by a storm",
               T::int32),
        column("decay_class", &R::decay_class, "1",
               "1 (sound) .. 5, from the share of the mass left (0.9, 0.7, 0.4, 0.2)", T::int32),
        column("year_died", &R::year_died, "yr", "simulation year in which the tree died",
               T::int32),
        column("year_down", &R::year_down, "yr", "year the snag fell; -1 while standing", T::int32),
        column("x_m", &R::x_m, "m", "the piece's base (slash: its thick end), east"),
        column("y_m", &R::y_m, "m", "the piece's base, north"),
        column("z_m", &R::z_m, "m", "ground elevation at the stem base"),
        column("end_x_m", &R::end_x_m, "m",
               "a lying piece's far end, east (a snag or stump: its base)"),
        column("end_y_m", &R::end_y_m, "m",
               "a lying piece's far end, north (a snag or stump: its base)"),
        column("dbh_m", &R::dbh_m, "m",
               "the tree's diameter at breast height at death; the stem tapers linearly from "
               "1.3 m to 0 at the tree's height (slash starts where it is 10.16 cm)"),
        column("tree_height_m", &R::tree_height_m, "m", "the tree's height at death"),
        column("length_m", &R::length_m, "m",
               "a snag's or stump's standing height, a log's or slash's length"),
        column("azimuth_rad", &R::azimuth_rad, "rad",
               "a lying piece's direction from base to far end, counterclockwise from east (a "
               "snag or stump: 0)"),
        column("height_m", &R::height_m, "m",
               "height above the ground: a snag's or stump's top; a lying piece's top at its "
               "base (its diameter there, less as it collapses in decay classes 3-5)"),
        column("end_height_m", &R::end_height_m, "m",
               "height above the ground of a lying piece's top at its far end (a snag or stump: "
               "its top)"),
        column("mass_kg", &R::mass_kg, "kg", "dry mass left"),
        column("volume_m3", &R::volume_m3, "m3",
               "volume: mass over the decay class's density (Domke et al. 2011)"),
    };
    return c;
}

std::string deadwood_csv(const std::vector<DeadWoodRecord>& pieces,
                         const std::vector<std::string>& species) {
    const auto& cols = deadwood_columns();
    std::string out;
    for (std::size_t k = 0; k < cols.size(); ++k) out.append(k ? "," : "").append(cols[k].name);
    out += ",species_name\n";
    for (const auto& p : pieces) {
        for (std::size_t k = 0; k < cols.size(); ++k) {
            const double v = cols[k].get(p);
            out.append(k ? "," : "")
                .append(cols[k].type == ColumnType::float64
                            ? number_text(v)
                            : std::to_string(static_cast<long long>(v)));
        }
        const auto sp = static_cast<std::size_t>(p.species);
        out.append(",")
            .append(csv_field(sp < species.size() ? species[sp] : std::to_string(sp)))
            .append("\n");
    }
    return out;
}

std::string stem_csv(const std::vector<PlantRecord>& plants,
                     const std::vector<std::string>& species) {
    const auto& cols = stem_csv_columns();
    std::string out;
    for (std::size_t k = 0; k < cols.size(); ++k) out.append(k ? "," : "").append(cols[k].name);
    out += '\n';
    for (const auto& p : plants) {
        for (std::size_t k = 0; k < cols.size(); ++k)
            out.append(k ? "," : "")
                .append(cols[k].type == ColumnType::text ? csv_field(cols[k].text(p, species))
                                                         : cols[k].text(p, species));
        out += '\n';
    }
    return out;
}

nlohmann::ordered_json stem_records_json(const std::vector<PlantRecord>& plants,
                                         const std::vector<std::string>& species) {
    const auto& cols = stem_csv_columns();
    nlohmann::ordered_json out = nlohmann::ordered_json::array();
    for (const auto& p : plants) {
        nlohmann::ordered_json r = nlohmann::ordered_json::object();
        for (const auto& c : cols) {
            const std::string t = c.text(p, species);
            if (c.type == ColumnType::text)
                r[c.name] = t;
            else if (c.type == ColumnType::float64)
                r[c.name] = std::stod(t);
            else
                r[c.name] = std::stoll(t);
        }
        out.push_back(std::move(r));
    }
    return out;
}

nlohmann::ordered_json deadwood_records_json(const std::vector<DeadWoodRecord>& pieces,
                                             const std::vector<std::string>& species) {
    const auto& cols = deadwood_columns();
    nlohmann::ordered_json out = nlohmann::ordered_json::array();
    for (const auto& p : pieces) {
        nlohmann::ordered_json r = nlohmann::ordered_json::object();
        for (const auto& c : cols) {
            const double v = c.get(p);
            if (c.type == ColumnType::float64)
                r[c.name] = v;
            else
                r[c.name] = static_cast<long long>(v);
        }
        const auto sp = static_cast<std::size_t>(p.species);
        r["species_name"] = sp < species.size() ? species[sp] : std::to_string(sp);
        out.push_back(std::move(r));
    }
    return out;
}

} // namespace ecoterra::run
