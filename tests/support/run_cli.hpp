#pragma once
// Runs the ecoterra program in a folder, as a user would, capturing its output and exit code.
#include "support/temp_dir.hpp"

#include <catch2/catch.hpp>

#include <array>
#include <cstdio>
#include <string>
#include <sys/wait.h>

namespace ecoterra::test {

struct Run {
    int code = -1;
    std::string out; ///< stdout and stderr
};

inline Run run(const TempDir& dir, const std::string& args, const std::string& env = "") {
    const std::string cmd =
        "cd '" + dir.path().string() + "' && " + env + " '" ECOTERRA_BIN "' " + args + " 2>&1";
    Run r;
    FILE* p = popen(cmd.c_str(), "r");
    REQUIRE(p != nullptr);
    std::array<char, 4096> buf{};
    while (fgets(buf.data(), buf.size(), p)) r.out += buf.data();
    const int status = pclose(p);
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}

} // namespace ecoterra::test
