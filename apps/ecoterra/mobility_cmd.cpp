// `ecoterra mobility`: speed made good through a stand (a run's snapshot, or a stem list over a
// DEM).
#include "common.hpp"
#include "subcommands.hpp"

#include "ecoterra/analyses/analyses.hpp"
#include "ecoterra/hydro/soil.hpp"
#include "ecoterra/hydro/soil_strength.hpp"
#include "ecoterra/io/atomic_file.hpp"
#include "ecoterra/io/staging.hpp"
#include "ecoterra/mobility/map.hpp"
#include "ecoterra/mobility/route.hpp"
#include "ecoterra/mobility/stand.hpp"
#include "ecoterra/mobility/traverse.hpp"
#include "ecoterra/run/pictures.hpp"
#include "ecoterra/run/run_reader.hpp"
#include "ecoterra/run/season.hpp"
#include "ecoterra/terrain/analysis.hpp"
#include "ecoterra/terrain/io/raster_io.hpp"
#include "ecoterra/terrain/missions.hpp"
#include "ecoterra/units.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>

namespace ecoterra::app {

namespace {

using nlohmann::json;

struct MobilityArgs {
    // Defaults of the mobility analysis's catalogue (analyses.hpp), as an ensemble's.
    std::string run, stems, deadwood, dem, vehicle, json_out, layout = "random", pictures;
    std::string effects = "both";
    bool no_pictures = false, force = false, no_deadwood = false, no_soil = false;
    int snapshot = -1, lines = analyses::MobilityAnalysis{}.lines;
    long long seed = 1;
    double length_m = analyses::MobilityAnalysis{}.length_m;
};

/// Where pictures go: --pictures DIR, else NAME.pictures beside --json NAME.json, else nowhere.
std::filesystem::path picture_dir(const std::string& given, bool none,
                                  const std::string& json_file) {
    if (none) return {};
    if (!given.empty()) return given;
    if (json_file.empty()) return {};
    std::filesystem::path p(json_file);
    return p.parent_path() / (p.stem().string() + ".pictures");
}

/// The stand to drive through: a run's snapshot (with its dead wood unless --no-deadwood), or a
/// stem list (and a dead-wood list) over a DEM.
struct StandInput {
    std::vector<mobility::StandStem> stems; ///< snags included
    mobility::StandDeadWood dead;
    RasterD dem;
    json source;
    std::optional<run::SnapshotGround> ground; ///< the snapshot's soil and standing water
};

StandInput read_stand_input(const MobilityArgs& a) {
    StandInput in;
    auto& [stems, dead, dem, source, ground] = in;
    if (!a.run.empty()) {
        const auto s = run::read_snapshot_plants(a.run, a.snapshot);
        stems = run::stand_stems(s.plants);
        if (!a.no_deadwood)
            dead = run::stand_deadwood(run::read_snapshot_deadwood(a.run, s.index).pieces);
        dem = terrain::io::read_hdf5(a.run, terrain::io::kRunTerrainDataset);
        source = {{"run", a.run}, {"snapshot", s.index}, {"year", s.year}};
        if (!a.no_soil) ground = run::read_snapshot_ground(a.run, s.index, dem.grid());
    } else {
        stems = mobility::read_stem_csv(a.stems);
        if (!a.deadwood.empty()) dead = mobility::read_deadwood_csv(a.deadwood);
        std::vector<std::string> warnings;
        dem = terrain::io::read_raster(a.dem, &warnings);
        print_warnings(warnings);
        source = {{"stems", a.stems}, {"dem", a.dem}};
        if (!a.deadwood.empty()) source["deadwood"] = a.deadwood;
    }
    source["deadwood_included"] = a.run.empty() ? !a.deadwood.empty() : !a.no_deadwood;
    stems.insert(stems.end(), dead.snags.begin(), dead.snags.end());
    mobility::carve_pits(dem, dead.pits); // the root plates' pits are ground the vehicle meets
    return in;
}

/// The ground lines of the report: the snapshot's rating cone index against the vehicle's needs,
/// and its standing water against the fording depth.
void print_ground(const StandInput& in, const mobility::Vehicle& v,
                  const mobility::ConeIndexNeeds& needs) {
    if (!in.ground) return;
    if (in.ground->rci_kpa && !v.cone_index_defaults.empty()) {
        std::string keys;
        for (const auto& k : v.cone_index_defaults) keys += (keys.empty() ? "" : ", ") + k;
        std::printf("soil: the vehicle file gives no %s: the defaults (ecoterra describe vehicle) "
                    "are taken\n",
                    keys.c_str());
    }
    if (const auto& rci = in.ground->rci_kpa) {
        const auto [lo, hi] = std::minmax_element(rci->data(), rci->data() + rci->size());
        if (needs.calibrated)
            std::printf("soil: rating cone index %.0f-%.0f kPa against VCI1 %.0f kPa (VCI50 %.0f); "
                        "soft soil slows the vehicle (Brixius)\n",
                        *lo, *hi, needs.vci1_kpa(), needs.vci50_kpa());
        else
            std::printf("soil: rating cone index %.0f-%.0f kPa; no VCI1 (the vehicle's mobility "
                        "index %.2f is outside the regressions): soft soil slows or stops it by "
                        "Brixius's traction alone\n",
                        *lo, *hi, needs.mobility_index);
    }
    if (const auto& w = in.ground->water_depth_m) {
        const double deepest = *std::max_element(w->data(), w->data() + w->size());
        std::printf("water: standing water up to %.3g m against a fording depth of %.3g m%s\n",
                    deepest, v.fording_depth(),
                    v.fording_depth_m ? "" : " (none given: the ground clearance)");
    }
}

/// The combinations of inputs `ecoterra mobility` refuses.
void check_mobility_inputs(const MobilityArgs& a) {
    if (a.run.empty() == a.stems.empty())
        throw InputError("mobility: give a run file, or --stems FILE.csv with --dem");
    if (!a.stems.empty() && a.dem.empty())
        throw InputError("mobility: --stems needs --dem (the terrain the stems stand on)");
    if (!a.deadwood.empty() && a.stems.empty())
        throw InputError("mobility: --deadwood goes with --stems (a run brings its own dead wood)");
    if (!a.deadwood.empty() && a.no_deadwood)
        throw InputError("mobility: --deadwood and --no-deadwood contradict each other");
}

void run_mobility(const MobilityArgs& a) {
    check_mobility_inputs(a);
    if (!a.json_out.empty()) {
        std::vector<std::string> inputs{a.vehicle};
        for (const auto& p : {a.run, a.stems, a.deadwood, a.dem})
            if (!p.empty()) inputs.push_back(p);
        refuse_output_over_input("--json", a.json_out, inputs);
        claim_output("--json", a.json_out, a.force);
        io::AtomicOutput probe(a.json_out); // the folder exists: fail now, not after the lines
    }
    claim_output("--pictures", picture_dir(a.pictures, a.no_pictures, a.json_out).string(),
                 a.force);
    const mobility::Vehicle v = mobility::load_vehicle(a.vehicle);
    mobility::StandLinesOptions opt;
    opt.lines = a.lines;
    opt.seed = static_cast<std::uint64_t>(a.seed);
    opt.length_m = a.length_m;
    if (a.layout == "transects")
        opt.layout = mobility::LineLayout::transects;
    else if (a.layout != "random")
        throw InputError("--layout must be random or transects, got '" + a.layout + "'");
    opt.effects = mobility::StemEffects::both;
    bool known = false;
    for (const auto& [name, e] : mobility::stem_effects_names())
        if (name == a.effects) opt.effects = e, known = true;
    if (!known)
        throw InputError("--effects must be both, override_only or avoidance_only, got '" +
                         a.effects + "'");
    StandInput in = read_stand_input(a);
    const mobility::ConeIndexNeeds needs = mobility::cone_index_needs(v);
    if (in.ground) opt.smg.ground = in.ground->maps();
    in.source["soil_strength_applied"] = in.ground && in.ground->rci_kpa.has_value();
    in.source["standing_water_applied"] = in.ground && in.ground->water_depth_m.has_value();
    auto& stems = in.stems;
    const auto& dead = in.dead;
    const RasterD& dem = in.dem;
    json& source = in.source;
    Stopwatch sw;
    const auto m = with_context(a.run.empty() ? a.stems : a.run, [&] {
        return mobility::analyse_stand(v, stems, dem, opt, dead.logs);
    });
    const double seconds = sw.seconds();
    std::string others;
    if (m.shrubs > 0) others += ", " + std::to_string(m.shrubs) + " shrubs";
    if (m.objects > 0) others += ", " + std::to_string(m.objects) + " objects";
    if (m.snags > 0) others += ", " + std::to_string(m.snags) + " snags";
    if (m.logs > 0) others += ", " + std::to_string(m.logs) + " logs";
    std::printf("%s through %lld trees%s on %.4g ha: basal area %.2f m2/ha (%.1f ft2/acre); "
                "critical diameter %.2f cm\n",
                v.name.c_str(), static_cast<long long>(m.trees), others.c_str(), m.area_ha,
                m.basal_area_m2_per_ha, m.basal_area_m2_per_ha * kFt2PerAcrePerM2PerHa,
                m.critical_diameter_m * kCmPerM);
    std::printf("%d lines of %.4g m: SMG mean %.3f m/s, median %.3f, p10 %.3f, p90 %.3f; NOGO "
                "%.1f %%; distance overriding %.1f %%, detouring %.1f %%\n",
                opt.lines, opt.length_m, m.smg_mean_m_per_s, m.smg_median_m_per_s,
                m.smg_p10_m_per_s, m.smg_p90_m_per_s, 100 * m.nogo_fraction,
                100 * m.override_fraction, 100 * m.detour_fraction);
    if (m.logs > 0)
        std::printf("logs: %.2f climbed per 100 m (step limit %.2f m), %.2f too high across each "
                    "line\n",
                    m.log_crossings_per_100m, m.step_limit_m, m.logs_avoided_per_line);
    print_ground(in, v, needs);
    std::printf("%.3f s (%.3g lines/s)\n", seconds, opt.lines / std::max(seconds, 1e-9));
    if (!a.json_out.empty()) {
        json j = analyses::mobility_json(m, v);
        j["source"] = source;
        j["lines_layout"] = a.layout;
        j["effects"] = a.effects;
        j["line_length_m"] = opt.length_m;
        j["seed"] = opt.seed;
        j["provenance"] = provenance();
        io::write_text_atomic(a.json_out, j.dump(2) + "\n");
        std::printf("wrote %s\n", a.json_out.c_str());
    }
    const auto pics = picture_dir(a.pictures, a.no_pictures, a.json_out);
    if (!pics.empty()) {
        run::draw_mobility_pictures(m, v, dem, pics);
        std::printf("pictures: %s/{smg_lines,smg_histogram}.png\n", pics.string().c_str());
    }
}

struct MapArgs {
    MobilityArgs in; ///< the stand and ground (run or stem list), the vehicle, --force
    std::string output, soil_moisture, texture, water_depth;
    double cell_m = 0;
    int headings = mobility::MapOptions{}.headings;
    int year = 0;        ///< the snapshot of this year (0: --snapshot's); with --season, its days
    bool season = false; ///< every day of the year, replayed from the run
};

/// USDA classes whose silt + clay is mostly 50 % or more (the USCS's fine-grained soils): their
/// share of sand in the textural triangle lies mostly below 50 %.
bool texture_fine_grained(hydro::Texture t) {
    using T = hydro::Texture;
    return t == T::loam || t == T::silt_loam || t == T::silt || t == T::clay_loam ||
           t == T::silty_clay_loam || t == T::silty_clay || t == T::clay;
}

/// A raster given beside --dem that must cover it cell for cell.
RasterD read_beside_dem(const std::string& option, const std::string& file, const RasterD& dem,
                        const std::string& dem_file) {
    std::vector<std::string> warnings;
    RasterD r = terrain::io::read_raster(file, &warnings);
    print_warnings(warnings);
    const GridSpec &g = r.grid(), &d = dem.grid();
    const double tol = 1e-6 * d.cell_size_m;
    if (g.nx != d.nx || g.ny != d.ny || std::abs(g.cell_size_m - d.cell_size_m) > tol ||
        std::abs(g.origin_x_m - d.origin_x_m) > tol || std::abs(g.origin_y_m - d.origin_y_m) > tol)
        throw InputError(option + " " + file + ": " + std::to_string(g.nx) + " x " +
                         std::to_string(g.ny) + " cells of " + format_number(g.cell_size_m) +
                         " m from (" + format_number(g.origin_x_m) + ", " +
                         format_number(g.origin_y_m) + ") does not cover the DEM " + dem_file +
                         " (" + std::to_string(d.nx) + " x " + std::to_string(d.ny) + " cells of " +
                         format_number(d.cell_size_m) + " m from (" + format_number(d.origin_x_m) +
                         ", " + format_number(d.origin_y_m) + ")) cell for cell");
    return r;
}

/// The ground of a stem list's map: the rating cone index from --soil-moisture and --texture,
/// and --water-depth.
run::SnapshotGround ground_beside_dem(const MapArgs& a, const RasterD& dem) {
    run::SnapshotGround g;
    if (!a.soil_moisture.empty()) {
        const auto tex = hydro::parse_texture(a.texture);
        if (!tex) throw InputError("--texture: '" + a.texture + "' is not a USDA texture class");
        RasterD theta = read_beside_dem("--soil-moisture", a.soil_moisture, dem, a.in.dem);
        for (int j = 0; j < theta.ny(); ++j)
            for (int i = 0; i < theta.nx(); ++i) {
                const double t = theta(i, j);
                if (!(t >= 0 && t <= 1) && !std::isnan(t))
                    throw InputError("--soil-moisture " + a.soil_moisture + ": cell (" +
                                     std::to_string(i) + ", " + std::to_string(j) + ") holds " +
                                     format_number(t) +
                                     ", not a volumetric water content "
                                     "(0-1 m3/m3)");
                theta(i, j) = std::isnan(t) ? t : hydro::rating_cone_index_kpa(*tex, t);
            }
        g.rci_kpa = std::move(theta);
        g.fine_grained = RasterU8(dem.grid(), texture_fine_grained(*tex) ? 1 : 0);
    }
    if (!a.water_depth.empty()) {
        RasterD w = read_beside_dem("--water-depth", a.water_depth, dem, a.in.dem);
        for (int j = 0; j < w.ny(); ++j)
            for (int i = 0; i < w.nx(); ++i)
                if (w(i, j) < 0)
                    throw InputError("--water-depth " + a.water_depth + ": cell (" +
                                     std::to_string(i) + ", " + std::to_string(j) + ") holds " +
                                     format_number(w(i, j)) + " m, below 0");
        g.water_depth_m = std::move(w);
    }
    return g;
}

void check_map_inputs(const MapArgs& a) {
    check_mobility_inputs(a.in);
    if ((a.season || a.year != 0) && a.in.run.empty())
        throw InputError("mobility map: --year and --season need a run file");
    if (a.year < 0)
        throw InputError("mobility map: --year " + std::to_string(a.year) + " is not a year");
    if (!a.in.run.empty() && (!a.soil_moisture.empty() || !a.water_depth.empty()))
        throw InputError("mobility map: --soil-moisture and --water-depth go with --stems (a run "
                         "brings its own soil water)");
    if (a.soil_moisture.empty() != a.texture.empty())
        throw InputError("mobility map: --soil-moisture and --texture go together");
    std::vector<std::string> inputs{a.in.vehicle};
    for (const auto& p :
         {a.in.run, a.in.stems, a.in.deadwood, a.in.dem, a.soil_moisture, a.water_depth})
        if (!p.empty()) inputs.push_back(p);
    refuse_output_over_input("-o", a.output, inputs);
    claim_output("-o", a.output, a.in.force);
}

/// A heading in a layer's name: whole degrees, three digits ("045"), as the map writes them and
/// the route reads them.
std::string heading_tag(double deg) {
    char text[16];
    std::snprintf(text, sizeof text, "%03.0f", deg);
    return text;
}

/// Writes `r` as the GeoTIFF `name` of the folder and lists it (file, units, what) in `layers`.
void write_layer(io::OutputFolder& folder, json& layers, const RasterD& r, const std::string& name,
                 const std::string& units, const std::string& what) {
    terrain::io::write_geotiff(r, folder.staged_path(name), units);
    layers.push_back({{"file", name}, {"units", units}, {"what", what}});
}

/// A categorical raster as GeoTIFF values (its nodata code as NaN).
RasterD codes(const RasterU8& r) {
    RasterD out(r.grid());
    out.set_crs_wkt(r.crs_wkt());
    for (int j = 0; j < r.ny(); ++j)
        for (int i = 0; i < r.nx(); ++i)
            out(i, j) = r(i, j) == static_cast<std::uint8_t>(mobility::Limit::nodata) ? std::nan("")
                                                                                      : r(i, j);
    return out;
}

/// Writes the map's layers, summary and pictures into `folder`; returns the layers' names.
json write_map(const mobility::MobilityMap& m, const RasterD& dem, bool pictures,
               io::OutputFolder& folder) {
    json layers = json::array();
    const auto layer = [&](const RasterD& r, const std::string& name, const std::string& units,
                           const std::string& what) {
        write_layer(folder, layers, r, name, units, what);
    };
    layer(m.speed_mean_m_per_s, "speed_mean_m_per_s.tif", "m/s",
          "mean over the headings of the steady speed across the cell (NO-GO as 0)");
    layer(m.go_fraction, "go_fraction.tif", "1", "share of the headings that are GO");
    layer(codes(m.limiting), "limiting_factor.tif", "code",
          "the factor that limits most headings: 0 none, 1 slope, 2 soil, 3 vegetation, 4 "
          "water, 5 obstacle");
    for (std::size_t h = 0; h < m.headings_deg.size(); ++h) {
        const std::string deg = heading_tag(m.headings_deg[h]);
        layer(m.speed_m_per_s[h], std::string("speed_") + deg + "deg_m_per_s.tif", "m/s",
              std::string("steady speed heading ") + deg + " deg (clockwise from north)");
        layer(codes(m.limit[h]), std::string("limit_") + deg + "deg.tif", "code",
              std::string("limiting factor heading ") + deg + " deg");
    }
    layer(m.rci_kpa, "rating_cone_index_kpa.tif", "kPa",
          "the soil strength the map used (NaN: firm ground, not modelled)");
    layer(m.water_depth_m, "water_depth_m.tif", "m", "the standing water the map used");
    if (pictures)
        run::draw_mobility_map_pictures(m, dem, folder.staged_path("speed.png"),
                                        folder.staged_path("limiting_factor.png"));
    return layers;
}

void run_season_map(const MapArgs& a, const mobility::Vehicle& v);

void run_mobility_map(const MapArgs& given) {
    check_map_inputs(given);
    const mobility::Vehicle v = mobility::load_vehicle(given.in.vehicle);
    if (given.season) return run_season_map(given, v);
    MapArgs a = given;
    if (a.year != 0) a.in.snapshot = run::snapshot_of_year(a.in.run, a.year);
    StandInput in = read_stand_input(a.in);
    if (a.in.run.empty() && (!a.soil_moisture.empty() || !a.water_depth.empty()))
        in.ground = ground_beside_dem(a, in.dem);
    mobility::MapOptions opt;
    opt.cell_m = a.cell_m;
    opt.headings = a.headings;
    io::OutputFolder folder(a.output, a.in.force);
    Stopwatch sw;
    const mobility::GroundMaps ground = in.ground ? in.ground->maps() : mobility::GroundMaps{};
    const auto m = with_context(a.in.run.empty() ? a.in.stems : a.in.run, [&] {
        return mobility::mobility_map(v, in.dem, in.stems, in.dead.logs, ground, opt);
    });
    const double seconds = sw.seconds();
    const double cell_headings = static_cast<double>(m.grid.size()) * m.headings_deg.size();
    std::printf("%s map of %d x %d cells of %.4g m, %zu headings: mean speed %.3f m/s (top "
                "%.3f); GO in %.1f %% of cell-headings, %.1f %% of cells in some heading\n",
                v.name.c_str(), m.grid.nx, m.grid.ny, m.grid.cell_size_m, m.headings_deg.size(),
                m.mean_speed_m_per_s, m.top_speed_m_per_s, 100 * m.go_share, 100 * m.any_go_share);
    std::string shares;
    for (int k = 0; k < mobility::kLimitKinds; ++k) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "%s%s %.1f %%", k ? ", " : "",
                      mobility::limit_name(static_cast<mobility::Limit>(k)),
                      100 * m.limit_share[static_cast<std::size_t>(k)]);
        shares += buf;
    }
    std::printf("limiting factor (cell-headings): %s\n", shares.c_str());
    print_ground(in, v, mobility::cone_index_needs(v));
    std::printf("%.3f s (%.3g cell-headings/s)\n", seconds,
                cell_headings / std::max(seconds, 1e-9));
    json j = mobility::to_json(m);
    j["layers"] = write_map(m, in.dem, !a.in.no_pictures, folder);
    j["vehicle"] = mobility::to_json(v);
    j["vehicle_cone_index"] = {{"vci1_kpa", mobility::cone_index_needs(v).vci1_kpa()},
                               {"fording_depth_m", v.fording_depth()}};
    in.source["soil_strength_applied"] = in.ground && in.ground->rci_kpa.has_value();
    in.source["standing_water_applied"] = in.ground && in.ground->water_depth_m.has_value();
    if (!a.soil_moisture.empty())
        in.source["soil_moisture"] = a.soil_moisture, in.source["texture"] = a.texture;
    if (!a.water_depth.empty()) in.source["water_depth"] = a.water_depth;
    j["source"] = in.source;
    j["seconds"] = seconds;
    j["provenance"] = provenance();
    folder.write("summary.json", j.dump(2) + "\n");
    folder.commit();
    std::printf("wrote %s/{summary.json, speed_mean_m_per_s.tif, go_fraction.tif, "
                "limiting_factor.tif, ...}%s\n",
                a.output.c_str(), a.in.no_pictures ? "" : " and speed.png, limiting_factor.png");
}

