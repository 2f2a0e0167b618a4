#pragma once
// A busy neighbour for the benchmarks: a child process that spins on one core until it is killed.
#include <csignal>
#include <cstdio>
#include <sys/wait.h>
#include <unistd.h>

namespace ecoterra::bench {

inline pid_t start_busy() {
    std::fflush(stdout);
    const pid_t pid = fork();
    if (pid == 0) {
        volatile unsigned long x = 0;
        for (;;) x = x + 1;
    }
    return pid;
}

inline void stop_busy(pid_t pid) {
    kill(pid, SIGKILL);
    waitpid(pid, nullptr, 0);
}

} // namespace ecoterra::bench
