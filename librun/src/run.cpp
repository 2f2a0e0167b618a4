#include "ecoterra/run/run.hpp"
#include "ecoterra/memory.hpp"

#include "ecoterra/run/pictures.hpp"
#include "ecoterra/run/run_reader.hpp"
#include "run_layout.hpp"

#include "ecoterra/io/atomic_file.hpp"
#include "ecoterra/io/file_lock.hpp"
#include "ecoterra/io/staging.hpp"

#include <H5Cpp.h>

#include <cctype>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstring>
#include <optional>
#include <unistd.h>

namespace ecoterra::run {

using namespace ecoterra::eco;

using nlohmann::json;
using namespace layout;

namespace {
/// Removes what killed runs into `out` left behind: staging files and folders of a replacing run
/// and the temporary files of interrupted writes, in the run's folder and its snapshot folder,
/// when the process of this host that made them is gone (io/staging.hpp). A live process's files
/// and another host's are left alone.
void remove_leftovers(const fs::path& parent, const fs::path& out) {
    const std::string stem = out.stem().string();
    io::sweep_dead_staging(parent, stem, ".replacing-"); // a replacing run's file and folder
    io::sweep_dead_staging(parent, std::string(".").append(stem), ".tmp-"); // its file half-written
    io::sweep_dead_staging(parent, out.filename().string(), ".tmp-"); // the run file half-written
    io::sweep_dead_staging(parent, snapshot_dir_name(out), ".old-");  // earlier snapshots aside
    const fs::path snaps = parent / snapshot_dir_name(out);
    std::error_code ec;
    if (fs::is_directory(snaps, ec)) io::sweep_dead_staging(snaps, "", ".tmp-"); // half-written
}

/// The staging name of a new run over the earlier one at `out`: ".STEM.replacing-HOST-PID" +
/// `suffix` + the run file's extension.
fs::path replacing_path(const fs::path& out, const std::string& suffix = "") {
    const fs::path parent = out.has_parent_path() ? out.parent_path() : fs::path(".");
    return io::staging_path(parent, out.stem().string(), "replacing",
                            suffix + out.extension().string());
}

/// Puts a complete new run (run file `work`, snapshots in `snap_dir`) in the place of the earlier
/// run at `out`. The run file linking the final folder is written completely first (under a
/// staging name), so that the swap is three renames: earlier snapshots aside, new ones into
/// place, new run file over the earlier one. A kill can fall only between two renames, not in
/// the middle of writing a file; a failure at any step puts the earlier run back as it was.
void replace_run(const Ecosystem& eco, const fs::path& out, const fs::path& work,
                 const fs::path& snap_dir, const json& prov,
                 const std::vector<std::string>& checksums, io::ChunkCache* cache = nullptr) {
    const fs::path parent = out.has_parent_path() ? out.parent_path() : fs::path(".");
    const fs::path final_dir = parent / snapshot_dir_name(out);
    const fs::path old_dir = io::staging_path(parent, snapshot_dir_name(out), "old");
    // ".STEM.replacing-HOST-PID.ready.h5": swept with the other staging files if the process dies.
    const fs::path ready = replacing_path(out, ".ready");
    write_main(eco, ready, prov, checksums, snapshot_dir_name(out), cache);
    std::error_code ec;
    fs::remove_all(old_dir, ec);
    const bool had_snapshots = fs::exists(final_dir, ec);
    if (had_snapshots) fs::rename(final_dir, old_dir, ec);
    if (ec) {
        fs::remove(ready, ec);
        throw IoError(final_dir.string() +
                      ": cannot move the earlier run's snapshots aside: " + ec.message());
    }
    auto restore = [&] {
        std::error_code e2;
        fs::remove(ready, e2);
        if (had_snapshots) fs::rename(old_dir, final_dir, e2);
    };
    fs::rename(snap_dir, final_dir, ec);
    if (ec) {
        restore();
        throw IoError(final_dir.string() +
                      ": cannot move the new snapshots into place: " + ec.message());
    }
    fs::rename(ready, out, ec);
    if (ec) {
        std::error_code e2;
        fs::rename(final_dir, snap_dir, e2);
        restore();
        throw IoError(out.string() + ": cannot move the new run file into place: " + ec.message());
    }
    fs::remove(work, ec);
    fs::remove_all(old_dir, ec);
}
} // namespace

namespace {

/// One call of run_ecosystem: the engine, where it writes, and what it has written.
class RunJob {
public:
    RunJob(const RunOptions& opt, const std::function<void(const RunProgress&)>& progress)
        : m_opt(opt), m_progress(progress), m_out(opt.output),
          m_parent(m_out.has_parent_path() ? m_out.parent_path() : fs::path(".")),
          m_prov(opt.provenance) {}

