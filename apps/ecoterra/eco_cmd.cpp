// `ecoterra run`, `ecoterra stand`, `ecoterra export vegetation` and `ecoterra export deadwood`.
#include "common.hpp"
#include "subcommands.hpp"

#include "ecoterra/analyses/analyses.hpp"
#include "ecoterra/analyses/describe.hpp"
#include "ecoterra/eco/stand_metrics.hpp"
#include "ecoterra/io/atomic_file.hpp"
#include "ecoterra/json_util.hpp"
#include "ecoterra/run/run.hpp"
#include "ecoterra/run/run_reader.hpp"
#include "ecoterra/terrain/io/raster_io.hpp"

#include <array>
#include <cstdio>
#include <memory>
#include <optional>
#include <sstream>

namespace ecoterra::app {

namespace {

/// One line of shrubs and objects and one of the ground layer, when the run has them.
void print_undergrowth(const eco::UndergrowthMetrics& u, const std::vector<std::string>& names) {
    if (u.shrubs_per_ha > 0 || u.objects_per_ha > 0)
        std::printf("undergrowth: %.1f shrubs/ha (crowns cover %.1f %%, mean height %.2f m), %.1f "
                    "objects/ha\n",
                    u.shrubs_per_ha, 100 * u.shrub_crown_cover_fraction, u.shrub_mean_height_m,
                    u.objects_per_ha);
    if (u.ground_cover_by_species.empty()) return;
    std::string list;
    for (const auto& c : u.ground_cover_by_species) {
        char buf[160];
        std::snprintf(buf, sizeof buf, "%s%s %.1f %%", list.empty() ? "" : ", ",
                      c.species < static_cast<int>(names.size())
                          ? names[static_cast<std::size_t>(c.species)].c_str()
                          : "?",
                      100 * c.fraction);
        list += buf;
    }
    std::printf("ground layer: %.1f %% cover (%s)\n", 100 * u.ground_cover_fraction, list.c_str());
}

using nlohmann::json;
namespace fs = std::filesystem;

struct RunArgs {
    std::string scene, output = "run.h5", resume, pictures_dir;
    std::optional<int> years;
    std::optional<std::uint64_t> seed;
    std::vector<std::string> sets;
    bool no_pictures = false, force = false;
    bool strict = false;       ///< exit 3 when the diagnosis finds the stand empty, sparse or short
    bool output_given = false; ///< -o was on the command line (even with its default value)
};

/// The scene of `run`, with its --set, --seed and --years overrides (none with --resume alone).
std::optional<eco::EcoScene> run_scene(const RunArgs& a, std::vector<std::string>& sets) {
    if (a.seed) sets.push_back("simulation.seed=" + std::to_string(*a.seed));
    if (a.scene.empty()) {
        if (!sets.empty())
            throw InputError("run --resume: --set and --seed need the scene file too (and then "
                             "must not change it)");
        return std::nullopt;
    }
    json j = parse_json(io::read_text(a.scene), a.scene);
    if (a.years && a.resume.empty()) sets.push_back("simulation.years=" + std::to_string(*a.years));
    apply_overrides(j, sets);
    const fs::path base = fs::absolute(fs::path(a.scene)).parent_path();
    auto scene = with_context(a.scene, [&] { return eco::load_eco_scene(j, base); });
    print_notes(scene.hydro.notes);
    print_terrain_source(scene.hydro.terrain_source);
    for (const auto& n : scene.ecosystem.notes)
        std::fprintf(stderr, "note: %s: %s\n", scene.ecosystem.source.c_str(), n.c_str());
    if (scene.hydro.observed) print_notes(hydro::fill_report(*scene.hydro.observed));
    return scene;
}

/// Where and how `run` writes; a new run claims its outputs (--force to replace them).
run::RunOptions run_options(const RunArgs& a, const std::optional<eco::EcoScene>& scene,
                            const std::vector<std::string>& sets) {
    run::RunOptions opt;
    opt.resume = !a.resume.empty();
    opt.output = opt.resume ? fs::path(a.resume) : fs::path(a.output);
    opt.replace = a.force;
    if (!opt.resume) {
        // A new run replaces an earlier one only with --force (then atomically: a failed or
        // killed run leaves the earlier one as it was); its picture folder likewise.
        claim_output("-o", a.output, a.force);
        if (!a.no_pictures)
            claim_output("--pictures",
                         a.pictures_dir.empty() ? (opt.output.parent_path() /
                                                   (opt.output.stem().string() + ".pictures"))
                                                      .string()
                                                : a.pictures_dir,
                         a.force);
    }
    opt.pictures = !a.no_pictures;
    opt.picture_dir = a.pictures_dir;
    opt.provenance = provenance({{"scene_file", a.scene}, {"overrides", sets}});
    if (scene && scene->hydro.observed)
        opt.provenance["observed_weather_filled"] = scene->hydro.observed->filled;
    if (opt.resume) opt.years = a.years;
    return opt;
}

/// The diagnosis when the stand is empty, sparse or short of its target.
void print_diagnosis(const eco::Diagnosis& d) {
    if (d.verdict == eco::StandVerdict::ok) return;
    std::printf("diagnosis: %s\n", d.headline.c_str());
    for (const auto& l : d.lines) std::printf("  %s\n", l.c_str());
    std::printf("  (every count is in the run's /diagnosis; --strict makes this exit 3)\n");
}

void print_run_summary(const run::RunSummary& sum, const fs::path& output) {
    const auto& st = sum.stand;
    std::printf("%d years run (%d in total)%s in %.2f s: %.3g plant-years/s, %.3g simulated "
                "years/s\n",
                sum.years_run, sum.years_total,
                sum.reached_target ? ", stopped at the target basal area" : "", sum.seconds,
                sum.plant_years / sum.seconds, sum.years_run / sum.seconds);
    std::printf("stand: %lld stems, %.1f stems/ha, basal area %.2f m2/ha (%.1f ft2/acre), Dq "
                "%.1f cm, SDI %.0f per ha\n",
                static_cast<long long>(st.stems), st.stems_per_ha, st.basal_area_m2_per_ha,
                st.basal_area_m2_per_ha * kFt2PerAcrePerM2PerHa, st.quadratic_mean_dbh_m * kCmPerM,
                st.sdi_per_ha);
    print_undergrowth(sum.undergrowth, sum.species);
    print_diagnosis(sum.diagnosis);
    std::printf("budgets: water residual %.2e, carbon residual %.2e of throughput\n",
                sum.water_residual_relative, sum.carbon_residual_relative);
    std::printf("methods (cite them with the run; also in its /provenance):\n%s",
                methods_text(sum.methods).c_str());
    std::printf("wrote %s (%d snapshots)\n", output.string().c_str(), sum.snapshots);
    if (!sum.picture_dir.empty())
        std::printf("pictures: %s/{stems,dbh_histogram,stand_history,soil_moisture,"
                    "surface_water_depth}.png\n",
                    sum.picture_dir.string().c_str());
}

void run_run(const RunArgs& a) {
    if (a.scene.empty() && a.resume.empty())
        throw InputError("run: give a scene file, or --resume RUN.h5");
    if (a.resume.empty()) refuse_output_over_input("-o", a.output, {a.scene});
    if (!a.resume.empty() && a.output_given)
        throw InputError("-o " + a.output + ": --resume " + a.resume +
                         " continues that run file in place; -o is not used with --resume");
    std::vector<std::string> sets = a.sets;
    const std::optional<eco::EcoScene> scene = run_scene(a, sets);
    const run::RunOptions opt = run_options(a, scene, sets);
    if (scene) {
        const auto& g = scene->hydro.dem.grid();
        std::printf("ecosystem: %s, %zu species, %s competition, %.4g x %.4g m (terrain %d x %d "
                    "cells of %.4g m, plant grid %.4g m), seed %llu\n",
                    scene->ecosystem.name.c_str(), scene->ecosystem.species.size(),
                    eco::competition_name(scene->competition).c_str(), g.width_m(), g.height_m(),
                    g.nx, g.ny, g.cell_size_m, scene->plant_cell_m,
                    static_cast<unsigned long long>(scene->seed));
    }
    const auto sum =
        run::run_ecosystem(scene ? &*scene : nullptr, opt, [](const run::RunProgress& p) {
            constexpr int kBar = 24;
            const int done = p.years > 0 ? kBar * p.year / p.years : kBar;
            std::string bar(static_cast<std::size_t>(done), '#');
            bar.resize(kBar, '.');
            progress_line(p.years > 0 ? static_cast<double>(p.year) / p.years : 1.0, p.seconds,
                          "  [%s] year %d/%d  %zu plants  BA %.2f m2/ha  %.3g plant-years/s  ",
                          bar.c_str(), p.year, p.years, p.plants, p.basal_area_m2_per_ha,
                          p.plant_years / std::max(p.seconds, 1e-9));
        });
    end_progress_line();
    print_run_summary(sum, opt.output);
    if (a.strict && sum.diagnosis.verdict != eco::StandVerdict::ok) set_exit_code(3);
}

struct StandArgs {
    std::string run, json_out;
    int snapshot = -1;
    bool force = false;
};

void run_stand(const StandArgs& a) {
    refuse_output_over_input("--json", a.json_out, {a.run});
    claim_output("--json", a.json_out, a.force);
    const auto info = run::read_run_info(a.run);
    const auto s = run::read_snapshot_plants(a.run, a.snapshot);
    const std::vector<double> dbh = s.values("dbh_m"); // 0 below breast height
    const auto all = eco::stand_metrics(dbh, info.area_m2);
    json out = analyses::stand_json(all);
    out["run"] = a.run;
    out["snapshot"] = s.index;
    out["year"] = s.year;
    std::printf("%s, snapshot %d (year %d), %.4g ha\n", a.run.c_str(), s.index, s.year,
                all.area_ha);
    auto print = [](const std::string& label, const eco::StandMetrics& m) {
        std::printf("%-24s %7lld stems %9.1f /ha  BA %7.2f m2/ha %7.1f ft2/acre  Dq %6.1f cm  "
                    "SDI %6.0f /ha\n",
                    label.c_str(), static_cast<long long>(m.stems), m.stems_per_ha,
                    m.basal_area_m2_per_ha, m.basal_area_m2_per_ha * kFt2PerAcrePerM2PerHa,
                    m.quadratic_mean_dbh_m * kCmPerM, m.sdi_per_ha);
    };
    print("trees, all species", all);
    json per = json::object();
    std::vector<int> species;
    for (const auto& p : s.plants) species.push_back(p.species);
    const auto by_species =
        eco::stand_metrics_by_species(dbh, species, info.species.size(), info.area_m2);
    const auto run_species = run::read_run_species(a.run);
    for (std::size_t sp = 0; sp < info.species.size(); ++sp) {
        if (sp < run_species.size() && run_species[sp].life_form != eco::LifeForm::tree) continue;
        print(info.species[sp], by_species[sp]);
        per[info.species[sp]] = analyses::stand_json(by_species[sp]);
    }
    out["species"] = per;
    out["note"] = "trees only: shrubs, objects and the ground layer are under undergrowth";
    const auto u = run::read_snapshot_undergrowth(a.run, s.index);
    out["undergrowth"] = eco::to_json(u, info.species);
    print_undergrowth(u, info.species);
    std::printf("DBH classes (cm)   stems/ha\n");
    for (std::size_t i = 0; i < all.histogram.size(); ++i)
        std::printf("  %3g-%-3g        %9.1f\n", static_cast<double>(i) * all.class_width_cm,
                    static_cast<double>(i + 1) * all.class_width_cm,
                    static_cast<double>(all.histogram[i]) / all.area_ha);
    if (all.fit_valid)
        std::printf("negative exponential: N = %.4g exp(-%.4f d_cm), q = %.3f per %g cm, R2 = "
                    "%.3f\n",
                    std::exp(all.intercept) / all.area_ha, all.rate_per_cm, all.q_per_class,
                    all.class_width_cm, all.r2);
    else
        std::printf("negative exponential: fewer than 3 non-empty classes, no fit\n");
    if (!a.json_out.empty()) {
        io::write_text_atomic(a.json_out, out.dump(2) + "\n");
        std::printf("wrote %s\n", a.json_out.c_str());
    }
}

struct ExportArgs {
    std::string run, output;
    int snapshot = -1;
    bool force = false;
};

/// True for a .json output, false for .csv; an InputError for any other suffix.
bool json_table(const std::string& output) {
    const std::string ext = fs::path(output).extension().string();
    if (ext == ".json") return true;
    if (ext == ".csv") return false;
    throw InputError("-o " + output +
                     ": give a .csv file (a table) or a .json file (an array of "
                     "records); the suffix picks the format");
}

void run_export_vegetation(const ExportArgs& a) {
    const bool as_json = json_table(a.output);
    refuse_output_over_input("-o", a.output, {a.run});
    claim_output("-o", a.output, a.force);
    const auto info = run::read_run_info(a.run);
    const auto s = run::read_snapshot_plants(a.run, a.snapshot);
    io::write_text_atomic(a.output,
                          as_json ? run::stem_records_json(s.plants, info.species).dump(1) + "\n"
                                  : run::stem_csv(s.plants, info.species));
    std::printf("wrote %zu stems of snapshot %d (year %d) to %s\n", s.plants.size(), s.index,
                s.year, a.output.c_str());
}

void run_export_deadwood(const ExportArgs& a) {
    const bool as_json = json_table(a.output);
    refuse_output_over_input("-o", a.output, {a.run});
    claim_output("-o", a.output, a.force);
    const auto info = run::read_run_info(a.run);
    const auto s = run::read_snapshot_deadwood(a.run, a.snapshot);
    io::write_text_atomic(
        a.output, as_json ? run::deadwood_records_json(s.pieces, info.species).dump(1) + "\n"
                          : run::deadwood_csv(s.pieces, info.species));
    std::array<std::ptrdiff_t, 4> n{}; // snags, logs, stumps, slash
    for (const auto& r : s.pieces) ++n[r.piece == 1 ? 2 : r.piece == 2 ? 3 : r.standing ? 0 : 1];
    std::printf("wrote %td snags, %td logs, %td stumps and %td pieces of slash of snapshot %d "
                "(year %d) to %s\n",
                n[0], n[1], n[2], n[3], s.index, s.year, a.output.c_str());
}

} // namespace

void add_eco_commands(CLI::App& app) {
    auto r = std::make_shared<RunArgs>();
    CLI::App* run = app.add_subcommand("run", "grow an ecosystem: the coupled engine");
    run->add_option("scene", r->scene, "scene JSON file (docs/formats.md)");
    CLI::Option* output =
        run->add_option("-o,--output", r->output, "HDF5 run file (snapshots go to NAME.snapshots/)")
            ->capture_default_str();
    run->add_option("--resume", r->resume, "continue the run in this file from its last snapshot");
    run->add_option("--years", r->years,
                    "simulated years (a new run: overrides simulation.years; --resume: years to "
                    "add)");
    run->add_option("--seed", r->seed, "random seed (overrides simulation.seed)");
    run->add_option("--set", r->sets, "KEY=VALUE: override any scene key by its dotted path");
    run->add_flag("--no-pictures", r->no_pictures, "skip the pictures");
    run->add_flag("--strict", r->strict,
                  "exit with status 3 when the stand ends empty, sparse or short of "
                  "simulation.target_basal_area_m2_per_ha (the diagnosis says why)");
    run->add_option("--pictures", r->pictures_dir, "picture folder (default NAME.pictures/)");
    add_force_flag(run, r->force);
    run->callback([r, output] {
        r->output_given = output->count() > 0;
        run_run(*r);
    });

    auto s = std::make_shared<StandArgs>();
    CLI::App* stand = app.add_subcommand("stand", "stand metrics of a run snapshot");
    stand->add_option("run", s->run, "HDF5 run file")->required();
    stand->add_option("--snapshot", s->snapshot, "snapshot index (negative: from the last)")
        ->capture_default_str();
    stand->add_option("--json", s->json_out, "also write the metrics as JSON");
    add_force_flag(stand, s->force);
    stand->callback([s] { run_stand(*s); });

    auto d = std::make_shared<std::pair<std::string, bool>>("all", false);
    CLI::App* desc = app.add_subcommand(
        "describe",
        "every key of scenes, species, terrain generators and vehicles, and every output column, "
        "with unit, default and range");
    desc->add_option("topic", d->first, "scene, species, terrain, vehicle, outputs or all")
        ->capture_default_str();
    desc->add_flag("--markdown", d->second, "Markdown tables (as docs/parameters.md)");
    desc->callback([d] { std::fputs(analyses::describe(d->first, d->second).c_str(), stdout); });

    auto e = std::make_shared<ExportArgs>();
    CLI::App* exp = app.add_subcommand("export", "export run contents");
    exp->require_subcommand(1);
    CLI::App* veg = exp->add_subcommand("vegetation", "one CSV row per stem (NRMM-style list)");
    veg->add_option("run", e->run, "HDF5 run file")->required();
    veg->add_option("--snapshot", e->snapshot, "snapshot index (negative: from the last)")
        ->capture_default_str();
    veg->add_option("-o,--output", e->output, "a .csv file, or .json (an array of records)")
        ->required();
    add_force_flag(veg, e->force);
    veg->callback([e] { run_export_vegetation(*e); });
    CLI::App* dead = exp->add_subcommand(
        "deadwood", "one CSV row per snag or log (docs/formats.md, the dead-wood table)");
    dead->add_option("run", e->run, "HDF5 run file")->required();
    dead->add_option("--snapshot", e->snapshot, "snapshot index (negative: from the last)")
        ->capture_default_str();
    dead->add_option("-o,--output", e->output, "a .csv file, or .json (an array of records)")
        ->required();
    add_force_flag(dead, e->force);
    dead->callback([e] { run_export_deadwood(*e); });
    add_export_scene_commands(*exp);
}

} // namespace ecoterra::app
