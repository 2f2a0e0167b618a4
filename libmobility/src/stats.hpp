#pragma once
// Summary statistics shared by the stand and traversal reports (private to libmobility).
#include <algorithm>
#include <cmath>
#include <vector>

namespace ecoterra::mobility::detail {

/// The q-quantile of `v` with linear interpolation between order statistics (R type 7); 0 when
/// empty. q = 0.5 is the median (the mean of the two middle values for an even count).
inline double quantile(std::vector<double> v, double q) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const double pos = q * static_cast<double>(v.size() - 1);
    const auto lo = static_cast<std::size_t>(std::floor(pos));
    const std::size_t hi = std::min(lo + 1, v.size() - 1);
    return v[lo] + (pos - static_cast<double>(lo)) * (v[hi] - v[lo]);
}

inline double mean(const std::vector<double>& v) {
    double sum = 0;
    for (const double x : v) sum += x;
    return v.empty() ? 0.0 : sum / static_cast<double>(v.size());
}

} // namespace ecoterra::mobility::detail
