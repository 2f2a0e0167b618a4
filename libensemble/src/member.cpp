#include "ecoterra/ensemble/member.hpp"

#include "ecoterra/analyses/analyses.hpp"

#include "ecoterra/eco/scene_config.hpp"
#include "ecoterra/error.hpp"
#include "ecoterra/export/formats.hpp"
#include "ecoterra/io/atomic_file.hpp"
#include "ecoterra/io/staging.hpp"
#include "ecoterra/json_util.hpp"
#include "ecoterra/mobility/stand.hpp"
#include "ecoterra/mobility/traverse.hpp"
#include "ecoterra/provenance.hpp"
#include "ecoterra/run/run.hpp"
#include "ecoterra/run/run_reader.hpp"
#include "ecoterra/terrain/analysis.hpp"
#include "ecoterra/terrain/generate.hpp"
#include "ecoterra/terrain/io/raster_io.hpp"
#include "ecoterra/terrain/missions.hpp"
#include "ecoterra/units.hpp"

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <optional>
#include <unistd.h>

namespace ecoterra::ensemble {

namespace fs = std::filesystem;
using nlohmann::json;

std::string member_name(const Manifest& m, std::size_t index) {
    std::string s = std::to_string(index);
    const std::size_t width = std::max<std::size_t>(6, std::to_string(m.members() - 1).size());
    if (s.size() < width) s.insert(0, width - s.size(), '0');
    return s;
}

fs::path member_dir(const fs::path& out, const Manifest& m, std::size_t index) {
    return out / "members" / member_name(m, index);
}

std::optional<json> read_member_record(const fs::path& out, const Manifest& m, std::size_t index) {
    const fs::path p = member_dir(out, m, index) / "member.json";
    std::error_code ec;
    if (!fs::is_regular_file(p, ec)) return std::nullopt;
    try {
        return json::parse(io::read_text(p));
    } catch (const std::exception&) {
        return std::nullopt; // unreadable: not done
    }
}

bool member_done(const fs::path& out, const Manifest& m, const Member& mb) {
    const auto r = read_member_record(out, m, mb.index);
    return r && r->value("status", "") == "ok" && r->value("input_hash", "") == mb.input_hash;
}

namespace {

using Metrics = std::vector<std::pair<std::string, double>>;

/// Paths in a member's analyses are relative to the manifest's folder.
fs::path manifest_path(const Manifest& m, const std::string& p) {
    return fs::path(p).is_absolute() ? fs::path(p) : m.dir / p;
}

json member_provenance(const Manifest& m, const Member& mb) {
    return provenance({{"ensemble", m.name}, {"member", mb.index}, {"input_hash", mb.input_hash}});
}

void add_stand(const eco::StandMetrics& s, Metrics& out, json& record) {
    analyses::add_values(out, "stand", analyses::stand_metrics(), s);
    std::vector<double> per_ha;
    for (auto c : s.histogram) per_ha.push_back(static_cast<double>(c) / s.area_ha);
    record["histogram"] = {
        {"class_width_cm", s.class_width_cm}, {"stems_per_ha", per_ha}, {"area_ha", s.area_ha}};
}

/// `dead` is read when analyses.mobility.deadwood is true (read_dead); `ground` is the snapshot's
/// soil strength and standing water (none for stem lists), applied when analyses.mobility.soil is
/// true.
template <class ReadDead>
void analyse_mobility(const Manifest& m, const json& a, std::vector<mobility::StandStem> stems,
                      ReadDead&& read_dead, const RasterD& dem,
                      const std::optional<run::SnapshotGround>& ground, const fs::path& stage,
                      Metrics& out) {
    const auto opt = analyses::mobility_catalog().read(a, {});
    const auto v = mobility::load_vehicle(manifest_path(m, opt.vehicle));
    mobility::StandDeadWood dead;
    if (opt.deadwood) dead = read_dead();
    stems.insert(stems.end(), dead.snags.begin(), dead.snags.end());
    auto lines = opt.lines_options();
    if (opt.soil && ground) lines.smg.ground = ground->maps();
    RasterD ground_dem = dem;
    mobility::carve_pits(ground_dem, dead.pits);
    const auto r = mobility::analyse_stand(v, stems, ground_dem, lines, dead.logs);
    json j = analyses::mobility_json(r, v);
    j["seed"] = opt.seed;
    io::write_text_atomic(stage / "mobility.json", j.dump(1) + "\n");
    analyses::add_values(out, "mobility", analyses::mobility_metrics(), r);
}

/// The member's mobility map (its snapshot's stand and ground): mobility_map.json and the layers
/// the ensemble's stochastic map adds up (mobility_map/speed_mean_m_per_s.tif, go_fraction.tif).
void analyse_mobility_map(const Manifest& m, const json& a, const fs::path& run_file,
                          const fs::path& stage, Metrics& out) {
    const auto opt = analyses::mobility_map_catalog().read(a, {});
    const auto v = mobility::load_vehicle(manifest_path(m, opt.vehicle));
    const auto w = run::read_driving_world(run_file, -1, opt.deadwood, opt.soil);
    const auto map = mobility::mobility_map(v, w.dem, w.stems, w.dead.logs,
                                            w.ground ? w.ground->maps() : mobility::GroundMaps{},
                                            opt.map_options());
    io::create_folder(stage / "mobility_map", "the member's map folder");
    terrain::io::write_geotiff(map.speed_mean_m_per_s,
                               stage / "mobility_map/speed_mean_m_per_s.tif", "m/s");
    terrain::io::write_geotiff(map.go_fraction, stage / "mobility_map/go_fraction.tif", "1");
    io::write_text_atomic(stage / "mobility_map.json", mobility::to_json(map).dump(1) + "\n");
    analyses::add_values(out, "mobility_map", analyses::mobility_map_metrics(), map);
}

void analyse_terrain(const json& a, const RasterD& z, const fs::path& stage, Metrics& out) {
    const auto opt = analyses::terrain_catalog().read(a, {}).options();
    const auto r = terrain::analyze_terrain(z, opt);
    const json j = analyses::terrain_json(r, opt);
    io::write_text_atomic(stage / "terrain.json", j.dump(1) + "\n");
    analyses::add_values(out, "terrain", analyses::terrain_metrics(), r);
}

void analyse_traverse(const Manifest& m, const json& a, const RasterD& z, const fs::path& stage,
                      Metrics& out) {
    const auto opt = analyses::traverse_catalog().read(a, {});
    const auto v = mobility::load_vehicle(manifest_path(m, opt.vehicle));
    auto mo = opt.mission_options();
    mo.validate();
    std::vector<mobility::MissionLine> missions;
    for (const auto& p : terrain::plan_missions(z, terrain::AnalysisOptions{}, mo))
        missions.push_back({p.id, p.start_x_m, p.start_y_m, p.goal_x_m, p.goal_y_m});
    const auto r = mobility::traverse_missions(v, z, missions, opt.traverse_options());
    json j = analyses::traverse_json(r, v);
    j["seed"] = mo.seed;
    j["missions_requested"] = mo.count;
    io::write_text_atomic(stage / "traverse.json", j.dump(1) + "\n");
    analyses::add_values(out, "traverse", analyses::traverse_metrics(), r);
}

void export_scenes(const json& a, const fs::path& run, const fs::path& stage,
                   const fs::path& final_dir, const std::string& source) {
    namespace ex = ecoterra::exporter;
    const auto opt_a = analyses::export_catalog().read(a, {});
    ex::Scene s = ex::load_scene(run, -1);
    s.source = source; // not the staging folder, which is gone once the member is in place
    ex::ExportOptions opt;
    for (const auto& f : opt_a.formats) {
        const auto format = ex::scene_format_from_name(f);
        const std::string name = "scene_" + f;
        ex::OutputFolder folder(stage / name, false);
        opt.final_dir = final_dir / name;
        ex::write_scene(ex::in_local_frame(s), format, folder, opt);
        folder.commit();
    }
    if (opt_a.layers) {
        ex::OutputFolder folder(stage / "layers", false);
        ex::write_layers(s, folder, ex::LayerOptions{});
        folder.commit();
    }
}

/// The member's work, into `stage`. Fills the metrics and the record's histogram.
void execute(const Manifest& m, const Member& mb, const fs::path& stage, const fs::path& final_dir,
             Metrics& metrics, json& record) {
    const json& an = mb.analyses;
    if (m.kind == BaseKind::run) {
        auto scene = eco::load_eco_scene(mb.scene, m.base_dir);
        run::RunOptions opt;
        opt.output = stage / "run.h5";
        opt.pictures = an.value("pictures", false);
        opt.picture_dir = stage / "pictures";
        opt.provenance = member_provenance(m, mb);
        const auto sum = run::run_ecosystem(&scene, opt);
        analyses::add_values(metrics, "run", analyses::run_metrics(), sum);
        add_stand(sum.stand, metrics, record);
        if (an.contains("stand"))
            io::write_text_atomic(stage / "stand.json",
                                  analyses::stand_json(sum.stand).dump(1) + "\n");
        RasterD dem;
        if (an.contains("mobility") || an.contains("mobility_map") || an.contains("terrain") ||
            an.contains("traverse"))
            dem = terrain::io::read_hdf5(opt.output, terrain::io::kRunTerrainDataset);
        if (an.contains("mobility"))
            analyse_mobility(
                m, an["mobility"],
                run::stand_stems(run::read_snapshot_plants(opt.output, -1).plants),
                [&] {
                    return run::stand_deadwood(run::read_snapshot_deadwood(opt.output, -1).pieces);
                },
                dem, run::read_snapshot_ground(opt.output, -1, dem.grid()), stage, metrics);
        if (an.contains("mobility_map"))
            analyse_mobility_map(m, an["mobility_map"], opt.output, stage, metrics);
        if (an.contains("terrain")) analyse_terrain(an["terrain"], dem, stage, metrics);
        if (an.contains("traverse")) analyse_traverse(m, an["traverse"], dem, stage, metrics);
        if (an.contains("export"))
            export_scenes(an["export"], opt.output, stage, final_dir,
                          m.keep_files ? (final_dir / "run.h5").string()
                                       : "member " + std::to_string(mb.index) + " of ensemble " +
                                             m.name + " (its run file is not kept)");
        if (!m.keep_files) {
            fs::remove(opt.output);
            fs::remove_all(stage / "run.snapshots");
        }
    } else if (m.kind == BaseKind::terrain) {
        const auto t = terrain::generate_terrain(mb.scene);
        // What a replay needs: `ecoterra terrain generate --config terrain_spec.json` makes this
        // terrain again, bit for bit.
        io::write_text_atomic(stage / "terrain_spec.json", t.resolved.dump(1) + "\n");
        if (an.contains("terrain")) analyse_terrain(an["terrain"], t.z, stage, metrics);
        if (an.contains("traverse")) analyse_traverse(m, an["traverse"], t.z, stage, metrics);
        if (m.keep_files) {
            terrain::io::WriteOptions wo;
            wo.provenance = member_provenance(m, mb);
            wo.provenance["terrain"] = t.resolved;
            terrain::io::write_raster(t.z, stage / "terrain.h5", wo);
        }
    } else {
        const fs::path stems_file = m.base_dir / get_string(mb.scene, "stems", "", "base.mobility");
        const fs::path dem_file = m.base_dir / get_string(mb.scene, "dem", "", "base.mobility");
        const std::string dead_file = get_string(mb.scene, "deadwood", "", "base.mobility");
        const RasterD dem = terrain::io::read_raster(dem_file);
        if (an.contains("mobility"))
            analyse_mobility(
                m, an["mobility"], mobility::read_stem_csv(stems_file),
                [&] {
                    return dead_file.empty() ? mobility::StandDeadWood{}
                                             : mobility::read_deadwood_csv(m.base_dir / dead_file);
                },
                dem, std::nullopt, stage, metrics);
    }
}

std::string utc_now() {
    const std::time_t t = std::time(nullptr);
    char b[32];
    std::tm tm{};
    gmtime_r(&t, &tm);
    std::strftime(b, sizeof b, "%Y-%m-%dT%H:%M:%SZ", &tm);
    return b;
}

json base_record(const Manifest& m, const Member& mb) {
    json axes = json::array();
    for (const auto& [k, v] : mb.axes) axes.push_back({{"key", k}, {"value", v}});
    return {{"ensemble", m.name},
            {"member", mb.index},
            {"combination", mb.combination},
            {"replicate", mb.replicate},
            {"axes", axes},
            {"seed", mb.seed},
            {"seeds", mb.seeds},
            {"input_hash", mb.input_hash},
            {"software", {{"name", "ecoterra"}, {"version", version()}}}};
}

/// Moves the staged member into place. Another process may have finished the same member
/// meanwhile (a resumed ensemble racing an orphaned member): its record stays if it is ok with
/// the same inputs.
void publish(const fs::path& stage, const fs::path& final_dir, const std::string& hash) {
    std::error_code ec;
    if (fs::exists(final_dir, ec)) {
        try {
            const json r = json::parse(io::read_text(final_dir / "member.json"));
            if (r.value("status", "") == "ok" && r.value("input_hash", "") == hash) {
                fs::remove_all(stage, ec);
                return;
            }
        } catch (const std::exception&) {
        }
    }
    io::replace_folder(stage, final_dir);
}

/// `.NNNNNN.partial-HOST-PID`: member `index` being written by this process (io/staging.hpp).
fs::path stage_dir(const fs::path& out, const Manifest& m, std::size_t index) {
    return io::staging_path(out / "members", member_name(m, index), "partial");
}

void write_record(const fs::path& stage, const json& record, double seconds, int threads) {
    io::write_text_atomic(stage / "member.json", record.dump(1) + "\n");
    const json timing = {{"seconds", seconds},
                         {"threads", threads},
                         {"host", io::host_name()},
                         {"pid", static_cast<long long>(getpid())},
                         {"finished_utc", utc_now()}};
    io::write_text_atomic(stage / "timing.json", timing.dump(1) + "\n");
}

} // namespace

MemberOutcome run_member(const fs::path& out, const Manifest& m, const Member& mb, int threads) {
    MemberOutcome o;
    const auto t0 = std::chrono::steady_clock::now();
    const fs::path stage = stage_dir(out, m, mb.index);
    std::error_code ec;
    fs::remove_all(stage, ec);
    io::create_folder(stage, "the member's staging folder");
    json record = base_record(m, mb);
    Metrics metrics;
    try {
        execute(m, mb, stage, member_dir(out, m, mb.index), metrics, record);
        o.ok = true;
    } catch (const std::bad_alloc&) {
        o.error = "out of memory";
    } catch (const std::exception& e) {
        o.error = e.what();
    }
    if (!o.ok) {
        // Nothing half-made stays beside a failed record.
        for (const auto& e : fs::directory_iterator(stage)) fs::remove_all(e.path(), ec);
        metrics.clear();
        record.erase("histogram");
    }
    record["status"] = o.ok ? "ok" : "failed";
    if (!o.ok) record["error"] = o.error;
    json jm = json::object();
    for (const auto& [k, v] : metrics) jm[k] = std::isfinite(v) ? json(v) : json(nullptr);
    record["metrics"] = jm;
    o.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    write_record(stage, record, o.seconds, threads);
    publish(stage, member_dir(out, m, mb.index), mb.input_hash);
    return o;
}

std::size_t sweep_stale_stages(const fs::path& out) {
    return io::sweep_dead_staging(out / "members", "", ".partial-") +
           io::sweep_dead_staging(out / "members", "", ".old-");
}

void record_crashed_member(const fs::path& out, const Manifest& m, const Member& mb,
                           const std::string& reason, const fs::path& log) {
    std::string tail;
    {
        std::ifstream in(log, std::ios::binary);
        std::string all((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        tail = all.size() > 2000 ? all.substr(all.size() - 2000) : all;
    }
    const fs::path stage = stage_dir(out, m, mb.index);
    std::error_code ec;
    fs::remove_all(stage, ec);
    io::create_folder(stage, "the member's staging folder");
    json record = base_record(m, mb);
    record["status"] = "failed";
    record["error"] = reason + (tail.empty() ? "" : "; its log ends: " + tail);
    record["metrics"] = json::object();
    write_record(stage, record, 0, 0);
    publish(stage, member_dir(out, m, mb.index), mb.input_hash);
}

void prepare_output(const fs::path& out, const Manifest& m) {
    const fs::path e = out / "ensemble.json";
    std::error_code ec;
    if (fs::exists(out, ec) && !fs::is_directory(out, ec))
        throw InputError("-o " + out.string() + ": exists and is not a folder");
    if (fs::exists(e, ec)) {
        json j;
        try {
            j = json::parse(io::read_text(e));
        } catch (const std::exception& x) {
            throw InputError(e.string() + ": unreadable (" + x.what() +
                             "); this folder is not an ensemble's output: choose another -o");
        }
        const std::string other = j.value("name", ""), other_file = j.value("manifest_file", "");
        if (other != m.name)
            throw InputError("-o " + out.string() + " holds the members of ensemble '" + other +
                             "' (manifest " + other_file + "), not of '" + m.name + "' (" +
                             m.file.string() +
                             "): choose another -o, or remove that folder to start again");
    } else if (fs::exists(out, ec) && !fs::is_empty(out, ec)) {
        throw InputError("-o " + out.string() +
                         ": the folder has files and no ensemble.json; an ensemble writes only "
                         "into a new or empty folder (or one of its own)");
    }
    io::create_folder(out / "members", "the ensemble's folder (-o " + out.string() + ")");
    io::create_folder(out / "logs", "the ensemble's folder (-o " + out.string() + ")");
    const json doc = {{"name", m.name},
                      {"manifest_file", fs::absolute(m.file).lexically_normal().string()},
                      {"manifest_dir", m.dir.string()},
                      {"base_dir", m.base_dir.string()},
                      {"members", m.members()},
                      {"combinations", m.combinations()},
                      {"replicates", m.replicates},
                      {"manifest", m.document},
                      {"base", m.base},
                      {"software", {{"name", "ecoterra"}, {"version", version()}}}};
    const std::string text = doc.dump(1) + "\n";
    // Left alone when it already says the same (many processes may start at once).
    try {
        if (io::read_text(e) == text) return;
    } catch (const std::exception&) {
    }
    io::write_text_atomic(e, text);
}

Manifest manifest_of_output(const fs::path& out) {
    const fs::path e = out / "ensemble.json";
    std::error_code ec;
    if (!fs::is_regular_file(e, ec))
        throw InputError(out.string() + ": no ensemble.json; not an ensemble's output folder");
    const json j = parse_json(io::read_text(e), e.string());
    if (!j.contains("manifest") || !j.contains("base"))
        throw InputError(e.string() + ": no manifest in it; not an ensemble's output folder");
    const json base = j["base"];
    return manifest_from_document(j["manifest"], j.value("manifest_file", e.string()),
                                  j.value("manifest_dir", out.string()), &base);
}

} // namespace ecoterra::ensemble