/// The median of a raster's finite cells (NaN when none is).
double raster_median(const RasterD& r) {
    std::vector<double> v;
    for (int j = 0; j < r.ny(); ++j)
        for (int i = 0; i < r.nx(); ++i)
            if (std::isfinite(r(i, j))) v.push_back(r(i, j));
    if (v.empty()) return std::nan("");
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
    return v[v.size() / 2];
}

/// Writes the season's layers and pictures; returns the layers' list.
json write_season(const mobility::MapSeason& season, const json& days, bool pictures,
                  io::OutputFolder& folder) {
    json layers = json::array();
    const auto layer = [&](const RasterD& r, const std::string& name, const std::string& units,
                           const std::string& what) {
        write_layer(folder, layers, r, name, units, what);
    };
    const RasterD go = season.go_share_of_days();
    layer(go, "go_share_of_days.tif", "1", "share of the year's days GO in at least one heading");
    layer(season.speed_quantile_m_per_s(0.5), "speed_median_m_per_s.tif", "m/s",
          "median over the days of the day's mean speed over the headings (NO-GO as 0)");
    layer(season.speed_quantile_m_per_s(0.1), "speed_p10_m_per_s.tif", "m/s",
          "10th percentile over the days of the day's mean speed over the headings");
    if (!pictures) return layers;
    terrain::Image img = terrain::colormap_image(go, 0.0, 1.0);
    terrain::MapFigure f;
    f.title = "Share of the year's days GO (" + std::to_string(season.days()) + " days)";
    f.bar_label = "share of days GO";
    f.smooth = false;
    terrain::write_map_figure(img, go.grid(), f, folder.staged_path("season_go_share.png"));
    run::PlotSeries speed{"mean speed over the map (m/s)", {}, {}, {}, {}};
    run::PlotSeries share{"GO share of cell-headings x 10", {}, {}, {}, {}};
    run::PlotSeries rain{"rain (cm)", {}, {}, {}, {}};
    for (const auto& d : days) {
        const double x = d["day_of_year"].get<double>();
        speed.x.push_back(x), speed.y.push_back(d["mean_speed_m_per_s"].get<double>());
        share.x.push_back(x), share.y.push_back(10 * d["go_share_of_cell_headings"].get<double>());
        rain.x.push_back(x), rain.y.push_back(d["rain_mm"].get<double>() / 10);
    }
    run::draw_line_plot({speed, share, rain}, "The year day by day", "day of year",
                        "m/s; GO share x 10; rain (cm)", "the map's daily means",
                        folder.staged_path("season_daily.png"));
    return layers;
}

