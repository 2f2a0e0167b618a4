// `ecoterra mobility`: speed made good through a stand (a run's snapshot, or a stem list over a
// DEM).
#include "common.hpp"
#include "subcommands.hpp"

#include "ecoterra/analyses/analyses.hpp"
#include "ecoterra/io/atomic_file.hpp"
#include "ecoterra/mobility/stand.hpp"
#include "ecoterra/mobility/traverse.hpp"
#include "ecoterra/run/pictures.hpp"
#include "ecoterra/run/run_reader.hpp"
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
    std::optional<RasterD> rci_kpa; ///< the snapshot's soil strength (runs that store it)
};

StandInput read_stand_input(const MobilityArgs& a) {
    StandInput in;
    auto& [stems, dead, dem, source, rci] = in;
    if (!a.run.empty()) {
        const auto s = run::read_snapshot_plants(a.run, a.snapshot);
        stems = run::stand_stems(s.plants);
        if (!a.no_deadwood)
            dead = run::stand_deadwood(run::read_snapshot_deadwood(a.run, s.index).pieces);
        dem = terrain::io::read_hdf5(a.run, terrain::io::kRunTerrainDataset);
        source = {{"run", a.run}, {"snapshot", s.index}, {"year", s.year}};
        if (!a.no_soil) rci = run::read_snapshot_soil(a.run, s.index, dem.grid());
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
    return in;
}

/// The soil line of the report: the snapshot's rating cone index against the vehicle's needs,
/// or why it was not applied.
void print_soil(const StandInput& in, const mobility::StandLinesOptions& opt,
                const mobility::Vehicle& v, const mobility::ConeIndexNeeds& needs) {
    if (in.rci_kpa && !v.cone_index_defaults.empty()) {
        std::string keys;
        for (const auto& k : v.cone_index_defaults) keys += (keys.empty() ? "" : ", ") + k;
        std::printf("soil: the vehicle file gives no %s: the defaults (ecoterra describe vehicle) "
                    "are taken\n",
                    keys.c_str());
    }
    if (opt.smg.rating_cone_index_kpa) {
        const auto [lo, hi] =
            std::minmax_element(in.rci_kpa->data(), in.rci_kpa->data() + in.rci_kpa->size());
        std::printf("soil: rating cone index %.0f-%.0f kPa against VCI1 %.0f kPa (VCI50 %.0f)\n",
                    *lo, *hi, needs.vci1_kpa(), needs.vci50_kpa());
    } else if (in.rci_kpa) {
        std::printf(
            "soil: not applied (the vehicle's mobility index %.2f is outside the cone-index "
            "regressions)\n",
            needs.mobility_index);
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
    StandInput in = read_stand_input(a);
    const mobility::ConeIndexNeeds needs = mobility::cone_index_needs(v);
    in.source["soil_strength_applied"] = in.rci_kpa && mobility::use_soil(opt.smg, *in.rci_kpa, v);
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
    print_soil(in, opt, v, needs);
    std::printf("%.3f s (%.3g lines/s)\n", seconds, opt.lines / std::max(seconds, 1e-9));
    if (!a.json_out.empty()) {
        json j = analyses::mobility_json(m, v);
        j["source"] = source;
        j["lines_layout"] = a.layout;
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

struct TraverseArgs {
    std::string dem, vehicle, missions, json_out, pictures;
    bool no_pictures = false, force = false;
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
        for (const auto& m : terrain::plan_missions(dem, terrain::AnalysisOptions{}, mo))
            missions.push_back({m.id, m.start_x_m, m.start_y_m, m.goal_x_m, m.goal_y_m});
    }
    mobility::TraverseOptions opt;
    opt.speed_m_per_s = a.speed;
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
                    "roll rates (a kinematic proxy of Majhor & Bos (paper 000)'s simulator)");
    tr->add_option("dem", t->dem, "terrain raster")->required();
    tr->add_option("--vehicle", t->vehicle, "vehicle file (data/vehicles/*.json)")->required();
    tr->add_option("--missions", t->missions,
                   "missions CSV (ecoterra terrain missions); default: plan Majhor & Bos (paper "
                   "000)'s missions");
    tr->add_option("--count", t->count, "missions to plan without --missions")
        ->capture_default_str();
    tr->add_option("--seed", t->seed, "seed of the planned missions")->capture_default_str();
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
                "drive on firm ground: leave out the snapshot's soil strength (a cell whose "
                "rating cone index is below the vehicle's VCI1 is otherwise NO-GO)");
    m->add_option("--dem", a->dem, "terrain raster under the stem list");
    m->add_option("--vehicle", a->vehicle, "vehicle file (data/vehicles/*.json)")->required();
    m->add_option("--lines", a->lines, "number of straight lines")->capture_default_str();
    m->add_option("--length", a->length_m, "length of each line, m")->capture_default_str();
    m->add_option("--layout", a->layout,
                  "random (random positions and headings) | transects (parallel, west to east)")
        ->capture_default_str();
    m->add_option("--seed", a->seed, "seed of the random lines")->capture_default_str();
    m->add_option("--json", a->json_out, "write the figures and every line as JSON");
    m->add_option("--pictures", a->pictures,
                  "picture folder (default: NAME.pictures beside --json NAME.json)");
    m->add_flag("--no-pictures", a->no_pictures, "write no pictures");
    add_force_flag(m, a->force);
    m->callback([a] { run_mobility(*a); });
}

} // namespace ecoterra::app
