#include "ecoterra/analyses/describe.hpp"
#include "ecoterra/data_dir.hpp"
#include "ecoterra/hydro/soil_strength.hpp"
#include "ecoterra/units.hpp"

#include "ecoterra/analyses/analyses.hpp"

#include "ecoterra/catalog.hpp"
#include "ecoterra/eco/outputs.hpp"
#include "ecoterra/eco/scene_config.hpp"
#include "ecoterra/eco/species.hpp"
#include "ecoterra/hydro/scene.hpp"
#include "ecoterra/mobility/vehicle.hpp"
#include "ecoterra/run/records.hpp"
#include "ecoterra/terrain/generate.hpp"

#include <algorithm>

namespace ecoterra::analyses {

using namespace ecoterra::eco;
using run::plant_columns;
using run::stem_csv_columns;

namespace {

struct Section {
    std::string title, note;
    std::vector<std::string> header;
    std::vector<std::vector<std::string>> rows;
};

Section params(std::string title, std::string note, const std::vector<ParamInfo>& info) {
    Section s{
        std::move(title), std::move(note), {"key", "unit", "default", "range", "meaning"}, {}};
    for (const auto& i : info)
        s.rows.push_back({i.key, i.unit, i.default_value, i.range, i.description});
    return s;
}

/// An output group: columns (Column<R>) or raster layers (RasterLayer<Src>).
template <class Catalogue>
Section outputs(std::string title, std::string note, const std::string& group,
                const Catalogue& cat) {
    Section s{std::move(title), std::move(note), {"name", "unit", "type", "meaning"}, {}};
    for (const auto& i : describe(group, cat))
        s.rows.push_back({i.name, i.unit, i.type, i.description});
    return s;
}

/// An ecosystem scene's simulation keys: the hydrology scene's years and seed, then its own.
std::vector<ParamInfo> eco_simulation_params(const hydro::HydroScene& h, const EcoScene& e) {
    std::vector<ParamInfo> out;
    for (auto& i : describe(hydro::hydro_simulation_catalog(), h))
        if (i.key != "simulation.snapshot_interval_days") out.push_back(std::move(i));
    for (auto& i : describe(eco_simulation_catalog(), e)) out.push_back(std::move(i));
    return out;
}

std::vector<Section> scene_sections() {
    hydro::HydroScene h;
    EcoScene e;
    return {
        params("Scene: climate",
               "Defaults are the humid_subtropical preset's; any key overrides the preset "
               "(climate.preset, data/climates/NAME.json).",
               describe(hydro::climate_catalog(), hydro::climate_preset("humid_subtropical"))),
        params("Scene: soil.uniform", "One of soil.uniform, soil.random, soil.rasters.",
               describe(hydro::soil_composition_catalog(), hydro::SoilComposition{})),
        params("Scene: soil.random", "Perlin fields of sand, clay and pH around the mean.",
               describe(hydro::random_soil_catalog(), hydro::RandomSoilParams{})),
        params("Scene: soil.rasters", "Files relative to the scene's folder.",
               describe(hydro::soil_rasters_catalog(), hydro::SoilRasterFiles{})),
        params("Scene: vegetation (ecoterra hydro run)",
               "Ecosystem runs compute the density from their plants.",
               describe(hydro::vegetation_cover_catalog(), hydro::VegetationCover{})),
        params("Scene: hydrology", "",
               describe(hydro::hydrology_catalog(), hydro::HydrologyOptions{})),
        params("Scene: simulation (ecoterra hydro run)", "",
               describe(hydro::hydro_simulation_catalog(), h)),
        params("Scene: vegetation (ecoterra run)",
               "Besides vegetation.ecosystem (required) and vegetation.initial (docs/formats.md).",
               describe(vegetation_catalog(), e)),
        params("Scene: vegetation.initial.random (ecoterra run)", "",
               describe(initial_random_catalog(), InitialPlants{})),
        params("Scene: vegetation.windthrow (ecoterra run)",
               "Besides vegetation.windthrow.storms, a list of {year, wind_m_per_s, from_deg} "
               "(docs/formats.md).",
               describe(windthrow_catalog(), WindthrowOptions{})),
        params("Scene: simulation (ecoterra run)", "", eco_simulation_params(h, e)),
    };
}

} // namespace

std::vector<std::string> scene_keys() {
    std::vector<std::string> keys{"terrain.generate",     "terrain.file",       "climate.preset",
                                  "vegetation.ecosystem", "vegetation.initial", "soil.uniform",
                                  "climate.csv",          "soil.random",        "soil.rasters"};
    for (const auto& s : scene_sections())
        for (const auto& row : s.rows) keys.push_back(row.front());
    return keys;
}

std::string scene_key_unit(const std::string& key) {
    for (const auto& s : scene_sections())
        for (const auto& row : s.rows)
            if (row.front() == key) return row[1];
    // A generator's parameter: "terrain.generate.params.NAME" or, for a terrain base,
    // "params.NAME".
    const auto at = key.rfind("params.");
    if (at != std::string::npos) {
        const std::string name = key.substr(at);
        for (const auto& [method, info] : terrain::describe_terrain_params())
            for (const auto& i : info)
                if (i.key == name) return i.unit;
    }
    return "";
}

namespace {

std::vector<Section> species_sections() {
    const Species d;
    return {params("Species: MAVS keys",
                   "The keys of a MAVS ecosystem species, read as MAVS reads them.",
                   describe(mavs_species_catalog(), d)),
            params("Species: physiology", "ecoterra's own block; every key is optional.",
                   describe(physiology_catalog(), d))};
}

std::vector<Section> terrain_sections() {
    std::vector<Section> out;
    for (const auto& [method, info] : terrain::describe_terrain_params())
        out.push_back(params("Terrain generator: " + method, "", info));
    return out;
}

std::vector<Section> output_sections() {
    return {
        outputs("Output: snapshot plants", "One row per live plant.", "/snapshots/NNNN/plants/",
                plant_columns()),
        outputs("Output: snapshot dead wood",
                "One row per snag or log (vegetation.deadwood; `ecoterra export deadwood` writes "
                "the same columns as CSV, with species_name last).",
                "/snapshots/NNNN/deadwood/", run::deadwood_columns()),
        outputs("Output: yearly series", "One row per simulated year.", "/series/yearly/",
                yearly_columns()),
        outputs("Output: daily series", "One row per day; the water budget over the whole domain.",
                "/series/daily/", hydro::daily_budget_columns()),
        outputs("Output: soil maps",
                "Rasters [ny, nx] of hydrology and ecosystem runs (hydrology grid).", "/soil/",
                hydro::soil_map_layers()),
        outputs("Output: water state of a snapshot",
                "Rasters [ny, nx] in every snapshot of hydrology and ecosystem runs.",
                "/snapshots/NNNN/", hydro::water_state_layers()),
        [] {
            Section s{"Output: stem CSV (ecoterra export vegetation)",
                      "One row per plant.",
                      {"name", "unit", "type", "meaning"},
                      {}};
            for (const auto& c : stem_csv_columns())
                s.rows.push_back({c.name, c.unit, column_type_name(c.type), c.description});
            return s;
        }(),
        [] {
            Section s{
                "Output: analysis metrics",
                "The figures of each analysis, one name and one unit everywhere: the top-level "
                "keys of `ecoterra stand --json`, `ecoterra mobility --json`, `ecoterra "
                "terrain traverse --json` and `ecoterra terrain analyze --json` (without the "
                "analysis's prefix), and the columns of an ensemble's tables (with it).",
                {"name", "unit", "type", "meaning"},
                {}};
            for (const auto& c : describe_metrics())
                s.rows.push_back({c.name, c.unit, c.type, c.description});
            return s;
        }(),
        params("Analysis options: mobility",
               "`ecoterra mobility` and an ensemble's `analyses.mobility` (the seed is derived per "
               "member there).",
               describe(mobility_catalog(), MobilityAnalysis{})),
        params("Analysis options: traverse",
               "`ecoterra terrain traverse` and an ensemble's `analyses.traverse`.",
               describe(traverse_catalog(), TraverseAnalysis{})),
        params("Analysis options: export", "An ensemble's `analyses.export`.",
               describe(export_catalog(), ExportAnalysis{})),
        params("Analysis options: terrain",
               "`ecoterra terrain analyze` and an ensemble's `analyses.terrain`.",
               describe(terrain_catalog(), TerrainAnalysisOptions{})),
    };
}

std::string markdown(const std::vector<Section>& sections) {
    std::string out;
    for (const auto& s : sections) {
        out += "## " + s.title + "\n\n";
        if (!s.note.empty()) out += s.note + "\n\n";
        auto row = [&](const std::vector<std::string>& cells) {
            out += "|";
            for (const auto& c : cells) {
                std::string v = c;
                std::replace(v.begin(), v.end(), '|', '/');
                out += " " + v + " |";
            }
            out += "\n";
        };
        row(s.header);
        out += "|";
        for (std::size_t k = 0; k < s.header.size(); ++k) out += "---|";
        out += "\n";
        for (const auto& r : s.rows) {
            auto cells = r;
            cells[0] = "`" + cells[0] + "`";
            row(cells);
        }
        out += "\n";
    }
    return out;
}

std::string text(const std::vector<Section>& sections) {
    std::string out;
    for (const auto& s : sections) {
        out += s.title + "\n";
        if (!s.note.empty()) out += "  " + s.note + "\n";
        std::vector<std::size_t> width(s.header.size(), 0);
        for (std::size_t k = 0; k + 1 < s.header.size(); ++k) {
            width[k] = s.header[k].size();
            for (const auto& r : s.rows) width[k] = std::max(width[k], r[k].size());
        }
        auto row = [&](const std::vector<std::string>& cells) {
            out += "  ";
            for (std::size_t k = 0; k < cells.size(); ++k) {
                out += cells[k];
                if (k + 1 < cells.size()) out += std::string(width[k] - cells[k].size() + 2, ' ');
            }
            out += "\n";
        };
        row(s.header);
        for (const auto& r : s.rows) row(r);
        out += "\n";
    }
    return out;
}

/// The rating cone index's coefficients by texture class, with its value at three soil waters.
Section soil_strength_section() {
    Section s{
        "Soil strength: rating cone index by texture",
        "RCI = exp(a + b ln(mc)) psi, mc = 100 theta / bulk density the gravimetric water "
        "in per cent (Sullivan & Anderson 2000, ERDC, as the WLDAS_RCI script applies it to "
        "the STATSGO texture classes; bulk densities of Morris & Lowery 1988). Snapshots "
        "store it per cell at the water of the critical layer (hydrology.critical_layer_depth_m) "
        "as rating_cone_index_kpa (docs/mobility.md s9).",
        {"texture", "a", "b", "bulk density g/cm3", "RCI psi at theta 0.2 / 0.3 / 0.4"},
        {}};
    for (int t = 0; t < hydro::kTextureCount; ++t) {
        const auto tex = static_cast<hydro::Texture>(t);
        const auto c = hydro::cone_index_coefficients(tex);
        std::string at;
        for (const double th : {0.2, 0.3, 0.4})
            at += (at.empty() ? "" : " / ") +
                  format_number(std::round(hydro::rating_cone_index_psi(tex, th)));
        s.rows.push_back({hydro::texture_name(tex), format_number(c.a), format_number(c.b),
                          format_number(c.bulk_density_g_per_cm3), at});
    }
    return s;
}

/// The shipped vehicles' mobility index and vehicle cone indices.
Section vehicle_cone_index_section() {
    Section s{"Vehicle cone index of the shipped vehicles",
              "WES's wheeled mobility index (Priddy 1999) and VCI1, VCI50 from it (Priddy & "
              "Willoughby 2006), from each file's mass, axles, tyres, wheel radius, tyre width "
              "and clearance (docs/mobility.md s7). A mobility index at or below 0 is outside "
              "the regressions (fit to military vehicles): no VCI.",
              {"file", "mobility index", "VCI1 psi (kPa)", "VCI50 psi (kPa)"},
              {}};
    std::vector<std::filesystem::path> files;
    const auto dir = data_dir() / "vehicles";
    if (std::filesystem::is_directory(dir))
        for (const auto& e : std::filesystem::directory_iterator(dir))
            if (e.path().extension() == ".json") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    for (const auto& f : files) {
        const auto n = mobility::cone_index_needs(mobility::load_vehicle(f));
        auto both = [](double psi) {
            return std::isnan(psi) ? std::string("none (outside the regressions)")
                                   : format_number(std::round(psi * 10) / 10) + " (" +
                                         format_number(std::round(psi * kKpaPerPsi)) + ")";
        };
        s.rows.push_back({f.filename().string(),
                          format_number(std::round(n.mobility_index * 100) / 100), both(n.vci1_psi),
                          both(n.vci50_psi)});
    }
    return s;
}

std::vector<Section> vehicle_sections() {
    Section s =
        params("Vehicle files",
               "data/vehicles/*.json. Besides these, `tractive_force_n` (required): rows "
               "[speed m/s, force N], from speed 0, speeds strictly increasing, forces >= 0; "
               "linear between rows, 0 beyond the last.",
               describe(mobility::vehicle_catalog(), mobility::Vehicle{}));
    return {s, soil_strength_section(), vehicle_cone_index_section()};
}

} // namespace

std::string describe(const std::string& topic, bool md) {
    std::vector<Section> s;
    auto add = [&](std::vector<Section> more) {
        for (auto& x : more) s.push_back(std::move(x));
    };
    if (topic == "scene" || topic == "all") add(scene_sections());
    if (topic == "species" || topic == "all") add(species_sections());
    if (topic == "terrain" || topic == "all") add(terrain_sections());
    if (topic == "vehicle" || topic == "all") add(vehicle_sections());
    if (topic == "outputs" || topic == "all") add(output_sections());
    if (s.empty())
        throw InputError("describe: unknown topic '" + topic +
                         "' (scene, species, terrain, vehicle, outputs or all)");
    if (!md) return text(s);
    if (topic != "all") return markdown(s);
    return "# Parameters and output columns\n\n"
           "Every scene key, species key, terrain-generator parameter and vehicle key with its "
           "unit, default "
           "and valid range, and every output column with its unit and type. Generated from the "
           "catalogues in the code by `ecoterra describe all --markdown`; a test fails when this "
           "file and the code differ. The structure of the files (which sections exist, "
           "`terrain.generate` or `terrain.file`, `soil.*`, `vegetation.initial`) is in "
           "[formats.md](formats.md).\n\n" +
           markdown(s);
}

} // namespace ecoterra::analyses
