// ecoterra: grows synthetic off-road worlds. Thin subcommands over the libraries.
#include "common.hpp"
#include "subcommands.hpp"

#include "ecoterra/error.hpp"

#include <CLI/CLI.hpp>

#include <cstdio>

int main(int argc, char** argv) {
    ecoterra::app::set_command_line(argc, argv);
    CLI::App app{"ecoterra: synthetic off-road worlds (terrain, hydrology, vegetation)"};
    app.require_subcommand(1);
    app.set_version_flag("--version", std::string("ecoterra ") + ecoterra::app::version());
    ecoterra::app::add_terrain_command(app);
    ecoterra::app::add_hydro_command(app);
    ecoterra::app::add_eco_commands(app);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    } catch (const ecoterra::InputError& e) {
        std::fprintf(stderr, "ecoterra: error: %s\n", e.what());
        return 2;
    } catch (const ecoterra::Error& e) {
        std::fprintf(stderr, "ecoterra: error: %s\n", e.what());
        return 1;
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "ecoterra: error: out of memory\n");
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "ecoterra: internal error: %s\n", e.what());
        return 3;
    }
    return 0;
}