/// One day of a season's summary: its rain, the map's figures and the ground's extremes.
json season_day(const run::SeasonDay& d, const mobility::MobilityMap& m) {
    const RasterD& w = *d.water_depth_m;
    return {{"day_of_year", d.day_of_year},
            {"rain_mm", d.weather->rain_mm},
            {"mean_speed_m_per_s", m.mean_speed_m_per_s},
            {"go_share_of_cell_headings", m.go_share},
            {"go_share_of_cells_any_heading", m.any_go_share},
            {"rating_cone_index_median_kpa", raster_median(*d.rci_kpa)},
            {"standing_water_max_m", *std::max_element(w.data(), w.data() + w.size())}};
}

void run_season_map(const MapArgs& a, const mobility::Vehicle& v) {
    mobility::MapOptions opt;
    opt.cell_m = a.cell_m;
    opt.headings = a.headings;
    io::OutputFolder folder(a.output, a.in.force);
    mobility::MapSeason season;
    run::SeasonStand stand;
    std::optional<mobility::MapPlan> plan;
    json days = json::array();
    Stopwatch sw;
    double map_seconds = 0;
    run::replay_season(
        a.in.run, a.year,
        [&](const run::SeasonStand& s) {
            stand = s;
            if (!a.in.no_deadwood) {
                stand.stems.insert(stand.stems.end(), s.dead.snags.begin(), s.dead.snags.end());
                mobility::carve_pits(stand.dem, s.dead.pits);
            } else
                stand.dead = {};
            // The stand is the year's start's all year: its lanes are laid out once.
            Stopwatch t;
            plan.emplace(v, stand.dem, stand.stems, stand.dead.logs, opt);
            map_seconds += t.seconds();
        },
        [&](const run::SeasonDay& d) {
            mobility::GroundMaps g;
            if (!a.in.no_soil) {
                g.rci_kpa = d.rci_kpa;
                g.water_depth_m = d.water_depth_m;
                g.fine_grained = &stand.fine_grained;
            }
            Stopwatch t;
            const auto m =
                mobility::mobility_map(v, stand.dem, stand.stems, stand.dead.logs, g, opt);
            map_seconds += t.seconds();
            season.add(m);
            days.push_back(season_day(d, m));
        });
    const double seconds = sw.seconds();
    double go_days = 0, worst = 1;
    for (const auto& d : days) {
        go_days += d["go_share_of_cell_headings"].get<double>();
        worst = std::min(worst, d["go_share_of_cell_headings"].get<double>());
    }
    std::printf("%s, year %d day by day (%d days, replayed from year %d): GO in %.1f %% of "
                "cell-headings on the mean day, %.1f %% on the worst\n",
                v.name.c_str(), stand.year, season.days(), stand.replayed_from,
                100 * go_days / std::max<std::size_t>(days.size(), 1), 100 * worst);
    std::printf("%.3f s: %.3f s growing and stepping the days, %.3f s for %d maps (%.3g "
                "cell-headings/s)\n",
                seconds, seconds - map_seconds, map_seconds, season.days(),
                static_cast<double>(season.go_share_of_days().grid().size()) * a.headings *
                    season.days() / std::max(map_seconds, 1e-9));
    json j;
    j["season"] = {
        {"year", stand.year}, {"days", season.days()}, {"replayed_from_year", stand.replayed_from}};
    j["cell_size_m"] = season.go_share_of_days().grid().cell_size_m;
    j["headings"] = a.headings;
    j["days"] = days;
    j["layers"] = write_season(season, days, !a.in.no_pictures, folder);
    j["vehicle"] = mobility::to_json(v);
    j["source"] = {{"run", a.in.run},
                   {"deadwood_included", !a.in.no_deadwood},
                   {"soil_strength_applied", !a.in.no_soil},
                   {"standing_water_applied", !a.in.no_soil}};
    j["seconds"] = seconds;
    j["provenance"] = provenance();
    folder.write("summary.json", j.dump(2) + "\n");
    folder.commit();
    std::printf("wrote %s/{summary.json, go_share_of_days.tif, speed_median_m_per_s.tif, "
                "speed_p10_m_per_s.tif}%s\n",
                a.output.c_str(),
                a.in.no_pictures ? "" : " and season_go_share.png, season_daily.png");
}

