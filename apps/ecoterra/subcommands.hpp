#pragma once
#include <CLI/CLI.hpp>

namespace ecoterra::app {

/// `ecoterra terrain generate|analyze|missions|convert`.
void add_terrain_command(CLI::App& app);
/// `ecoterra hydro soil|et|pond|run`.
void add_hydro_command(CLI::App& app);
/// `ecoterra run`, `ecoterra stand`, `ecoterra export vegetation`.
void add_eco_commands(CLI::App& app);
/// `export scene` and `export layers`, under the `export` command.
void add_export_scene_commands(CLI::App& exp);
/// `ecoterra mobility`.
void add_mobility_command(CLI::App& app);
/// `ecoterra ensemble`.
void add_ensemble_command(CLI::App& app);

} // namespace ecoterra::app
