#pragma once
// Running one member of an ensemble into the output folder, and reading members back.
//
// Folder layout (docs/ensembles.md):
//   OUT/ensemble.json              the manifest as read, its name and member count
//   OUT/members/NNNNNN/            a finished member (ok or failed): member.json, timing.json and
//                                  the files of its analyses
//   OUT/members/.NNNNNN.partial-HOST-PID  a member being written (never counted)
//   OUT/logs/NNNNNN.log            what the member's process printed
//   OUT/summary/                   members.csv, aggregate.csv, histograms.csv, summary.h5, *.png
#include "ecoterra/ensemble/manifest.hpp"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <optional>
#include <string>

namespace ecoterra::ensemble {

/// "000017": six digits at least, more when the ensemble has more members.
std::string member_name(const Manifest& m, std::size_t index);
std::filesystem::path member_dir(const std::filesystem::path& out, const Manifest& m,
                                 std::size_t index);

/// The record of a finished member (its member.json), if there is one.
std::optional<nlohmann::json> read_member_record(const std::filesystem::path& out,
                                                 const Manifest& m, std::size_t index);
/// True when member `index` finished with status ok and the same input hash.
bool member_done(const std::filesystem::path& out, const Manifest& m, const Member& mb);

struct MemberOutcome {
    bool ok = false;
    bool skipped = false; ///< it was done already (same inputs)
    std::string error;
    double seconds = 0;
};

/// Runs the member in this process: its files are written into a staging folder and renamed
/// into place when complete. An error in the member (bad override, a run that fails) is caught
/// and recorded as status "failed" with its message; only a failure to write the record itself
/// throws. `threads` is recorded in timing.json (the caller sets the thread count).
MemberOutcome run_member(const std::filesystem::path& out, const Manifest& m, const Member& mb,
                         int threads);

/// Records a member that died without writing its record (a crash or a kill): status failed,
/// with `reason` and the end of its log.
void record_crashed_member(const std::filesystem::path& out, const Manifest& m, const Member& mb,
                           const std::string& reason, const std::filesystem::path& log);

/// Removes the staging folders left by processes of this host that are gone (a member killed
/// while it was writing); folders of live processes and of other hosts are left alone. Returns
/// how many were removed.
std::size_t sweep_stale_stages(const std::filesystem::path& out);

/// Prepares OUT for the manifest: creates it, or checks that it holds this ensemble (same name)
/// and nothing else; writes ensemble.json. InputError naming both manifests otherwise.
void prepare_output(const std::filesystem::path& out, const Manifest& m);

/// Reads OUT/ensemble.json back into a manifest (for --summary): the copy of the manifest it
/// holds, resolved against the manifest's original folder.
Manifest manifest_of_output(const std::filesystem::path& out);

} // namespace ecoterra::ensemble
