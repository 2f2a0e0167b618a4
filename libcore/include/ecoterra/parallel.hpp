#pragma once
// Deterministic parallel sums over cells: the cells are cut into fixed blocks (whatever the thread
// count), each block sums on its own, and the block sums are added in block order. The same
// inputs give the same bits on 1 thread or many.
#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <vector>

namespace ecoterra {

inline constexpr std::int64_t kSumBlockCells = 16384;
inline constexpr std::int64_t kMinParallelBlocks = 8;
/// Loops over fewer independent items than this (plants, cells of a daily pass) run on one thread:
/// waking threads that sleep while they wait (OMP_WAIT_POLICY=passive, ecoterra's default) costs
/// tens of microseconds a region, more than a small loop saves. Results do not depend on it.
inline constexpr std::int64_t kMinParallelItems = 16384;

namespace detail {
inline std::atomic<std::int64_t>& parallel_min_items_value() {
    static std::atomic<std::int64_t> v{[] {
        const char* e = std::getenv("ECOTERRA_PARALLEL_MIN_ITEMS");
        const long long n = e ? std::atoll(e) : 0;
        return n >= 1 ? static_cast<std::int64_t>(n) : kMinParallelItems;
    }()};
    return v;
}
} // namespace detail

/// The size below which loops stay on one thread: kMinParallelItems, or the environment's
/// ECOTERRA_PARALLEL_MIN_ITEMS (>= 1), or what set_parallel_min_items set. Tests set 1 so that
/// small scenes run every parallel loop on all threads; results never depend on it.
inline std::int64_t parallel_min_items() {
    return detail::parallel_min_items_value().load(std::memory_order_relaxed);
}
inline void set_parallel_min_items(std::int64_t n) {
    detail::parallel_min_items_value().store(std::max<std::int64_t>(1, n),
                                             std::memory_order_relaxed);
}

/// Calls f(begin, end, sums) for every fixed block [begin, end) of kSumBlockCells cells in [0, n)
/// in parallel, where sums is the block's std::array<double, K> (zero on entry); returns the K
/// totals, the block sums added in block order. Passes that do several things to a block while it
/// is in cache (HydrologyModel's soil day) sum here with the same bits as blocked_sums. Runs on
/// one thread below `parallel_from` items (by default a few blocks' worth: a pass of cheap sums
/// gains little from a second thread; heavy passes give parallel_min_items()).
template <std::size_t K, class F>
std::array<double, K> blocked_range_sums(std::int64_t n, F&& f, std::int64_t parallel_from = 0) {
    if (parallel_from <= 0) parallel_from = kMinParallelBlocks * parallel_min_items();
    const std::int64_t blocks = (n + kSumBlockCells - 1) / kSumBlockCells;
    std::vector<std::array<double, K>> part(static_cast<std::size_t>(blocks));
    // Small grids stay on one thread: a parallel region costs more than it saves there.
#pragma omp parallel for schedule(static) if (n >= parallel_from)
    for (std::int64_t b = 0; b < blocks; ++b) {
        std::array<double, K> s{};
        f(b * kSumBlockCells, std::min(n, (b + 1) * kSumBlockCells), s);
        part[static_cast<std::size_t>(b)] = s;
    }
    std::array<double, K> total{};
    for (const auto& s : part)
        for (std::size_t i = 0; i < K; ++i) total[i] += s[i];
    return total;
}

/// Calls f(cell, sums) for every cell in [0, n) in parallel, where sums is the block's
/// std::array<double, K>; returns the K totals (blocked_range_sums, a cell at a time).
template <std::size_t K, class F>
std::array<double, K> blocked_sums(std::int64_t n, F&& f) {
    return blocked_range_sums<K>(
        n, [&](std::int64_t begin, std::int64_t end, std::array<double, K>& s) {
            for (std::int64_t k = begin; k < end; ++k) f(k, s);
        });
}

/// Calls f(begin, end) for every fixed block [begin, end) of kSumBlockCells cells in [0, n), in
/// parallel where n is large enough: for passes that work a block at a time (a vectorised call
/// over the block). Blocks are independent, so the result does not depend on the thread count.
template <class F>
void for_each_block(std::int64_t n, F&& f) {
    const std::int64_t blocks = (n + kSumBlockCells - 1) / kSumBlockCells;
#pragma omp parallel for schedule(static) if (n >= parallel_min_items())
    for (std::int64_t b = 0; b < blocks; ++b)
        f(b * kSumBlockCells, std::min(n, (b + 1) * kSumBlockCells));
}

/// Neumaier's compensated sum (Neumaier 1974, ZAMM 54:39): `sum` plus the rounding errors lost
/// on the way in `carry`. Its error is about one rounding of the total, independent of the count.
struct CompensatedSum {
    double sum = 0, carry = 0;
    void add(double x) {
        const double t = sum + x;
        carry += std::abs(sum) >= std::abs(x) ? (sum - t) + x : (x - t) + sum;
        sum = t;
    }
    double value() const { return sum + carry; }
};

/// The sum of f(k) for every k in [0, n), compensated within and across fixed blocks: for totals
/// whose differences are taken (the storages of a water budget). A plain sum of 2.6e5 cell
/// storages of similar size is off by ~1e-11 of the total, which is 1e-5 m3 of a 512 x 512 aquifer
/// and more than the budget allows; this one is off by one rounding. Deterministic as
/// blocked_sums.
template <class F>
double compensated_sum(std::int64_t n, F&& f) {
    const std::int64_t blocks = (n + kSumBlockCells - 1) / kSumBlockCells;
    std::vector<CompensatedSum> part(static_cast<std::size_t>(blocks));
#pragma omp parallel for schedule(static) if (n >= kMinParallelBlocks * parallel_min_items())
    for (std::int64_t b = 0; b < blocks; ++b) {
        CompensatedSum s;
        const std::int64_t end = std::min(n, (b + 1) * kSumBlockCells);
        for (std::int64_t k = b * kSumBlockCells; k < end; ++k) s.add(f(k));
        part[static_cast<std::size_t>(b)] = s;
    }
    CompensatedSum total;
    for (const auto& s : part) {
        total.add(s.sum);
        total.add(s.carry);
    }
    return total.value();
}

} // namespace ecoterra
