#include "ecoterra/run/run.hpp"

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
                 const std::vector<std::string>& checksums) {
    const fs::path parent = out.has_parent_path() ? out.parent_path() : fs::path(".");
    const fs::path final_dir = parent / snapshot_dir_name(out);
    const fs::path old_dir = io::staging_path(parent, snapshot_dir_name(out), "old");
    // ".STEM.replacing-HOST-PID.ready.h5": swept with the other staging files if the process dies.
    const fs::path ready = replacing_path(out, ".ready");
    write_main(eco, ready, prov, checksums, snapshot_dir_name(out));
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

RunSummary run_ecosystem(const EcoScene* scene, const RunOptions& opt,
                         const std::function<void(const RunProgress&)>& progress) {
    const auto t0 = std::chrono::steady_clock::now();
    const fs::path out = opt.output;
    const fs::path parent = out.has_parent_path() ? out.parent_path() : fs::path(".");
    if (!fs::is_directory(parent))
        throw IoError(out.string() + ": the folder " + parent.string() + " does not exist");
    // One writer per run: a second run or resume into the same path is refused while this one
    // works (the kernel drops the lock if the process is killed).
    const io::FileLock lock(out);
    if (!opt.resume && !opt.replace && fs::exists(out))
        throw InputError(out.string() + ": the file exists; give --force to replace it (nothing "
                                        "was written)");
    std::unique_ptr<Ecosystem> eco;
    json prov = opt.provenance;
    int snapshots = 0;
    std::vector<std::string> checksums; // of the snapshot files, one each
    int years_total = 0;
    if (opt.resume) {
        const RunInfo info = read_run_info(out);
        const json& stored = info.provenance;
        if (!stored.contains("scene") || !stored.contains("version"))
            throw InputError(out.string() + ": /provenance lacks the scene or the version");
        if (prov.contains("version") && stored["version"] != prov["version"])
            throw InputError(out.string() + ": written by ecoterra " + stored["version"].dump() +
                             ", this is " + prov["version"].dump() +
                             "; a checkpoint resumes only with the version that wrote it");
        json stored_scene = stored["scene"];
        if (scene) {
            json a = scene->resolved, b = stored_scene;
            a["simulation"].erase("years");
            b["simulation"].erase("years");
            if (a != b)
                throw InputError(out.string() + ": the run was made from another scene; resume "
                                                "it without a scene file or with the same scene");
        }
        const EcoScene sc = load_eco_scene(stored_scene, "/");
        eco = std::make_unique<Ecosystem>(sc);
        H5::H5File f = open_run(out);
        std::vector<std::uint8_t> bytes;
        std::string hash, checksum;
        try {
            bytes = read_vector<std::uint8_t>(f.openGroup("/checkpoint"), "state",
                                              H5::PredType::NATIVE_UINT8);
            hash = read_string_attr(f.openGroup("/checkpoint"), "terrain_hash");
            checksum = read_string_attr(f.openGroup("/checkpoint"), "checksum_fnv1a64");
        } catch (const H5::Exception& e) {
            throw InputError(out.string() + ": cannot read /checkpoint (" + e.getDetailMsg() + ")");
        }
        if (checksum != std::to_string(fnv1a64(bytes.data(), bytes.size())))
            throw InputError(out.string() +
                             ": /checkpoint/state is damaged (its checksum_fnv1a64 " + checksum +
                             " does not match its " + std::to_string(bytes.size()) + " bytes)");
        if (hash != std::to_string(raster_hash(sc.hydro.dem)))
            throw InputError(out.string() + ": the terrain rebuilt from the stored scene differs "
                                            "from the run's (was the terrain file changed?)");
        // Every snapshot the run file lists must be there and whole, or the resumed run would link
        // to files that are gone.
        for (int k = 0; k < info.snapshots; ++k)
            open_snapshot(out, k, [&](const H5::Group& g) {
                if (!g.nameExists("plants") || !g.attrExists("year"))
                    throw InputError(out.string() + ": snapshot " + std::to_string(k) +
                                     " lacks its plants or its year");
            });
        ArchiveReader r(bytes.data(), bytes.size(), out.string());
        with_context(out.string() + ": /checkpoint", [&] { eco->load_state(r); });
        snapshots = info.snapshots;
        checksums = read_snapshot_checksums(out, snapshots);
        prov["scene"] = stored_scene;
        prov["resumed_from_year"] = eco->years_done();
        if (stored.contains("resumed_from_year"))
            prov["first_resumed_from_year"] = stored["resumed_from_year"];
        years_total = stored_scene["simulation"]["years"].get<int>();
    } else {
        if (!scene) throw InputError("run: a scene is required");
        eco = std::make_unique<Ecosystem>(*scene);
        prov["scene"] = scene->resolved;
        years_total = scene->years;
    }
    const EcoScene& sc = eco->scene();
    const Methods methods = scene_methods(sc);
    prov["methods"] = methods_json(methods);
    const int to_run = opt.years ? *opt.years : years_total - eco->years_done();
    if (to_run <= 0)
        throw InputError(out.string() + ": the run already has " +
                         std::to_string(eco->years_done()) + " of its " +
                         std::to_string(years_total) + " years; give --years N to continue");
    // A new run into the path of an earlier one works under a staging name and replaces the
    // earlier run only when it is complete: killed or failed, it leaves the earlier run as it was.
    // A new run into a free path (and a resumed run) writes in place, so that a killed run can be
    // resumed from its last snapshot.
    // The picture folder is tried before the years are run, not found unwritable after them.
    fs::path picture_dir;
    if (opt.pictures) {
        picture_dir = opt.picture_dir.empty() ? parent / (out.stem().string() + ".pictures")
                                              : opt.picture_dir;
        require_writable_folder(picture_dir, "the picture folder");
    }
    std::error_code ec;
    remove_leftovers(parent, out);
    const bool staged = !opt.resume && fs::exists(out, ec);
    const fs::path work = staged ? replacing_path(out) : out;
    const fs::path snap_dir = parent / snapshot_dir_name(work);
    if (staged) fs::remove_all(snap_dir, ec); // left by a killed process of the same id
    io::create_folder(snap_dir, "the snapshot folder");

    RunSummary sum;
    sum.picture_dir = picture_dir;
    sum.methods = methods;
    double plant_years = 0;
    const int first_year = eco->years_done();
    auto grow = [&] {
        for (int y = 1; y <= to_run; ++y) {
            eco->run_year();
            plant_years += static_cast<double>(eco->plants().size());
            const StandMetrics st = eco->stand();
            const bool reached = sc.target_basal_area_m2_per_ha && !opt.years &&
                                 st.basal_area_m2_per_ha >= *sc.target_basal_area_m2_per_ha;
            const bool last = y == to_run || reached;
            if (eco->years_done() % sc.snapshot_interval_years == 0 || last) {
                const fs::path file = snap_dir / snapshot_file_name(snapshots);
                write_snapshot(*eco, file, snapshots);
                checksums.push_back(file_checksum(file));
                ++snapshots;
                write_main(*eco, work, prov, checksums);
            }
            if (progress) {
                RunProgress p;
                p.year = eco->years_done();
                p.years = first_year + to_run;
                p.plants = eco->plants().size();
                p.basal_area_m2_per_ha = st.basal_area_m2_per_ha;
                p.seconds =
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
                p.plant_years = plant_years;
                progress(p);
            }
            if (reached) {
                sum.reached_target = true;
                break;
            }
        }
        // Pictures before the swap: a picture folder that cannot be written leaves an earlier run
        // in place.
        if (opt.pictures) {
            sum.picture_dir = opt.picture_dir.empty() ? parent / (out.stem().string() + ".pictures")
                                                      : opt.picture_dir;
            draw_run_pictures(*eco, sum.picture_dir);
        }
    };
    if (!staged) {
        grow();
    } else {
        // A failed replacement removes its staging file and folder and names the user's path.
        auto discard = [&] {
            fs::remove(work, ec);
            fs::remove_all(snap_dir, ec);
        };
        const std::string kept = ": the new run failed and the earlier run is kept: ";
        try {
            grow();
            replace_run(*eco, out, work, snap_dir, prov, checksums);
        } catch (const IoError& e) {
            discard();
            throw IoError(out.string() + kept + e.what());
        } catch (const InputError& e) {
            discard();
            throw InputError(out.string() + kept + e.what());
        } catch (...) {
            discard();
            throw;
        }
    }
    if (!staged && !opt.resume) {
        // Snapshot files of an earlier run into the same path that the new run did not replace.
        for (int k = snapshots;; ++k) {
            const fs::path stale = snap_dir / snapshot_file_name(k);
            if (!fs::exists(stale)) break;
            fs::remove(stale, ec);
        }
    }
    sum.years_run = eco->years_done() - first_year;
    sum.years_total = eco->years_done();
    sum.snapshots = snapshots;
    sum.stand = eco->stand();
    sum.undergrowth = eco->undergrowth();
    for (const auto& s : eco->scene().ecosystem.species) sum.species.push_back(s.name);
    sum.plant_years = plant_years;
    sum.water_residual_relative = std::abs(eco->hydrology().cumulative_residual_m3()) /
                                  std::max(eco->hydrology().cumulative_throughput_m3(), 1e-300);
    sum.carbon_residual_relative = eco->carbon_residual_relative();
    sum.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return sum;
}

} // namespace ecoterra::run