struct RouteArgs {
    std::string map, from, to, json_out;
    bool no_pictures = false, force = false;
};

/// "X,Y" in metres.
mobility::Point parse_point(const std::string& option, const std::string& text) {
    const auto comma = text.find(',');
    double x = 0, y = 0;
    std::size_t ex = 0, ey = 0;
    try {
        if (comma == std::string::npos) throw std::invalid_argument("");
        x = std::stod(text.substr(0, comma), &ex);
        y = std::stod(text.substr(comma + 1), &ey);
    } catch (const std::exception&) {
        ex = 0;
    }
    if (ex == 0 || ex != comma || ey != text.size() - comma - 1 || !std::isfinite(x) ||
        !std::isfinite(y))
        throw InputError(option + " '" + text + "' is not X,Y (m, the map's frame)");
    return {x, y};
}

void run_route(const RouteArgs& a) {
    const std::filesystem::path dir = a.map;
    const std::filesystem::path summary = dir / "summary.json";
    if (!std::filesystem::exists(summary))
        throw InputError("route: " + a.map +
                         " holds no summary.json (give the folder of "
                         "`ecoterra mobility map -o`)");
    const json s = parse_json(io::read_text(summary), summary.string());
    if (!s.contains("headings_deg"))
        throw InputError("route: " + summary.string() +
                         " has no headings_deg (a --season folder "
                         "holds no speeds per heading)");
    const auto headings = s["headings_deg"].get<std::vector<double>>();
    std::vector<RasterD> speed;
    for (const double h : headings) {
        speed.push_back(
            terrain::io::read_raster(dir / ("speed_" + heading_tag(h) + "deg_m_per_s.tif")));
    }
    const mobility::Point from = parse_point("--from", a.from), to = parse_point("--to", a.to);
    if (!a.json_out.empty()) {
        refuse_output_over_input("--json", a.json_out, {summary.string()});
        claim_output("--json", a.json_out, a.force);
    }
    Stopwatch sw;
    const mobility::Route r = mobility::fastest_route(speed, headings, from, to);
    const double seconds = sw.seconds();
    if (r.found)
        std::printf("route: %.1f s over %.1f m (straight %.1f m, speed made good %.3f m/s), %zu "
                    "cells\n",
                    r.time_s, r.length_m, r.straight_m, r.smg_m_per_s(), r.path.size());
    else
        std::printf("route: none: the goal cannot be reached from the start over GO cells\n");
    std::printf("%.3f s (%.3g cells/s)\n", seconds,
                static_cast<double>(speed.front().grid().size()) / std::max(seconds, 1e-9));
    if (a.json_out.empty()) return;
    json pts = json::array();
    for (const auto& p : r.path) pts.push_back({p.x_m, p.y_m});
    const json j = {{"map", a.map},
                    {"from_m", {from.x_m, from.y_m}},
                    {"to_m", {to.x_m, to.y_m}},
                    {"found", r.found},
                    {"time_s", r.time_s},
                    {"length_m", r.length_m},
                    {"straight_m", r.straight_m},
                    {"smg_m_per_s", r.smg_m_per_s()},
                    {"path_m", pts},
                    {"provenance", provenance()}};
    io::write_text_atomic(a.json_out, j.dump(2) + "\n");
    std::printf("wrote %s\n", a.json_out.c_str());
    if (!a.no_pictures) {
        std::filesystem::path png = a.json_out;
        png.replace_extension(".png");
        io::AtomicOutput out(png);
        run::draw_route_picture(terrain::io::read_raster(dir / "speed_mean_m_per_s.tif"),
                                s.value("top_speed_m_per_s", 1.0), r, out.temp_path());
        out.commit();
        std::printf("picture: %s\n", png.string().c_str());
    }
}

