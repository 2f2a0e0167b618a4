// ecoterra: grows synthetic off-road worlds. Thin subcommands over the libraries.
#include "common.hpp"
#include "subcommands.hpp"

#include "ecoterra/error.hpp"
#include "ecoterra/wait_policy.hpp"

#include <CLI/CLI.hpp>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

namespace {

/// Prints an error on a line of its own, after what the program printed so far.
void report(const char* kind, const char* what) {
    std::fflush(stdout);
    ecoterra::app::end_progress_line();
    std::fprintf(stderr, "ecoterra: %s: %s\n", kind, what);
}
} // namespace

int main(int argc, char** argv) {
    ecoterra::ensure_passive_wait(argv);
    // A file over the size limit (ulimit -f) is a write error to report, not a fatal signal.
    std::signal(SIGXFSZ, SIG_IGN);
    ecoterra::set_command_line(argc, argv);
    CLI::App app{"ecoterra: synthetic off-road worlds (terrain, hydrology, vegetation)"};
    app.require_subcommand(1);
    // --help shows every option's default (subcommands inherit this when they are added).
    app.option_defaults()->always_capture_default();
    app.set_version_flag("--version", std::string("ecoterra ") + ecoterra::version());
    ecoterra::app::add_terrain_command(app);
    ecoterra::app::add_hydro_command(app);
    ecoterra::app::add_eco_commands(app);
    ecoterra::app::add_mobility_command(app);
    ecoterra::app::add_ensemble_command(app);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        // --help and --version exit 0; every usage error is bad input: exit 2, as documented.
        const int code = app.exit(e);
        return code == 0 ? 0 : 2;
    } catch (const nlohmann::json::exception& e) {
        // JSON errors the readers did not put in context (they name the file where they can).
        report("error", e.what());
        return 2;
    } catch (const ecoterra::InputError& e) {
        report("error", e.what());
        return 2;
    } catch (const ecoterra::Error& e) {
        report("error", e.what());
        return 1;
    } catch (const std::filesystem::filesystem_error& e) {
        // A folder or file the system refuses (read-only, no permission, no space): a failure to
        // write, named by its path, not an internal error.
        const std::string path = e.path1().empty() ? "" : e.path1().string() + ": ";
        report("error", (path + "cannot write or read here (" + e.code().message() + ")").c_str());
        return 1;
    } catch (const std::bad_alloc&) {
        report("error", "out of memory");
        return 1;
    } catch (const std::exception& e) {
        report("internal error", e.what());
        return 3;
    }
    return ecoterra::app::exit_code();
}
