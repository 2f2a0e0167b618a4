#include "common.hpp"

#include "ecoterra/error.hpp"
#include "ecoterra/io/hdf5_writer.hpp"
#include "ecoterra/terrain/io/raster_io.hpp"

#include <algorithm>
#include <cstdarg>
#include <cstdio>
#include <filesystem>
#include <unistd.h>

namespace ecoterra::app {

void refuse_output_over_input(const std::string& option, const std::string& output,
                              const std::vector<std::string>& inputs) {
    namespace fs = std::filesystem;
    if (output.empty()) return;
    for (const auto& reference : inputs) {
        const std::string in = raster_file_part(reference);
        if (in.empty()) continue;
        std::error_code ec;
        const bool same = fs::exists(output, ec) && fs::exists(in, ec)
                              ? fs::equivalent(output, in, ec)
                              : fs::weakly_canonical(output, ec) == fs::weakly_canonical(in, ec);
        if (same)
            throw InputError(option + " " + output + ": the output is the input " + in +
                             "; writing it would destroy the input (choose another path)");
    }
}

void claim_output(const std::string& option, const std::string& path, bool force) {
    namespace fs = std::filesystem;
    if (path.empty()) return;
    std::error_code ec;
    const auto st = fs::status(path, ec);
    if (!fs::exists(st)) return;
    const bool folder = fs::is_directory(st);
    if (folder && fs::is_empty(path, ec)) return;
    const std::string what = folder ? "the folder exists with files in it" : "the file exists";
    if (!force)
        throw InputError(option + " " + path + ": " + what +
                         "; give --force to replace it (nothing was written)");
    end_progress_line();
    std::fprintf(stderr, "note: %s %s: %s and is replaced (--force)\n", option.c_str(),
                 path.c_str(), what.c_str());
}

void add_force_flag(CLI::App* command, bool& force) {
    command->add_flag("--force", force,
                      "replace existing outputs (without it an existing output file, or an output "
                      "folder with files in it, is refused)");
}

std::string raster_file_part(const std::string& reference) {
    return terrain::io::split_hdf5_reference(reference).first;
}

void refuse_over_run_file(const std::string& option, const std::string& path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (path.empty() || !fs::is_regular_file(path, ec)) return;
    // HDF5's signature at offset 0 (files ecoterra writes have no user block).
    const std::string what = io::hdf5_run_kind(path);
    if (!what.empty())
        throw InputError(option + " " + path + ": is " + what +
                         "; a raster written there would destroy it, with or without --force "
                         "(choose another path)");
}

void print_warnings(const std::vector<std::string>& warnings) {
    end_progress_line();
    std::fflush(stdout); // after what was printed before them
    for (const auto& w : warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
}

void print_notes(const std::vector<std::string>& notes) {
    end_progress_line();
    std::fflush(stdout);
    for (const auto& n : notes) std::fprintf(stderr, "note: %s\n", n.c_str());
}

void print_terrain_source(const nlohmann::json& r) {
    if (!r.contains("size")) return;
    const auto& src = r["source"];
    const std::string crs = r.value("crs", std::string());
    const int epsg = r.value("epsg", 0);
    std::printf("terrain: %s, window %s, %d x %d cells of %.6g m by GDAL's warper (%s) from its "
                "%d x %d cells of %.6g %s%s; %s%s\n",
                r["file"].get<std::string>().c_str(), r["window"].dump().c_str(),
                r["size"][0].get<int>(), r["size"][1].get<int>(), r["cell_m"].get<double>(),
                r["resampling"].get<std::string>().c_str(), src["size"][0].get<int>(),
                src["size"][1].get<int>(), src["cell"].get<double>(),
                src.value("units", std::string("m")).c_str(),
                r.value("reprojected", false) ? " (reprojected)" : "",
                crs.empty() ? "no coordinate system" : crs.c_str(),
                epsg ? (" (EPSG:" + std::to_string(epsg) + ")").c_str() : "");
}

namespace {
int g_exit_code = 0;
} // namespace

void set_exit_code(int code) {
    g_exit_code = code;
}
int exit_code() {
    return g_exit_code;
}

namespace {
bool g_progress_showing = false;
int g_progress_logged_tenths = -1; ///< in a log: the last 10 % step written

std::string eta_text(double fraction, double elapsed_s) {
    if (!(fraction > 0) || fraction >= 1) return "";
    const double left = elapsed_s * (1 - fraction) / fraction;
    char buf[48];
    if (left < 90)
        std::snprintf(buf, sizeof buf, "ETA %.0f s", left);
    else if (left < 5400)
        std::snprintf(buf, sizeof buf, "ETA %.0f min", left / 60);
    else
        std::snprintf(buf, sizeof buf, "ETA %.1f h", left / 3600);
    return buf;
}
} // namespace

void progress_line(double fraction, double elapsed_s, const char* format, ...) {
    static const bool terminal = ::isatty(STDERR_FILENO) == 1;
    fraction = std::clamp(fraction, 0.0, 1.0);
    const int tenths = static_cast<int>(fraction * 10 + 1e-9);
    if (!terminal && tenths <= g_progress_logged_tenths) return;
    std::fflush(stdout); // what the command said before the progress, in order
    if (terminal) std::fputc('\r', stderr);
    va_list args;
    va_start(args, format);
    std::vfprintf(stderr, format, args);
    va_end(args);
    std::fprintf(stderr, "%3.0f %%  %s   ", 100 * fraction, eta_text(fraction, elapsed_s).c_str());
    if (terminal) {
        g_progress_showing = true;
    } else {
        std::fputc('\n', stderr);
        g_progress_logged_tenths = tenths;
    }
}

void end_progress_line() {
    if (g_progress_showing) std::fputc('\n', stderr);
    g_progress_showing = false;
    g_progress_logged_tenths = -1;
}

} // namespace ecoterra::app