void add_route_command(CLI::App* mobility_cmd) {
    auto a = std::make_shared<RouteArgs>();
    CLI::App* c = mobility_cmd->add_subcommand(
        "route", "the fastest route over a mobility map (least time over its 8 headings)");
    c->add_option("map", a->map, "folder of `ecoterra mobility map -o`")->required();
    c->add_option("--from", a->from, "X,Y: the start, m in the map's frame")->required();
    c->add_option("--to", a->to, "X,Y: the goal, m in the map's frame")->required();
    c->add_option("--json", a->json_out,
                  "write the route (cells, time, length) as JSON and its picture as NAME.png");
    c->add_flag("--no-pictures", a->no_pictures, "write no picture");
    add_force_flag(c, a->force);
    c->callback([a] { run_route(*a); });
}

/// `ecoterra mobility map`'s options.
void add_map_command(CLI::App* mobility_cmd) {
    auto a = std::make_shared<MapArgs>();
    CLI::App* c = mobility_cmd->add_subcommand(
        "map", "a mobility map: per cell and heading the steady speed, GO/NO-GO and what limits "
               "it (slope, soil, vegetation, water, obstacle) as GeoTIFF layers and pictures");
    MobilityArgs& in = a->in;
    c->add_option("run", in.run,
                  "ecosystem run file (its snapshot's plants, dead wood, soil "
                  "and standing water, and its terrain)");
    c->add_option("--snapshot", in.snapshot, "snapshot of the run (negative: from the last)")
        ->capture_default_str();
    c->add_option("--year", a->year,
                  "the snapshot of this year; with --season the year replayed (default: the "
                  "run's last)");
    c->add_flag("--season", a->season,
                "every day of the year: replays it from the run (deterministically, nothing "
                "written to the run) and writes per cell the share of days GO and the median and "
                "10th-percentile speed");
    c->add_option("--stems", in.stems, "stem list CSV instead of a run (as `ecoterra mobility`)");
    c->add_option("--deadwood", in.deadwood, "dead-wood list CSV with --stems");
    c->add_option("--dem", in.dem, "terrain raster under the stem list");
    c->add_option("--soil-moisture", a->soil_moisture,
                  "with --stems: root-zone water raster (m3/m3) on the DEM's grid");
    c->add_option("--texture", a->texture, "with --soil-moisture: the USDA texture class");
    c->add_option("--water-depth", a->water_depth,
                  "with --stems: standing water raster (m) on the DEM's grid");
    c->add_flag("--no-deadwood", in.no_deadwood, "leave out the run's dead wood");
    c->add_flag("--no-soil", in.no_soil,
                "firm, dry ground: leave out the snapshot's soil strength and standing water");
    c->add_option("--vehicle", in.vehicle, "vehicle file (data/vehicles/*.json)")->required();
    c->add_option("--cell", a->cell_m,
                  "map cell, m: a whole multiple of the terrain's (default: the terrain's)");
    c->add_option("--headings", a->headings, "headings, evenly spaced from north")
        ->capture_default_str();
    c->add_option("-o,--output", a->output, "output folder")->required();
    c->add_flag("--no-pictures", in.no_pictures, "write no pictures");
    add_force_flag(c, in.force);
    c->callback([a] { run_mobility_map(*a); });
}

