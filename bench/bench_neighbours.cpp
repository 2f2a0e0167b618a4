// Good neighbours: the wall time of an `ecoterra run` alone and beside 0, 1 and 2 busy processes
// (each a process that spins on one core), with ecoterra's default wait policy (threads sleep
// while they wait) and with OMP_WAIT_POLICY=active (threads spin), as ratios to the time alone.
// A fair share of a 2-core machine beside two busy processes is about 2x.
// Usage: bench_neighbours [--years N] [--repeat R] [--scene FILE]
#include "busy.hpp"

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

namespace {

/// Runs the command (argv) with OMP_WAIT_POLICY set as given ("" = unset); returns seconds.
double timed_run(const std::vector<std::string>& args, const std::string& policy) {
    std::fflush(stdout);
    const auto t0 = std::chrono::steady_clock::now();
    const pid_t pid = fork();
    if (pid == 0) {
        if (policy.empty())
            unsetenv("OMP_WAIT_POLICY");
        else
            setenv("OMP_WAIT_POLICY", policy.c_str(), 1);
        std::vector<char*> argv;
        for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
        argv.push_back(nullptr);
        if (!std::freopen("/dev/null", "w", stdout) || !std::freopen("/dev/null", "w", stderr))
            _exit(126);
        execv(argv[0], argv.data());
        _exit(127);
    }
    int status = 0;
    waitpid(pid, &status, 0);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        std::fprintf(stderr, "bench_neighbours: the run failed (status %d)\n", status);
        std::exit(1);
    }
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

} // namespace

int main(int argc, char** argv) {
    int years = 20, repeat = 3;
    std::string scene = std::string(ECOTERRA_DATA_DIR) + "/scenes/quickstart.json";
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--years") && i + 1 < argc)
            years = std::atoi(argv[++i]);
        else if (!std::strcmp(argv[i], "--repeat") && i + 1 < argc)
            repeat = std::atoi(argv[++i]);
        else if (!std::strcmp(argv[i], "--scene") && i + 1 < argc)
            scene = argv[++i];
        else {
            std::fprintf(stderr, "usage: bench_neighbours [--years N] [--repeat R] [--scene F]\n");
            return 2;
        }
    }
    char tmpl[] = "/tmp/ecoterra-neighbours-XXXXXX";
    if (!mkdtemp(tmpl)) return 1;
    const std::string out = std::string(tmpl) + "/run.h5";
    const std::vector<std::string> cmd = {ECOTERRA_BIN,
                                          "run",
                                          scene,
                                          "-o",
                                          out,
                                          "--set",
                                          "simulation.years=" + std::to_string(years),
                                          "--no-pictures",
                                          "--force"};
    std::printf("ecoterra run %s, %d years; median of %d runs; %ld cores\n", scene.c_str(), years,
                repeat, sysconf(_SC_NPROCESSORS_ONLN));
    std::printf("%-14s %-26s %10s %12s\n", "busy neighbours", "wait policy", "seconds", "x alone");
    for (const char* policy : {"", "active"}) {
        double alone = 0;
        for (int busy = 0; busy <= 2; ++busy) {
            std::vector<pid_t> spinners;
            for (int b = 0; b < busy; ++b) spinners.push_back(ecoterra::bench::start_busy());
            std::vector<double> t;
            for (int r = 0; r < repeat; ++r) t.push_back(timed_run(cmd, policy));
            for (const pid_t p : spinners) ecoterra::bench::stop_busy(p);
            std::sort(t.begin(), t.end());
            const double med = t[t.size() / 2];
            if (busy == 0) alone = med;
            std::printf("%-14d %-26s %10.2f %12.2f\n", busy,
                        *policy ? "active (spin)" : "default (passive, sleeps)", med, med / alone);
        }
    }
    std::filesystem::remove_all(tmpl);
    return 0;
}
