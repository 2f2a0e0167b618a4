// `ecoterra ensemble`: many scenes from one manifest, on every core of this machine (--jobs), one
// member at a time (--member, for Slurm job arrays) or across machines under mpirun (rank 0 hands
// out members, the other ranks run them). Each member runs in a process of its own, so a member
// that crashes or is killed takes nothing else with it (docs/ensembles.md).
#include "common.hpp"
#include "subcommands.hpp"

#include "ecoterra/ensemble/manifest.hpp"
#include "ecoterra/ensemble/member.hpp"
#include "ecoterra/ensemble/summary.hpp"
#include "ecoterra/error.hpp"

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <map>
#include <memory>
#include <sched.h>
#include <spawn.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

#ifdef ECOTERRA_HAVE_MPI
#include <mpi.h>
#endif

extern char** environ;

namespace ecoterra::app {

namespace {

namespace fs = std::filesystem;
namespace en = ecoterra::ensemble;

struct EnsembleArgs {
    std::string manifest, output, summary;
    int jobs = 0, threads = 0;
    long long member = -1;
    bool list = false;
};

/// The cores this process may run on (its affinity mask: a Slurm or taskset limit counts).
int usable_cores() {
    cpu_set_t set;
    CPU_ZERO(&set);
    if (sched_getaffinity(0, sizeof set, &set) == 0) return std::max(1, CPU_COUNT(&set));
    return static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

/// Starts `ecoterra ensemble MANIFEST -o OUT --member I --threads T` with its output in `log`
/// and OMP_NUM_THREADS = T. Returns the child's pid.
pid_t spawn_member(const fs::path& manifest, const fs::path& out, std::size_t index, int threads,
                   const fs::path& log) {
    std::vector<std::string> args{"ecoterra",
                                  "ensemble",
                                  fs::absolute(manifest).string(),
                                  "-o",
                                  fs::absolute(out).string(),
                                  "--member",
                                  std::to_string(index),
                                  "--threads",
                                  std::to_string(threads)};
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    std::vector<std::string> env;
    for (char** e = environ; *e; ++e)
        if (std::strncmp(*e, "OMP_NUM_THREADS=", 16) != 0) env.emplace_back(*e);
    env.push_back("OMP_NUM_THREADS=" + std::to_string(threads));
    std::vector<char*> envp;
    for (auto& e : env) envp.push_back(e.data());
    envp.push_back(nullptr);
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&fa, STDOUT_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                     0644);
    posix_spawn_file_actions_adddup2(&fa, STDOUT_FILENO, STDERR_FILENO);
    pid_t pid = 0;
    const int rc = posix_spawn(&pid, "/proc/self/exe", &fa, nullptr, argv.data(), envp.data());
    posix_spawn_file_actions_destroy(&fa);
    if (rc != 0) throw Error("cannot start a member process: " + std::string(std::strerror(rc)));
    return pid;
}

/// What a finished member process tells: 0 ok, 1 failed (it wrote its record), anything else a
/// crash, recorded here. Returns true when the member succeeded.
bool settle(const fs::path& out, const en::Manifest& m, std::size_t index, int status,
            const fs::path& log, std::string* error) {
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return true;
    const en::Member mb = en::make_member(m, index);
    if (WIFEXITED(status) && WEXITSTATUS(status) == 1) {
        const auto r = en::read_member_record(out, m, index);
        if (error && r) *error = r->value("error", "failed");
        return false;
    }
    const std::string why =
        WIFSIGNALED(status)
            ? "the member process was killed by signal " + std::to_string(WTERMSIG(status)) + " (" +
                  strsignal(WTERMSIG(status)) + ")"
            : "the member process exited with code " + std::to_string(WEXITSTATUS(status));
    en::record_crashed_member(out, m, mb, why, log);
    if (error) *error = why;
    return false;
}

fs::path log_path(const fs::path& out, const en::Manifest& m, std::size_t index) {
    return out / "logs" / (en::member_name(m, index) + ".log");
}

/// Members not yet done with these inputs, in index order.
std::vector<std::size_t> todo_list(const fs::path& out, const en::Manifest& m) {
    std::vector<std::size_t> todo;
    for (std::size_t i = 0; i < m.members(); ++i)
        if (!en::member_done(out, m, en::make_member(m, i))) todo.push_back(i);
    return todo;
}

void print_plan(const en::Manifest& m, std::size_t todo, const std::string& how) {
    std::printf("ensemble %s (%s): %zu members = %zu combinations x %d replicates; %zu done "
                "before, %zu to run%s\n",
                m.name.c_str(), m.file.string().c_str(), m.members(), m.combinations(),
                m.replicates, m.members() - todo, todo, todo ? (": " + how).c_str() : "");
}

/// Writes the summary and says what it holds; returns the exit code (1 when members failed).
int finish(const fs::path& out, const en::Manifest& m, double seconds, std::size_t ran) {
    const auto rep = en::write_summary(out, m);
    if (ran > 0)
        std::printf("%zu members run in %.1f s (%.3g members/hour)\n", ran, seconds,
                    3600.0 * static_cast<double>(ran) / std::max(seconds, 1e-9));
    std::printf("%zu of %zu members ok, %zu failed, %zu not run\n", rep.ok, rep.members, rep.failed,
                rep.missing);
    for (std::size_t k = 0; k < rep.failures.size() && k < 10; ++k)
        std::printf("  failed %s\n", rep.failures[k].c_str());
    if (rep.failures.size() > 10)
        std::printf("  ... and %zu more (summary/members.csv, column error)\n",
                    rep.failures.size() - 10);
    std::vector<std::size_t> redo = rep.failed_members;
    redo.insert(redo.end(), rep.missing_members.begin(), rep.missing_members.end());
    std::sort(redo.begin(), redo.end());
    if (!redo.empty())
        std::printf("to run them again: the same command (finished members are kept), or a "
                    "Slurm array: sbatch --array=%s ... ecoterra ensemble %s -o %s --member "
                    "$SLURM_ARRAY_TASK_ID\n",
                    en::index_ranges(redo).c_str(), m.file.string().c_str(), out.string().c_str());
    std::printf("summary:");
    for (const auto& f : rep.files) std::printf(" %s", f.string().c_str());
    std::printf("\n");
    return rep.failed + rep.missing > 0 ? 1 : 0;
}

int run_local(const EnsembleArgs& a, const en::Manifest& m) {
    const fs::path out = a.output;
    en::prepare_output(out, m);
    en::sweep_stale_stages(out);
    const auto todo = todo_list(out, m);
    const int cores = usable_cores();
    const int jobs =
        std::max(1, std::min<int>(a.jobs > 0 ? a.jobs : cores,
                                  static_cast<int>(std::max<std::size_t>(1, todo.size()))));
    const int threads = a.threads > 0 ? a.threads : std::max(1, cores / jobs);
    print_plan(m, todo.size(),
               std::to_string(jobs) + (jobs == 1 ? " process" : " processes") + " of " +
                   std::to_string(threads) + (threads == 1 ? " thread" : " threads"));
    Stopwatch sw;
    std::map<pid_t, std::size_t> running;
    std::size_t next = 0, done = 0, failed = 0;
    while (next < todo.size() || !running.empty()) {
        while (next < todo.size() && static_cast<int>(running.size()) < jobs) {
            const std::size_t i = todo[next++];
            running[spawn_member(m.file, out, i, threads, log_path(out, m, i))] = i;
        }
        int status = 0;
        const pid_t pid = waitpid(-1, &status, 0); // sleeps until a member ends
        if (pid < 0) {
            if (errno == EINTR) continue;
            throw Error(std::string("waiting for the members: ") + std::strerror(errno));
        }
        const auto it = running.find(pid);
        if (it == running.end()) continue;
        const std::size_t i = it->second;
        running.erase(it);
        if (!settle(out, m, i, status, log_path(out, m, i), nullptr)) ++failed;
        ++done;
        progress_line(static_cast<double>(done) / static_cast<double>(todo.size()), sw.seconds(),
                      "  %zu of %zu members, %zu failed  ", done, todo.size(), failed);
    }
    end_progress_line();
    return finish(out, m, sw.seconds(), todo.size());
}

int run_one(const EnsembleArgs& a, const en::Manifest& m) {
    const fs::path out = a.output;
    en::prepare_output(out, m);
    const en::Member mb = en::make_member(m, static_cast<std::size_t>(a.member));
    if (en::member_done(out, m, mb)) {
        std::printf("member %lld of %s is done with these inputs (%s): nothing to do\n", a.member,
                    m.name.c_str(), en::member_dir(out, m, mb.index).string().c_str());
        return 0;
    }
    const int threads = a.threads > 0 ? a.threads : 1;
    const auto o = en::run_member(out, m, mb, threads);
    if (o.ok) {
        std::printf("member %lld of %s: ok in %.2f s (%s)\n", a.member, m.name.c_str(), o.seconds,
                    en::member_dir(out, m, mb.index).string().c_str());
        return 0;
    }
    std::printf("member %lld of %s: failed: %s\n", a.member, m.name.c_str(), o.error.c_str());
    return 1;
}

void list_members(const en::Manifest& m) {
    std::printf("ensemble %s: %zu members = %zu combinations x %d replicates (%s base)\n",
                m.name.c_str(), m.members(), m.combinations(), m.replicates,
                en::base_kind_name(m.kind));
    std::printf("member,combination,replicate,seed,input_hash");
    for (const auto& ax : m.axes) std::printf(",%s", ax.key.c_str());
    std::printf("\n");
    for (std::size_t i = 0; i < m.members(); ++i) {
        const auto mb = en::make_member(m, i);
        std::printf("%zu,%zu,%d,%llu,%s", i, mb.combination, mb.replicate,
                    static_cast<unsigned long long>(mb.seed), mb.input_hash.c_str());
        for (const auto& [k, v] : mb.axes) std::printf(",%s", en::value_text(v).c_str());
        std::printf("\n");
    }
}

/// The number of processes mpirun (or another MPI launcher) started, from its environment; 0
/// when this process was not started by one.
int launcher_size() {
    for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_SIZE"})
        if (const char* s = std::getenv(v)) return std::atoi(s);
    return 0;
}

#ifdef ECOTERRA_HAVE_MPI

/// Waits for a request without spinning: MPI_Test, then a sleep that grows to 20 ms.
void wait_quietly(MPI_Request& req) {
    int flag = 0;
    useconds_t nap = 200;
    for (;;) {
        MPI_Test(&req, &flag, MPI_STATUS_IGNORE);
        if (flag) return;
        usleep(nap);
        nap = std::min<useconds_t>(nap * 2, 20000);
    }
}

void quiet_barrier() {
    MPI_Request req;
    MPI_Ibarrier(MPI_COMM_WORLD, &req);
    wait_quietly(req);
}

constexpr int kTagReady = 1, kTagAssign = 2;

/// Rank 0 prepares the output and tells the workers whether to go on; throws when it cannot.
void mpi_prepare(const fs::path& out, const en::Manifest& m) {
    std::string error;
    try {
        en::prepare_output(out, m);
    } catch (const std::exception& e) {
        error = e.what();
    }
    int bad = error.empty() ? 0 : 1;
    MPI_Bcast(&bad, 1, MPI_INT, 0, MPI_COMM_WORLD);
    if (bad) {
        MPI_Finalize();
        throw InputError(error);
    }
}

/// Rank 0 hands out the members one at a time to the worker that asks, sleeping (not spinning)
/// between requests; returns the exit code.
int mpi_lead(const EnsembleArgs& a, const en::Manifest& m, int size) {
    const fs::path out = a.output;
    mpi_prepare(out, m);
    en::sweep_stale_stages(out);
    const auto todo = todo_list(out, m);
    const int threads = a.threads > 0 ? a.threads : 1;
    print_plan(m, todo.size(),
               std::to_string(size - 1) + " worker ranks of " + std::to_string(threads) +
                   (threads == 1 ? " thread" : " threads") + " (rank 0 hands out members)");
    Stopwatch sw;
    std::size_t next = 0, done = 0, failed = 0, handed = 0;
    int active = size - 1;
    double handing_s = 0;
    useconds_t nap = 200;
    while (active > 0) {
        int flag = 0;
        MPI_Status st;
        MPI_Iprobe(MPI_ANY_SOURCE, kTagReady, MPI_COMM_WORLD, &flag, &st);
        if (!flag) {
            usleep(nap); // sleep, not spin, while the workers run
            nap = std::min<useconds_t>(nap * 2, 20000);
            continue;
        }
        nap = 200;
        Stopwatch hand;
        long long msg[2];
        MPI_Recv(msg, 2, MPI_LONG_LONG, st.MPI_SOURCE, kTagReady, MPI_COMM_WORLD,
                 MPI_STATUS_IGNORE);
        if (msg[0] >= 0) {
            ++done;
            failed += msg[1] != 0;
        }
        long long assign = next < todo.size() ? static_cast<long long>(todo[next++]) : -1;
        if (assign < 0) --active;
        MPI_Send(&assign, 1, MPI_LONG_LONG, st.MPI_SOURCE, kTagAssign, MPI_COMM_WORLD);
        if (assign >= 0) {
            handing_s += hand.seconds();
            ++handed;
        }
        if (msg[0] >= 0)
            progress_line(static_cast<double>(done) / static_cast<double>(todo.size()),
                          sw.seconds(), "  %zu of %zu members, %zu failed  ", done, todo.size(),
                          failed);
    }
    end_progress_line();
    if (handed > 0)
        std::printf("rank 0 spent %.1f us per member handing out work (%zu members)\n",
                    1e6 * handing_s / static_cast<double>(handed), handed);
    return finish(out, m, sw.seconds(), todo.size());
}

/// A worker rank asks rank 0 for a member, runs it as a child process, reports, and asks again
/// until told to stop; returns false when rank 0 could not prepare the output.
bool mpi_work(const EnsembleArgs& a, const en::Manifest& m) {
    int bad = 0;
    MPI_Bcast(&bad, 1, MPI_INT, 0, MPI_COMM_WORLD);
    if (bad) return false;
    const fs::path out = a.output;
    const int threads = a.threads > 0 ? a.threads : 1;
    long long last[2] = {-1, 0};
    for (;;) {
        MPI_Send(last, 2, MPI_LONG_LONG, 0, kTagReady, MPI_COMM_WORLD);
        long long assign = -1;
        MPI_Request req;
        MPI_Irecv(&assign, 1, MPI_LONG_LONG, 0, kTagAssign, MPI_COMM_WORLD, &req);
        wait_quietly(req);
        if (assign < 0) break;
        const auto i = static_cast<std::size_t>(assign);
        const fs::path log = log_path(out, m, i);
        const pid_t pid = spawn_member(m.file, out, i, threads, log);
        int status = 0;
        while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
        }
        last[0] = assign;
        last[1] = settle(out, m, i, status, log, nullptr) ? 0 : 1;
    }
    return true;
}

int run_mpi(const EnsembleArgs& a, const en::Manifest& m) {
    MPI_Init(nullptr, nullptr);
    int rank = 0, size = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    int code = 0;
    if (rank == 0) {
        code = mpi_lead(a, m, size);
    } else if (!mpi_work(a, m)) {
        MPI_Finalize();
        return 2;
    }
    quiet_barrier();
    MPI_Finalize();
    return code;
}

#endif

int run_ensemble(const EnsembleArgs& a) {
    if (!a.summary.empty()) {
        if (!a.manifest.empty() || !a.output.empty())
            throw InputError("--summary DIR gathers an ensemble's folder; give no manifest or -o");
        const auto m = en::manifest_of_output(a.summary);
        return finish(a.summary, m, 0, 0);
    }
    if (a.manifest.empty()) throw InputError("ensemble: give a manifest (data/studies/*.json)");
    const auto m = en::load_manifest(a.manifest);
    if (a.list) {
        list_members(m);
        return 0;
    }
    if (a.output.empty()) throw InputError("ensemble: give the output folder with -o DIR");
    refuse_output_over_input("-o", a.output, {a.manifest});
    if (a.member >= 0 || a.member < -1) {
        if (a.member < 0 || static_cast<std::size_t>(a.member) >= m.members())
            throw InputError("--member " + std::to_string(a.member) + " is out of range: " +
                             a.manifest + " has members 0 to " + std::to_string(m.members() - 1));
        return run_one(a, m);
    }
    if (a.jobs < 0) throw InputError("--jobs " + std::to_string(a.jobs) + ": must be 1 or more");
    if (a.threads < 0)
        throw InputError("--threads " + std::to_string(a.threads) + ": must be 1 or more");
    if (launcher_size() > 1) {
#ifdef ECOTERRA_HAVE_MPI
        return run_mpi(a, m);
#else
        throw InputError("started by mpirun with " + std::to_string(launcher_size()) +
                         " processes, but this ecoterra was built without MPI: each would run "
                         "the whole ensemble. Use --jobs N on one machine, or --member I per "
                         "job (Slurm arrays), or rebuild with libopenmpi-dev installed");
#endif
    }
    return run_local(a, m);
}

} // namespace

void add_ensemble_command(CLI::App& app) {
    auto a = std::make_shared<EnsembleArgs>();
    CLI::App* e = app.add_subcommand(
        "ensemble", "many scenes from one manifest: on every core (--jobs), one member "
                    "(--member, for Slurm arrays) or across machines under mpirun");
    e->add_option("manifest", a->manifest, "ensemble manifest JSON (docs/ensembles.md)");
    e->add_option("-o,--output", a->output, "output folder (rerunning resumes it)");
    e->add_option("--jobs", a->jobs, "member processes at once (default: the usable cores)");
    e->add_option("--threads", a->threads,
                  "threads per member (default: cores / jobs; 1 under mpirun and --member)");
    e->add_option("--member", a->member,
                  "run only this member (0-based), e.g. "
                  "$SLURM_ARRAY_TASK_ID");
    e->add_option("--summary", a->summary, "gather the summary of this output folder, as it is");
    e->add_flag("--list", a->list, "list the members (axes, seeds, input hashes) and stop");
    e->callback([a] { set_exit_code(run_ensemble(*a)); });
}

} // namespace ecoterra::app
