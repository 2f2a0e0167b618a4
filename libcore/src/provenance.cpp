#include "ecoterra/provenance.hpp"

namespace ecoterra {

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
    nlohmann::json p = {{"software", "ecoterra"}, {"version", version()}};
    for (const auto& [k, v] : extra.items()) p[k] = v;
    return p;
}

nlohmann::json command_provenance(const nlohmann::json& extra) {
    nlohmann::json p = provenance({{"command_line", command_line()}});
    for (const auto& [k, v] : extra.items()) p[k] = v;
    return p;
}

} // namespace ecoterra