    RunSummary run(const EcoScene* scene);

private:
    /// A new run of `scene`.
    void start(const EcoScene* scene);
    /// The run in m_out continued (with `scene`, when given, checked to be its scene).
    void resume(const EcoScene* scene);
    /// Where the run writes: in place, or (over an earlier run) under a staging name.
    void prepare_output();
    /// Runs the years with their snapshots, then the pictures.
    void grow();
    /// grow() under the staging name, then the swap; a failure keeps the earlier run.
    void grow_and_replace();
    /// Snapshot files of an earlier run into the same path that the new run did not replace.
    void remove_stale_snapshots();
    void report_progress(const StandMetrics& st) const;
    RunSummary summary();

    const RunOptions& m_opt;
    const std::function<void(const RunProgress&)>& m_progress;
    const fs::path m_out, m_parent;
    const std::chrono::steady_clock::time_point m_t0 = std::chrono::steady_clock::now();
    std::unique_ptr<Ecosystem> m_eco;
    json m_prov;
    int m_snapshots = 0, m_years_total = 0, m_first_year = 0, m_to_run = 0;
    std::vector<std::string> m_checksums; ///< of the snapshot files, one each
    io::ChunkCache m_chunks; ///< the run file's chunks, reused where the next write repeats them
    Methods m_methods;
    bool m_staged = false;
    fs::path m_work, m_snap_dir, m_picture_dir;
    double m_plant_years = 0;
    bool m_reached_target = false;
};

namespace {
void check_scene_memory(const EcoScene& sc) {
    check_memory(memory_estimate(sc), "the scene (" + std::to_string(sc.hydro.dem.nx()) + " x " +
                                          std::to_string(sc.hydro.dem.ny()) + " terrain cells)");
}
} // namespace

void RunJob::start(const EcoScene* scene) {
    if (!scene) throw InputError("run: a scene is required");
    check_scene_memory(*scene);
    m_eco = std::make_unique<Ecosystem>(*scene);
    m_prov["scene"] = scene->resolved;
    m_years_total = scene->years;
}

void RunJob::resume(const EcoScene* scene) {
    const RunInfo info = read_run_info(m_out);
    const json& stored = info.provenance;
    if (!stored.contains("scene") || !stored.contains("version"))
        throw InputError(m_out.string() + ": /provenance lacks the scene or the version");
    if (m_prov.contains("version") && stored["version"] != m_prov["version"])
        throw InputError(m_out.string() + ": written by ecoterra " + stored["version"].dump() +
                         ", this is " + m_prov["version"].dump() +
                         "; a checkpoint resumes only with the version that wrote it");
    const json& stored_scene = stored["scene"];
    if (scene) {
        json a = scene->resolved, b = stored_scene;
        a["simulation"].erase("years");
        b["simulation"].erase("years");
        if (a != b)
            throw InputError(m_out.string() + ": the run was made from another scene; resume it "
                                              "without a scene file or with the same scene");
    }
    // Every snapshot the run file lists must be there and whole, or the resumed run would link
    // to files that are gone.
    for (int k = 0; k < info.snapshots; ++k)
        open_snapshot(m_out, k, [&](const H5::Group& g) {
            if (!g.nameExists("plants") || !g.attrExists("year"))
                throw InputError(m_out.string() + ": snapshot " + std::to_string(k) +
                                 " lacks its plants or its year");
        });
    m_eco = load_run_engine(m_out);
    m_snapshots = info.snapshots;
    m_checksums = read_snapshot_checksums(m_out, m_snapshots);
    m_prov["scene"] = stored_scene;
    m_prov["resumed_from_year"] = m_eco->years_done();
    if (stored.contains("resumed_from_year"))
        m_prov["first_resumed_from_year"] = stored["resumed_from_year"];
    m_years_total = stored_scene["simulation"]["years"].get<int>();
}

void RunJob::prepare_output() {
    // A new run into the path of an earlier one works under a staging name and replaces the
    // earlier run only when it is complete: killed or failed, it leaves the earlier run as it was.
    // A new run into a free path (and a resumed run) writes in place, so that a killed run can be
    // resumed from its last snapshot.
    // The picture folder is tried before the years are run, not found unwritable after them.
    if (m_opt.pictures) {
        m_picture_dir = m_opt.picture_dir.empty() ? m_parent / (m_out.stem().string() + ".pictures")
                                                  : m_opt.picture_dir;
        require_writable_folder(m_picture_dir, "the picture folder");
    }
    std::error_code ec;
    remove_leftovers(m_parent, m_out);
    m_staged = !m_opt.resume && fs::exists(m_out, ec);
    m_work = m_staged ? replacing_path(m_out) : m_out;
    m_snap_dir = m_parent / snapshot_dir_name(m_work);
    if (m_staged) fs::remove_all(m_snap_dir, ec); // left by a killed process of the same id
    io::create_folder(m_snap_dir, "the snapshot folder");
}

void RunJob::report_progress(const StandMetrics& st) const {
    if (!m_progress) return;
    RunProgress p;
    p.year = m_eco->years_done();
    p.years = m_first_year + m_to_run;
    p.plants = m_eco->plants().size();
    p.basal_area_m2_per_ha = st.basal_area_m2_per_ha;
    p.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - m_t0).count();
    p.plant_years = m_plant_years;
    m_progress(p);
}

void RunJob::grow() {
    const EcoScene& sc = m_eco->scene();
    for (int y = 1; y <= m_to_run; ++y) {
        m_eco->run_year();
        m_plant_years += static_cast<double>(m_eco->plants().size());
        const StandMetrics st = m_eco->stand();
        const bool reached = sc.target_basal_area_m2_per_ha && !m_opt.years &&
                             st.basal_area_m2_per_ha >= *sc.target_basal_area_m2_per_ha;
        const bool last = y == m_to_run || reached;
        if (m_eco->years_done() % sc.snapshot_interval_years == 0 || last) {
            const fs::path file = m_snap_dir / snapshot_file_name(m_snapshots);
            write_snapshot(*m_eco, file, m_snapshots);
            m_checksums.push_back(file_checksum(file));
            ++m_snapshots;
            // A staged run's last run file would be written again by replace_run with the final
            // folder's links: it writes it once, there (a kill before leaves only staging files).
            if (!(last && m_staged)) write_main(*m_eco, m_work, m_prov, m_checksums, "", &m_chunks);
        }
        report_progress(st);
        if (reached) {
            m_reached_target = true;
            break;
        }
    }
    // Pictures before the swap: a picture folder that cannot be written leaves an earlier run in
    // place.
    if (m_opt.pictures) draw_run_pictures(*m_eco, m_picture_dir);
}

void RunJob::grow_and_replace() {
    // A failed replacement removes its staging file and folder and names the user's path.
    auto discard = [&] {
        std::error_code ec;
        fs::remove(m_work, ec);
        fs::remove_all(m_snap_dir, ec);
    };
    const std::string kept = ": the new run failed and the earlier run is kept: ";
    try {
        grow();
        replace_run(*m_eco, m_out, m_work, m_snap_dir, m_prov, m_checksums, &m_chunks);
    } catch (const IoError& e) {
        discard();
        throw IoError(m_out.string() + kept + e.what());
    } catch (const InputError& e) {
        discard();
        throw InputError(m_out.string() + kept + e.what());
    } catch (...) {
        discard();
        throw;
    }
}

void RunJob::remove_stale_snapshots() {
    std::error_code ec;
    for (int k = m_snapshots;; ++k) {
        const fs::path stale = m_snap_dir / snapshot_file_name(k);
        if (!fs::exists(stale)) break;
        fs::remove(stale, ec);
    }
}

RunSummary RunJob::summary() {
    RunSummary sum;
    sum.picture_dir = m_picture_dir;
    sum.methods = m_methods;
    sum.reached_target = m_reached_target;
    sum.years_run = m_eco->years_done() - m_first_year;
    sum.years_total = m_eco->years_done();
    sum.snapshots = m_snapshots;
    sum.stand = m_eco->stand();
    sum.undergrowth = m_eco->undergrowth();
    sum.diagnosis = m_eco->diagnosis();
    for (const auto& s : m_eco->scene().ecosystem.species) sum.species.push_back(s.name);
    sum.plant_years = m_plant_years;
    sum.water_residual_relative = std::abs(m_eco->hydrology().cumulative_residual_m3()) /
                                  std::max(m_eco->hydrology().cumulative_throughput_m3(), 1e-300);
    sum.carbon_residual_relative = m_eco->carbon_residual_relative();
    const Table& daily = m_eco->daily();
    const double years = std::max<double>(1.0, static_cast<double>(daily.rows()) / 365.0);
    auto per_year = [&](const char* column) {
        double total = 0;
        for (double v : daily.column(column)) total += v;
        return total / years;
    };
    auto& w = sum.water_mm_per_yr;
    w.rain = per_year("rain_mm");
    w.evaporation = per_year("evaporation_mm");
    w.transpiration = per_year("transpiration_mm");
    w.interception = per_year("interception_mm");
    w.runoff_out = per_year("runoff_out_mm");
    w.drainage_out = per_year("drainage_out_mm");
    w.groundwater_out = per_year("groundwater_out_mm");
    w.recharge = per_year("recharge_mm");
    sum.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - m_t0).count();
    return sum;
}

