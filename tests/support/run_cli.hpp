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

/// Runs a shell command in `dir`, capturing its output and exit code.
inline Run shell(const TempDir& dir, const std::string& command) {
    const std::string cmd = "cd '" + dir.path().string() + "' && " + command + " 2>&1";
    Run r;
    FILE* p = popen(cmd.c_str(), "r");
    REQUIRE(p != nullptr);
    std::array<char, 4096> buf{};
    while (fgets(buf.data(), buf.size(), p)) r.out += buf.data();
    const int status = pclose(p);
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}

/// Runs the ecoterra program with `args` in `dir` (`env`: assignments put before it).
inline Run run(const TempDir& dir, const std::string& args, const std::string& env = "") {
    return shell(dir, env + " '" ECOTERRA_BIN "' " + args);
}

} // namespace ecoterra::test
