#pragma once
// Where an output came from: the software, its version and, for the outputs of one command, its
// command line. The one place the version string and the provenance record are made.
#include <nlohmann/json.hpp>

#include <string>

namespace ecoterra {

/// ecoterra's version (the project version of the build, CMakeLists.txt).
const char* version();

/// Remembers this process's command line for command_provenance().
void set_command_line(int argc, char** argv);
const std::string& command_line();

/// {"software": "ecoterra", "version": version()} with the entries of `extra` merged in.
nlohmann::json provenance(const nlohmann::json& extra = nlohmann::json::object());
/// provenance() with "command_line": the record of one command's outputs. (Ensemble members leave
/// the command line out: a member is a function of its manifest and index only.)
nlohmann::json command_provenance(const nlohmann::json& extra = nlohmann::json::object());

} // namespace ecoterra