RunSummary RunJob::run(const EcoScene* scene) {
    if (!fs::is_directory(m_parent))
        throw IoError(m_out.string() + ": the folder " + m_parent.string() + " does not exist");
    // One writer per run: a second run or resume into the same path is refused while this one
    // works (the kernel drops the lock if the process is killed).
    const io::FileLock lock(m_out);
    if (!m_opt.resume && !m_opt.replace && fs::exists(m_out))
        throw InputError(m_out.string() + ": the file exists; give --force to replace it "
                                          "(nothing was written)");
    if (m_opt.resume)
        resume(scene);
    else
        start(scene);
    m_methods = scene_methods(m_eco->scene());
    m_prov["methods"] = methods_json(m_methods);
    m_first_year = m_eco->years_done();
    m_to_run = m_opt.years ? *m_opt.years : m_years_total - m_first_year;
    if (m_to_run <= 0)
        throw InputError(m_out.string() + ": the run already has " + std::to_string(m_first_year) +
                         " of its " + std::to_string(m_years_total) +
                         " years; give --years N to continue");
    prepare_output();
    if (m_staged)
        grow_and_replace();
    else
        grow();
    if (!m_staged && !m_opt.resume) remove_stale_snapshots();
    return summary();
}

} // namespace

std::unique_ptr<Ecosystem> load_run_engine(const fs::path& run) {
    const RunInfo info = read_run_info(run);
    if (!info.provenance.contains("scene"))
        throw InputError(run.string() + ": /provenance lacks the scene");
    const EcoScene sc = load_eco_scene(info.provenance["scene"], "/");
    check_scene_memory(sc);
    auto eco = std::make_unique<Ecosystem>(sc);
    const std::vector<std::uint8_t> bytes = read_run_checkpoint(run, sc).bytes;
    ArchiveReader r(bytes.data(), bytes.size(), run.string());
    // The series of a checkpoint that keeps them in the run file, opened only if it does.
    std::optional<H5::H5File> file;
    const Ecosystem::SeriesSource series = [&](const std::string& table, const std::string& col) {
        if (!file) file = open_run(run);
        return read_series_column(*file, run, table, col);
    };
    with_context(run.string() + ": /checkpoint", [&] { eco->load_state(r, series); });
    return eco;
}

