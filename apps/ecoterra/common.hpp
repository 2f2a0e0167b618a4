#pragma once
// Shared helpers of the ecoterra subcommands: provenance, timing, messages.
#include "ecoterra/provenance.hpp"
#include <CLI/CLI.hpp>

#include <nlohmann/json.hpp>

#include <chrono>
#include <string>
#include <vector>

namespace ecoterra::app {

/// The exit code a command asks for when it ends without an error (default 0), e.g. 1 when some
/// members of an ensemble failed.
void set_exit_code(int code);
int exit_code();
/// The provenance of a command's outputs (ecoterra/provenance.hpp: software, version, command
/// line).
inline nlohmann::json provenance(const nlohmann::json& extra = nlohmann::json::object()) {
    return command_provenance(extra);
}
/// Refuses an output that names an input (writing it would destroy the input): InputError naming
/// the option, the output and the input. Empty paths are ignored.
void refuse_output_over_input(const std::string& option, const std::string& output,
                              const std::vector<std::string>& inputs);
/// The one rule for what a command writes (docs/user-guide.md, "Outputs"): an existing file, or
/// an existing folder with anything in it, is refused unless `force` (InputError naming the option
/// and the path, before any work and with nothing written); with `force` it is replaced when the
/// command completes, and a note on stderr says so. Empty paths are ignored.
void claim_output(const std::string& option, const std::string& path, bool force);
/// Adds `--force` (see claim_output) to a subcommand.
void add_force_flag(CLI::App* command, bool& force);
/// Refuses to write a raster over an ecoterra run or snapshot file (a file with /checkpoint,
/// /snapshots or /NNNN/plants), whatever --force says: a raster would destroy the run's contents.
void refuse_over_run_file(const std::string& option, const std::string& path);
/// The file part of a raster reference "FILE" or "FILE.h5:/DATASET" (terrain::io::
/// split_hdf5_reference), for comparing paths.
std::string raster_file_part(const std::string& reference);
/// Prints each warning to stderr as "warning: ...".
void print_warnings(const std::vector<std::string>& warnings);
/// Prints each note to stderr as "note: ...".
void print_notes(const std::vector<std::string>& notes);
/// One line on a DEM read through a window or resampled (hydro::HydroScene::terrain_source);
/// nothing for a generated terrain or a file read as it is.
void print_terrain_source(const nlohmann::json& record);
/// Shows progress on stderr: `fraction` done (0..1) after `elapsed_s` seconds, with the text
/// (printf-style) and an estimate of the time left. On a terminal one line is rewritten in place;
/// into a log (stderr not a terminal) a whole line is written each time another 10 % is done,
/// with no carriage returns.
[[gnu::format(printf, 3, 4)]] void progress_line(double fraction, double elapsed_s,
                                                 const char* format, ...);
/// Ends the progress line, if one is showing, so that what follows starts on a line of its own.
void end_progress_line();

class Stopwatch {
public:
    double seconds() const {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count();
    }

private:
    std::chrono::steady_clock::time_point m_start = std::chrono::steady_clock::now();
};

} // namespace ecoterra::app
