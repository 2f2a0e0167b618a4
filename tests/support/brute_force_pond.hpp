#pragma once
// A brute-force reference for ponding (test use only): the same physical rules as the catchment
// model (D8 to pits, fill from the pits, spill at the lowest leaking saddle, merge when two lakes
// spill into each other; edges are outlets), computed with different machinery. Minimax path
// elevations come from a bottleneck Dijkstra search per lake, and lake levels from bisection.
// O(n log n) per lake and pass: for small DEMs only.
#include "ecoterra/hydro/routing.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <vector>

namespace ecoterra::test {

struct BruteForcePond {
    std::vector<double> depth_m; ///< per cell
    double lost_m3 = 0;
    double stored_m3 = 0;
};

inline BruteForcePond brute_force_pond(const RasterD& dem, double depth_m,
                                       hydro::D8Rule rule = hydro::D8Rule::steepest) {
    using hydro::cell_index;
    const hydro::FlowDirections fd(dem, rule);
    const auto& g = dem.grid();
    const std::int64_t n = g.size();
    const double area = g.cell_size_m * g.cell_size_m;
    BruteForcePond out;
    struct Lake {
        std::vector<std::int64_t> seeds;
        double v = 0;
        double level = 0;
        std::int64_t target = -2; // -2 none, -1 outlet, else pit cell
    };
    std::vector<Lake> lakes;
    auto lake_of_pit = [&](std::int64_t p) -> int {
        for (std::size_t k = 0; k < lakes.size(); ++k)
            if (std::find(lakes[k].seeds.begin(), lakes[k].seeds.end(), p) != lakes[k].seeds.end())
                return static_cast<int>(k);
        return -1;
    };
    for (std::int64_t c = 0; c < n; ++c) {
        const std::int64_t t = fd.terminus(c);
        if (fd.is_outlet(t)) {
            out.lost_m3 += depth_m * area;
            continue;
        }
        int k = lake_of_pit(t);
        if (k < 0) {
            lakes.push_back({{t}, 0});
            k = static_cast<int>(lakes.size()) - 1;
        }
        lakes[k].v += depth_m * area;
    }
    auto neighbours = [&](std::int64_t c, auto&& f) {
        const int i = static_cast<int>(c % g.nx), j = static_cast<int>(c / g.nx);
        for (const auto& o : kMooreOffsets)
            if (g.contains(i + o[0], j + o[1])) f(cell_index(g, i + o[0], j + o[1]));
    };
    // minimax[c]: lowest possible highest elevation on a path from the seeds to c (a bottleneck
    // Dijkstra; paths do not pass through outlets).
    auto minimax_from = [&](const std::vector<std::int64_t>& seeds) {
        std::vector<double> mm(n, std::numeric_limits<double>::infinity());
        using Item = std::pair<double, std::int64_t>;
        std::priority_queue<Item, std::vector<Item>, std::greater<Item>> pq;
        for (auto s : seeds) {
            mm[s] = fd.elevation(s);
            pq.emplace(mm[s], s);
        }
        while (!pq.empty()) {
            // (Not a structured binding: clang 14 cannot capture one in the lambda below.)
            const double v = pq.top().first;
            const auto c = pq.top().second;
            pq.pop();
            if (v > mm[c] || fd.is_outlet(c)) continue;
            neighbours(c, [&](std::int64_t q) {
                const double w = std::max(mm[c], fd.elevation(q));
                if (w < mm[q]) {
                    mm[q] = w;
                    pq.emplace(w, q);
                }
            });
        }
        return mm;
    };
    auto leaks = [&](const Lake& L, std::int64_t c) {
        if (fd.is_outlet(c)) return true;
        const std::int64_t t = fd.terminus(c);
        return fd.is_outlet(t) || std::find(L.seeds.begin(), L.seeds.end(), t) == L.seeds.end();
    };
    auto capacity = [&](const std::vector<double>& mm, double h) {
        double v = 0;
        for (std::int64_t c = 0; c < n; ++c)
            if (mm[c] < h && !fd.is_outlet(c)) v += (h - fd.elevation(c)) * area;
        return v;
    };
    for (int pass = 0; pass < 100000; ++pass) {
        bool changed = false;
        bool merged = false;
        for (std::size_t k = 0; k < lakes.size() && !merged; ++k) {
            Lake& L = lakes[k];
            if (L.v <= 1e-12) continue;
            const auto mm = minimax_from(L.seeds);
            // Spill level: the lowest minimax of a leaking cell.
            double s = std::numeric_limits<double>::infinity();
            for (std::int64_t c = 0; c < n; ++c)
                if (std::isfinite(mm[c]) && leaks(L, c)) s = std::min(s, mm[c]);
            // Leaking cells next to the non-leaking part of the lake at the saddle: the lowest wins
            // (what a priority flood meets first).
            std::int64_t dest = -1;
            for (std::int64_t c = 0; c < n; ++c) {
                if (!(mm[c] == s) || !leaks(L, c)) continue;
                bool adjacent = false;
                neighbours(c, [&](std::int64_t q) { adjacent |= mm[q] <= s && !leaks(L, q); });
                if (!adjacent) continue;
                if (dest < 0 || fd.elevation(c) < fd.elevation(dest)) dest = c;
            }
            const double cap = capacity(mm, s);
            if (L.v <= cap + 1e-12) {
                L.target = -2; // holds its water: the level is found once all spills are done
                L.level = s;
                continue;
            }
            const double excess = L.v - cap;
            L.v = cap;
            L.level = s;
            changed = true;
            const std::int64_t t = fd.is_outlet(dest) ? dest : fd.terminus(dest);
            if (fd.is_outlet(t)) {
                out.lost_m3 += excess;
                L.target = -1;
                continue;
            }
            L.target = t;
            int m = lake_of_pit(t);
            if (m < 0) {
                lakes.push_back({{t}, excess});
                continue;
            }
            lakes[m].v += excess;
            // Mutual spill: merge.
            Lake& M = lakes[m];
            if (M.target >= 0 &&
                std::find(L.seeds.begin(), L.seeds.end(), M.target) != L.seeds.end()) {
                Lake& L2 = lakes[k];
                L2.seeds.insert(L2.seeds.end(), lakes[m].seeds.begin(), lakes[m].seeds.end());
                L2.v += lakes[m].v;
                L2.target = -2;
                lakes.erase(lakes.begin() + m);
                merged = true; // indices moved: start the sweep again
            }
        }
        if (!changed) break;
    }
    out.depth_m.assign(n, 0.0);
    for (auto& L : lakes) {
        if (L.v <= 1e-12) continue;
        out.stored_m3 += L.v;
        const auto mm = minimax_from(L.seeds);
        double lo = fd.elevation(L.seeds[0]), hi = L.level;
        for (auto sd : L.seeds) lo = std::min(lo, fd.elevation(sd));
        for (int it = 0; it < 200; ++it) {
            const double mid = 0.5 * (lo + hi);
            (capacity(mm, mid) < L.v ? lo : hi) = mid;
        }
        L.level = 0.5 * (lo + hi);
        for (std::int64_t c = 0; c < n; ++c)
            if (mm[c] < L.level && !fd.is_outlet(c))
                out.depth_m[c] = std::max(out.depth_m[c], L.level - fd.elevation(c));
    }
    return out;
}

} // namespace ecoterra::test