struct TraverseArgs {
    std::string dem, vehicle, missions, json_out, pictures;
    bool no_pictures = false, force = false, allow_fewer = false;
    // Defaults of the traverse analysis's catalogue (analyses.hpp), as an ensemble's.
    double speed = analyses::TraverseAnalysis{}.speed_m_per_s;
    int count = analyses::TraverseAnalysis{}.missions;
    long long seed = 1;
};

void run_traverse(const TraverseArgs& a) {
    if (!a.json_out.empty()) {
        refuse_output_over_input("--json", a.json_out, {a.dem, a.vehicle, a.missions});
        claim_output("--json", a.json_out, a.force);
        io::AtomicOutput probe(a.json_out);
    }
    claim_output("--pictures", picture_dir(a.pictures, a.no_pictures, a.json_out).string(),
                 a.force);
    const mobility::Vehicle v = mobility::load_vehicle(a.vehicle);
    std::vector<std::string> warnings;
    const RasterD dem = terrain::io::read_raster(a.dem, &warnings);
    print_warnings(warnings);
    std::vector<mobility::MissionLine> missions;
    if (!a.missions.empty()) {
        missions = mobility::read_missions_csv(a.missions);
    } else {
        // Majhor & Bos (paper 000)'s missions on this terrain, as `ecoterra terrain missions` plans
        // them.
        terrain::MissionOptions mo;
        mo.count = a.count;
        mo.seed = static_cast<std::uint64_t>(a.seed);
        mo.allow_fewer = a.allow_fewer;
        for (const auto& m : terrain::plan_missions(dem, terrain::AnalysisOptions{}, mo))
            missions.push_back({m.id, m.start_x_m, m.start_y_m, m.goal_x_m, m.goal_y_m});
    }
    mobility::TraverseOptions opt;
    opt.speed_m_per_s = a.speed;
    opt.allow_no_missions = a.allow_fewer && a.missions.empty();
    Stopwatch sw;
    const auto rep = with_context(a.missions.empty() ? a.dem : a.missions, [&] {
        return mobility::traverse_missions(v, dem, missions, opt);
    });
    const double seconds = sw.seconds();
    std::printf("%s over %s: %d of %zu missions succeed (%.1f %%); medians of the successful: RMS "
                "vertical acceleration %.3f m/s2, RMS pitch rate %.2f deg/s, RMS roll rate %.2f "
                "deg/s, time %.2f s\n",
                v.name.c_str(), a.dem.c_str(), rep.successes, rep.results.size(),
                100 * rep.success_rate, rep.median_rms_vertical_acceleration_m_per_s2,
                rep.median_rms_pitch_rate_deg_per_s, rep.median_rms_roll_rate_deg_per_s,
                rep.median_time_s);
    std::printf("%.3f s (%.3g missions/s)\n", seconds,
                static_cast<double>(rep.results.size()) / std::max(seconds, 1e-9));
    if (!a.json_out.empty()) {
        json doc = analyses::traverse_json(rep, v);
        doc["dem"] = a.dem;
        doc["missions_file"] = a.missions;
        doc["provenance"] = provenance();
        io::write_text_atomic(a.json_out, doc.dump(2) + "\n");
        std::printf("wrote %s\n", a.json_out.c_str());
    }
    const auto pics = picture_dir(a.pictures, a.no_pictures, a.json_out);
    if (!pics.empty()) {
        run::draw_traverse_picture(missions, rep.results, dem, pics);
        std::printf("picture: %s/missions.png\n", pics.string().c_str());
    }
}

} // namespace