void write_run_file(const Ecosystem& eco, const fs::path& out, const json& provenance,
                    bool replace) {
    const fs::path parent = out.has_parent_path() ? out.parent_path() : fs::path(".");
    if (!fs::is_directory(parent))
        throw IoError(out.string() + ": the folder " + parent.string() + " does not exist");
    const io::FileLock lock(out);
    if (!replace && fs::exists(out))
        throw InputError(out.string() + ": the file exists; give replace (force) to replace it "
                                        "(nothing was written)");
    remove_leftovers(parent, out);
    json prov = provenance;
    prov["scene"] = eco.scene().resolved;
    prov["scene"]["simulation"]["years"] = std::max(1, eco.years_done());
    prov["methods"] = methods_json(scene_methods(eco.scene()));
    const fs::path work = replacing_path(out);
    const fs::path snap_dir = parent / snapshot_dir_name(work);
    std::error_code ec;
    fs::remove_all(snap_dir, ec);
    io::create_folder(snap_dir, "the snapshot folder");
    try {
        const fs::path file = snap_dir / snapshot_file_name(0);
        write_snapshot(eco, file, 0);
        replace_run(eco, out, work, snap_dir, prov, {file_checksum(file)});
    } catch (...) {
        fs::remove_all(snap_dir, ec);
        throw;
    }
}

RunSummary run_ecosystem(const EcoScene* scene, const RunOptions& opt,
                         const std::function<void(const RunProgress&)>& progress) {
    return RunJob(opt, progress).run(scene);
}

} // namespace ecoterra::run
