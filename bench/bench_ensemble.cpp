// Ensembles: members per hour of the 1 ha quickstart (data/scenes/quickstart.json, 40 years,
// stand metrics per member) with 1 and 2 member processes, the scaling between them, the
// per-member overhead of the driver against a bare `ecoterra run` of the same scene, and under
// mpirun the time rank 0 spends handing out each member. Quiet, then beside one busy process.
// Usage: bench_ensemble [--members N] [--no-mpi]
#include "busy.hpp"

#include <nlohmann/json.hpp>

#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

namespace {

namespace fs = std::filesystem;

struct Result {
    double seconds = 0;
    std::string out;
};

/// Runs a shell command, capturing its output; exits when it fails.
Result run(const std::string& cmd) {
    std::fflush(stdout);
    const auto t0 = std::chrono::steady_clock::now();
    Result r;
    FILE* p = popen((cmd + " 2>&1").c_str(), "r");
    if (!p) std::exit(1);
    std::array<char, 4096> buf{};
    while (fgets(buf.data(), buf.size(), p)) r.out += buf.data();
    const int status = pclose(p);
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (status != 0) {
        std::fprintf(stderr, "bench_ensemble: '%s' failed:\n%s\n", cmd.c_str(), r.out.c_str());
        std::exit(1);
    }
    return r;
}

} // namespace

int main(int argc, char** argv) {
    int members = 12;
    bool mpi = true;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--members") && i + 1 < argc)
            members = std::atoi(argv[++i]);
        else if (!std::strcmp(argv[i], "--no-mpi"))
            mpi = false;
        else {
            std::fprintf(stderr, "usage: bench_ensemble [--members N] [--no-mpi]\n");
            return 2;
        }
    }
    if (members < 2) members = 2;
    char tmpl[] = "/tmp/ecoterra-bench-ensemble-XXXXXX";
    if (!mkdtemp(tmpl)) return 1;
    const fs::path dir = tmpl;
    const std::string data = ECOTERRA_DATA_DIR, bin = ECOTERRA_BIN;
    const nlohmann::json manifest = {{"name", "bench"},
                                     {"base", {{"run", data + "/scenes/quickstart.json"}}},
                                     {"replicates", members},
                                     {"analyses", {{"stand", nlohmann::json::object()}}}};
    std::ofstream(dir / "m.json") << manifest.dump(1);
    const std::string m = (dir / "m.json").string();
    std::printf("ecoterra ensemble benchmark: the 1 ha quickstart (50 x 50 cells of 2 m, 40 "
                "years), %d members; %ld cores\n",
                members, sysconf(_SC_NPROCESSORS_ONLN));
    for (int busy = 0; busy <= 1; ++busy) {
        const pid_t spinner = busy ? ecoterra::bench::start_busy() : 0;
        std::printf("\n%s\n", busy ? "beside one busy process" : "quiet");
        // A bare run per member, one thread (what a member process does with --jobs 2 on 2 cores).
        double bare = 0;
        const int bare_runs = 3;
        for (int k = 0; k < bare_runs; ++k)
            bare += run("OMP_NUM_THREADS=1 '" + bin + "' run " + data +
                        "/scenes/quickstart.json --no-pictures -o " + (dir / "bare.h5").string() +
                        " --seed " + std::to_string(k + 1))
                        .seconds /
                    bare_runs;
        double rate1 = 0;
        for (int jobs : {1, 2}) {
            fs::remove_all(dir / "out");
            const Result r = run("'" + bin + "' ensemble " + m + " -o " + (dir / "out").string() +
                                 " --jobs " + std::to_string(jobs) + " --threads 1");
            const double per_hour = 3600.0 * members / r.seconds;
            if (jobs == 1) rate1 = per_hour;
            std::printf("  --jobs %d: %.1f s, %.0f members/hour", jobs, r.seconds, per_hour);
            if (jobs == 1)
                std::printf(", %.3f s per member against %.3f s for a bare run: overhead %.0f ms "
                            "(%.1f %%)\n",
                            r.seconds / members, bare, 1e3 * (r.seconds / members - bare),
                            100 * (r.seconds / members / bare - 1));
            else
                std::printf(", %.2f x the rate of one process\n", per_hour / rate1);
        }
        if (mpi && std::system("command -v mpirun > /dev/null 2>&1") == 0) {
            fs::remove_all(dir / "out");
            const Result r = run("mpirun --allow-run-as-root --oversubscribe -np 3 '" + bin +
                                 "' ensemble " + m + " -o " + (dir / "out").string());
            const auto at = r.out.find("rank 0 spent");
            const double per_hour = 3600.0 * members / r.seconds;
            std::printf(
                "  mpirun -np 3 (2 workers): %.1f s, %.0f members/hour; %s", r.seconds, per_hour,
                at == std::string::npos ? "(this ecoterra has no MPI)\n"
                                        : r.out.substr(at, r.out.find('\n', at) - at + 1).c_str());
        }
        if (spinner) ecoterra::bench::stop_busy(spinner);
    }
    fs::remove_all(dir);
    return 0;
}
