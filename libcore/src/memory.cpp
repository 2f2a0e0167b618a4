#include "ecoterra/memory.hpp"

#include "ecoterra/error.hpp"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>

namespace ecoterra {

namespace {

constexpr double kGiB = 1024.0 * 1024.0 * 1024.0;

std::string gib(double bytes) {
    std::ostringstream s;
    s.precision(bytes < 10 * kGiB ? 2 : 3);
    s << bytes / kGiB << " GiB";
    return s.str();
}

/// The first number in a file, or NaN ("max" and missing files too).
double number_in(const char* path) {
    std::ifstream f(path);
    double v = std::nan("");
    if (f) f >> v;
    return f ? v : std::nan("");
}

double meminfo_available() {
    std::ifstream f("/proc/meminfo");
    std::string key;
    double kb = 0;
    std::string unit;
    while (f >> key >> kb >> unit)
        if (key == "MemAvailable:") return kb * 1024.0;
    return std::nan("");
}

} // namespace

double MemoryEstimate::bytes() const {
    double b = fixed_bytes;
    for (const auto& t : terms) b += t.bytes();
    return b;
}

std::string MemoryEstimate::describe() const {
    std::ostringstream s;
    s << gib(bytes()) << " (" << std::lround(fixed_bytes / 1e6) << " MB fixed";
    for (const auto& t : terms)
        if (t.count > 0)
            s << " + " << grouped(t.count) << " " << t.what << " x " << t.bytes_each << " B";
    s << ")";
    return s.str();
}

double available_memory_bytes(std::string* source) {
    if (const char* e = std::getenv("ECOTERRA_MEMORY_LIMIT_GIB")) {
        char* end = nullptr;
        const double v = std::strtod(e, &end);
        if (end == e || *end != '\0' || !(v > 0))
            throw InputError("ECOTERRA_MEMORY_LIMIT_GIB = '" + std::string(e) +
                             "' is not a positive number of GiB");
        if (source) *source = "ECOTERRA_MEMORY_LIMIT_GIB";
        return v * kGiB;
    }
    double best = meminfo_available();
    std::string from = "MemAvailable in /proc/meminfo";
    const double limit2 = number_in("/sys/fs/cgroup/memory.max"),
                 used2 = number_in("/sys/fs/cgroup/memory.current");
    const double limit1 = number_in("/sys/fs/cgroup/memory/memory.limit_in_bytes"),
                 used1 = number_in("/sys/fs/cgroup/memory/memory.usage_in_bytes");
    auto consider = [&](double limit, double used, const char* what) {
        if (std::isfinite(limit) && limit < 1e18 && std::isfinite(used) &&
            (!std::isfinite(best) || limit - used < best)) {
            best = limit - used;
            from = what;
        }
    };
    consider(limit2, used2, "the cgroup's memory.max less memory.current");
    consider(limit1, used1, "the cgroup's memory.limit_in_bytes less its usage");
    if (!std::isfinite(best)) {
        best = std::numeric_limits<double>::infinity();
        from = "unknown (no /proc/meminfo or cgroup limit)";
    }
    if (source) *source = from;
    return best;
}

void check_memory(const MemoryEstimate& need, const std::string& what) {
    std::string source;
    const double have = available_memory_bytes(&source);
    if (need.bytes() <= have) return;
    throw InputError(what + " needs an estimated " + need.describe() + ", but " + gib(have) +
                     " is available (" + source +
                     "); make the grid smaller or coarser, or run it on a larger machine "
                     "(docs/scaling.md)");
}

std::string grouped(double n) {
    const std::string digits = std::to_string(static_cast<long long>(std::llround(n)));
    std::string out;
    for (std::size_t k = 0; k < digits.size(); ++k) {
        if (k > 0 && (digits.size() - k) % 3 == 0) out.push_back(',');
        out.push_back(digits[k]);
    }
    return out;
}

} // namespace ecoterra
