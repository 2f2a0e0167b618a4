#pragma once
// Memory: what a scene will need against what the machine has, so that a scene too large for the
// machine is refused at the start with its size and estimate named, not killed for want of memory
// hours later.
#include <cstdint>
#include <string>
#include <vector>

namespace ecoterra {

/// One term of an estimate: `count` items of `bytes_each`.
struct MemoryTerm {
    std::string what; ///< "terrain cells", "plants", ...
    double count = 0;
    double bytes_each = 0;
    double bytes() const { return count * bytes_each; }
};

struct MemoryEstimate {
    double fixed_bytes = 0; ///< the program, libraries and small tables
    std::vector<MemoryTerm> terms;
    double bytes() const;
    /// "1.9 GiB: 1,000,000 terrain cells x 570 B + ..."
    std::string describe() const;
};

/// Bytes the process may still use: the least of MemAvailable (/proc/meminfo) and the cgroup's
/// limit less its use (cgroup v2 memory.max, or v1 memory.limit_in_bytes). The environment
/// variable ECOTERRA_MEMORY_LIMIT_GIB, when set, replaces the machine's figure. `source` tells
/// which figure it was.
double available_memory_bytes(std::string* source = nullptr);

/// Throws InputError naming `what`, the estimate and what is available when the estimate exceeds
/// it.
void check_memory(const MemoryEstimate& need, const std::string& what);

} // namespace ecoterra
