#include "common.hpp"

#include "ecoterra/error.hpp"

#include <cstdarg>
#include <cstdio>
#include <filesystem>

namespace ecoterra::app {

namespace {
std::string& command_line_storage() {
    static std::string s;
    return s;
}
} // namespace

const char* version() {
    return ECOTERRA_VERSION;
}

void set_command_line(int argc, char** argv) {
    std::string s;
    for (int i = 0; i < argc; ++i) {
        if (i) s += ' ';
        s += argv[i];
    }
    command_line_storage() = s;
}

const std::string& command_line() {
    return command_line_storage();
}

nlohmann::json provenance(const nlohmann::json& extra) {
    nlohmann::json p = {
        {"software", "ecoterra"}, {"version", version()}, {"command_line", command_line()}};
    for (auto& [k, v] : extra.items()) p[k] = v;
    return p;
}

void refuse_output_over_input(const std::string& option, const std::string& output,
                              const std::vector<std::string>& inputs) {
    namespace fs = std::filesystem;
    if (output.empty()) return;
    for (const auto& in : inputs) {
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

void print_warnings(const std::vector<std::string>& warnings) {
    end_progress_line();
    for (const auto& w : warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
}

void print_notes(const std::vector<std::string>& notes) {
    end_progress_line();
    for (const auto& n : notes) std::fprintf(stderr, "note: %s\n", n.c_str());
}

namespace {
bool g_progress_showing = false;
}

void progress_line(const char* format, ...) {
    std::fflush(stdout); // what the command said before the progress, in order
    std::fputc('\r', stderr);
    va_list args;
    va_start(args, format);
    std::vfprintf(stderr, format, args);
    va_end(args);
    g_progress_showing = true;
}

void end_progress_line() {
    if (g_progress_showing) std::fputc('\n', stderr);
    g_progress_showing = false;
}

} // namespace ecoterra::app
