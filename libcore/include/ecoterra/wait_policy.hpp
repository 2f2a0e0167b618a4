#pragma once
// The OpenMP wait policy ecoterra's programs run under.
#include <cstdlib>
#include <unistd.h>

namespace ecoterra {

/// OpenMP threads that wait for work spin by default (libgomp busy-waits for a while before it
/// sleeps), which steals the core a working thread needs when the machine is shared: beside two
/// busy processes on two cores a run took 6-14 times as long as alone. libgomp reads
/// OMP_WAIT_POLICY once, before main, so when the user has not chosen a policy the program starts
/// itself again with the passive one (threads sleep while they wait). Results do not depend on
/// the policy; OMP_WAIT_POLICY=active restores spinning for a machine of one's own. Called first
/// in main by `ecoterra` and by the benchmarks, so that they time what the program does.
inline void ensure_passive_wait(char** argv) {
    if (std::getenv("OMP_WAIT_POLICY") != nullptr) return;
    if (setenv("OMP_WAIT_POLICY", "passive", 1) != 0) return;
    execv("/proc/self/exe", argv);
    // Only reached if the new start failed: go on with the runtime as it is.
}

} // namespace ecoterra
