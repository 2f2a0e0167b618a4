#include "common.hpp"

#include <cstdio>

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

void print_warnings(const std::vector<std::string>& warnings) {
    for (const auto& w : warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
}

} // namespace ecoterra::app