void add_mobility_command(CLI::App& app) {
    auto t = std::make_shared<TraverseArgs>();
    CLI::App* tr = app.get_subcommand("terrain")->add_subcommand(
        "traverse", "drive missions over a terrain: success, RMS vertical acceleration, pitch and "
                    "roll rates (a quasi-static proxy of Majhor & Bos (paper 000)'s simulator)");
    tr->add_option("dem", t->dem, "terrain raster")->required();
    tr->add_option("--vehicle", t->vehicle, "vehicle file (data/vehicles/*.json)")->required();
    tr->add_option("--missions", t->missions,
                   "missions CSV (ecoterra terrain missions); default: plan Majhor & Bos (paper "
                   "000)'s missions");
    tr->add_option("--count", t->count, "missions to plan without --missions")
        ->capture_default_str();
    tr->add_option("--seed", t->seed, "seed of the planned missions")->capture_default_str();
    tr->add_flag("--allow-fewer", t->allow_fewer,
                 "planned missions: drive those found when the terrain has room for fewer");
    tr->add_option("--speed", t->speed, "driving speed, m/s (default: the vehicle's top speed)");
    tr->add_option("--json", t->json_out, "write the figures and every mission as JSON");
    tr->add_option("--pictures", t->pictures,
                   "picture folder (default: NAME.pictures beside --json NAME.json)");
    tr->add_flag("--no-pictures", t->no_pictures, "write no picture");
    add_force_flag(tr, t->force);
    tr->callback([t] { run_traverse(*t); });

    auto a = std::make_shared<MobilityArgs>();
    CLI::App* m = app.add_subcommand(
        "mobility", "speed made good of a vehicle through a stand (NRMM-style override and "
                    "avoidance)");
    m->add_option("run", a->run, "ecosystem run file (its snapshot's plants and its terrain)");
    m->add_option("--snapshot", a->snapshot, "snapshot of the run (negative: from the last)")
        ->capture_default_str();
    m->add_option("--stems", a->stems,
                  "stem list CSV (x_m, y_m, dbh_cm or dbh_m, optional height_m, life_form with "
                  "stem_diameter_cm) instead of a run");
    m->add_option("--deadwood", a->deadwood,
                  "dead-wood list CSV (`ecoterra export deadwood`) with --stems: snags and logs");
    m->add_flag("--no-deadwood", a->no_deadwood,
                "leave out the run's dead wood (the living stand only)");
    m->add_flag("--no-soil", a->no_soil,
                "drive on firm, dry ground: leave out the snapshot's soil strength (otherwise "
                "NO-GO below the vehicle's VCI1 and slower on soft soil) and standing water "
                "(otherwise NO-GO over the fording depth)");
    m->add_option("--dem", a->dem, "terrain raster under the stem list");
    m->add_option("--vehicle", a->vehicle, "vehicle file (data/vehicles/*.json); required");
    m->add_option("--lines", a->lines, "number of straight lines")->capture_default_str();
    m->add_option("--length", a->length_m, "length of each line, m")->capture_default_str();
    m->add_option("--layout", a->layout,
                  "random (random positions and headings) | transects (parallel, west to east)")
        ->capture_default_str();
    m->add_option("--seed", a->seed, "seed of the random lines")->capture_default_str();
    m->add_option("--effects", a->effects,
                  "both | override_only (only the stems below the critical diameter) | "
                  "avoidance_only (only those at or above it, and objects): take the slowing "
                  "apart")
        ->capture_default_str();
    m->add_option("--json", a->json_out, "write the figures and every line as JSON");
    m->add_option("--pictures", a->pictures,
                  "picture folder (default: NAME.pictures beside --json NAME.json)");
    m->add_flag("--no-pictures", a->no_pictures, "write no pictures");
    add_force_flag(m, a->force);
    add_map_command(m);
    add_route_command(m);
    m->callback([a, m] {
        if (m->got_subcommand("map") || m->got_subcommand("route")) return;
        if (a->vehicle.empty()) throw InputError("mobility: --vehicle is required");
        run_mobility(*a);
    });
}

} // namespace ecoterra::app
