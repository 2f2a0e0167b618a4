#include "ecoterra/eco/canopy.hpp"
#include "ecoterra/fastmath.hpp"

#include "ecoterra/error.hpp"
#include "ecoterra/parallel.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include <omp.h>

namespace ecoterra::eco {

void CrownSet::add(const GridSpec& g, double x, double y, double r) {
    if (offset.empty()) offset.push_back(0);
    const auto [ic, jc] = g.clamped_cell(x, y);
    const int j0 = std::max(0, static_cast<int>(std::ceil(g.row_of(y - r))));
    const int j1 = std::min(g.ny - 1, static_cast<int>(std::floor(g.row_of(y + r))));
    std::int32_t n = 0;
    bool has_stem_cell = false;
    for (int j = j0; j <= j1; ++j) {
        const double dy = g.y_of(j) - y;
        const double h2 = r * r - dy * dy;
        if (h2 < 0) continue;
        const double hw = std::sqrt(h2);
        const int i0 = std::max(0, static_cast<int>(std::ceil(g.col_of(x - hw))));
        const int i1 = std::min(g.nx - 1, static_cast<int>(std::floor(g.col_of(x + hw))));
        if (i1 < i0) continue;
        spans.push_back({j, i0, i1});
        n += i1 - i0 + 1;
        if (j == jc && ic >= i0 && ic <= i1) has_stem_cell = true;
    }
    if (!has_stem_cell) {
        spans.push_back({jc, ic, ic});
        ++n;
    }
    offset.push_back(static_cast<std::uint32_t>(spans.size()));
    cells.push_back(n);
}

void CrownSet::append(const CrownSet& other) {
    if (offset.empty()) offset.push_back(0);
    const auto base = static_cast<std::uint32_t>(spans.size());
    spans.insert(spans.end(), other.spans.begin(), other.spans.end());
    for (std::size_t i = 1; i < other.offset.size(); ++i) offset.push_back(base + other.offset[i]);
    cells.insert(cells.end(), other.cells.begin(), other.cells.end());
}

CrownSet crown_set(const GridSpec& g, const std::vector<double>& x, const std::vector<double>& y,
                   const std::vector<double>& r) {
    const std::size_t n = x.size();
    std::vector<CrownSet> part(plant_blocks(n));
    for_each_plant_block(n, [&](std::size_t b, std::size_t first, std::size_t end) {
        CrownSet& c = part[b];
        c.clear();
        for (std::size_t p = first; p < end; ++p) c.add(g, x[p], y[p], r[p]);
    });
    CrownSet out;
    out.clear();
    std::size_t spans = 0;
    for (const CrownSet& c : part) spans += c.spans.size();
    out.spans.reserve(spans);
    out.offset.reserve(n + 1);
    out.cells.reserve(n);
    for (CrownSet& c : part) {
        out.append(c);
        c = CrownSet{}; // each part freed once joined
    }
    return out;
}

namespace {
/// The leaf area of crown q (lai per crown area, top `top_m`, depth `depth_m`) above height z.
double leaf_above(double lai, double top_m, double depth_m, double z) {
    if (!(top_m > z)) return 0.0;
    // A crown wholly above z (the common case under a closed canopy) needs no division: there
    // (top - z) / depth >= 1 and the minimum is 1, so both branches give the same bits.
    const double over = top_m - z;
    if (!(depth_m > 0) || over >= depth_m) return lai;
    return lai * std::min(1.0, over / depth_m);
}

/// The crowns ordered by their first row (a stable counting sort).
std::vector<std::uint32_t> crowns_by_first_row(const CrownSet& crowns, int ny) {
    const std::size_t n = crowns.size();
    std::vector<std::uint32_t> by_row(n), first(static_cast<std::size_t>(ny) + 1, 0);
    auto row_of = [&](std::size_t p) {
        return static_cast<std::size_t>(crowns.spans[crowns.offset[p]].row);
    };
    for (std::size_t p = 0; p < n; ++p) ++first[row_of(p) + 1];
    for (std::size_t r = 0; r < static_cast<std::size_t>(ny); ++r) first[r + 1] += first[r];
    for (std::size_t p = 0; p < n; ++p) by_row[first[row_of(p)]++] = static_cast<std::uint32_t>(p);
    return by_row;
}

/// The ground's shade, 1 - exp(-k L) of each cell's total leaf area index L over it, from the
/// cells' crown lists; each cell its own sum (in its list's order): the same bits on any thread
/// count.
RasterD ground_cover(const GridSpec& g, const std::vector<std::uint32_t>& start,
                     const std::vector<std::uint32_t>& ids, const std::vector<double>& lai,
                     double k) {
    RasterD ground(g, 0.0);
    double* out = ground.data();
    const auto nc = static_cast<std::int64_t>(start.size()) - 1;
    const bool parallel = static_cast<std::int64_t>(ids.size()) >= parallel_min_items();
#pragma omp parallel for schedule(static) if (parallel)
    for (std::int64_t c = 0; c < nc; ++c) {
        double l = 0;
        for (std::uint32_t e = start[c]; e < start[c + 1]; ++e) l += lai[ids[e]];
        out[c] = fastmath::beer_lambert_cover(l, k);
    }
    return ground;
}

/// The crowns over each cell, tallest first, equal heights in plant order (compressed rows:
/// cell c's are [start[c], start[c + 1]) of `ids`).
struct CellLists {
    std::vector<std::uint32_t> start, ids;
};

/// Calls f(c) for each cell c of crown p.
template <class F>
void for_each_crown_cell(const GridSpec& g, const CrownSet& crowns, std::uint32_t p, F&& f) {
    for (std::uint32_t s = crowns.offset[p]; s < crowns.offset[p + 1]; ++s) {
        const Span& sp = crowns.spans[s];
        const std::size_t row = static_cast<std::size_t>(sp.row) * static_cast<std::size_t>(g.nx);
        for (int x = sp.x0; x <= sp.x1; ++x) f(row + static_cast<std::size_t>(x));
    }
}

CellLists crowns_over_cells(const GridSpec& g, const CrownSet& crowns,
                            const std::vector<double>& height) {
    const std::size_t n = crowns.size();
    const auto cells = static_cast<std::size_t>(g.size());
    CellLists out;
    std::vector<std::uint32_t>& start = out.start;
    std::vector<std::uint32_t>& ids = out.ids;
    start.assign(cells + 1, 0);
    std::vector<std::uint32_t> fill;
    // Each thread counts and fills the lists of its own band of rows, visiting every crown in
    // plant order, so each list is filled in plant order whatever the thread count. (The plants
    // are sorted by their stem's cell, so this writes neighbouring cells' lists in turn.) Then
    // each list is put tallest first by a stable insertion sort: the lists a stable sort of all
    // plants by height would fill, without its random writes.
    const bool banded = static_cast<std::int64_t>(crowns.spans.size()) >= parallel_min_items();
#pragma omp parallel if (banded)
    {
        const int t = omp_get_thread_num(), team = omp_get_num_threads();
        const int r0 = g.ny * t / team, r1 = g.ny * (t + 1) / team;
        auto for_each_band_cell = [&](auto&& f) {
            for (std::uint32_t p = 0; p < n; ++p)
                for (std::uint32_t s = crowns.offset[p]; s < crowns.offset[p + 1]; ++s) {
                    const Span& sp = crowns.spans[s];
                    if (sp.row < r0 || sp.row >= r1) continue;
                    const std::size_t row =
                        static_cast<std::size_t>(sp.row) * static_cast<std::size_t>(g.nx);
                    for (int x = sp.x0; x <= sp.x1; ++x) f(p, row + static_cast<std::size_t>(x));
                }
        };
        for_each_band_cell([&](std::uint32_t, std::size_t c) { ++start[c + 1]; });
#pragma omp barrier
#pragma omp single
        {
            for (std::size_t c = 0; c < cells; ++c) start[c + 1] += start[c];
            ids.resize(start[cells]);
            fill.assign(start.begin(), start.end() - 1);
        }
        for_each_band_cell([&](std::uint32_t p, std::size_t c) { ids[fill[c]++] = p; });
    }
    const auto nc = static_cast<std::int64_t>(cells);
    const bool parallel = static_cast<std::int64_t>(ids.size()) >= parallel_min_items();
#pragma omp parallel for schedule(static) if (parallel)
    for (std::int64_t c = 0; c < nc; ++c) {
        std::uint32_t* list = ids.data() + start[c];
        const std::uint32_t len = start[c + 1] - start[c];
        for (std::uint32_t a = 1; a < len; ++a) {
            const std::uint32_t p = list[a];
            std::uint32_t b = a;
            for (; b > 0 && height[list[b - 1]] < height[p]; --b) list[b] = list[b - 1];
            list[b] = p;
        }
    }
    return out;
}

std::vector<double> crown_profile_shading(const GridSpec& g, const CrownSet& crowns,
                                          const std::vector<double>& height,
                                          const std::vector<double>& lai,
                                          const std::vector<double>& depth, double k,
                                          RasterD* ground) {
    const std::size_t n = crowns.size();
    if (depth.size() != n)
        throw Error("crown_profile shading needs a crown depth per plant (" +
                    std::to_string(depth.size()) + " for " + std::to_string(n) + " plants)");
    const CellLists lists = crowns_over_cells(g, crowns, height);
    const std::vector<std::uint32_t>&start = lists.start, &ids = lists.ids;
    const auto cells = static_cast<std::size_t>(g.size());
    auto for_each_cell = [&](std::uint32_t p, auto&& f) { for_each_crown_cell(g, crowns, p, f); };

    // The crowns visited row band by row band, so that consecutive crowns read neighbouring
    // cells' lists: in plant order they are scattered over the grid and most reads of `start` and
    // `ids` miss the cache. Each crown's shade is its own sum either way: the same bits.
    const std::vector<std::uint32_t> by_row = crowns_by_first_row(crowns, g.ny);
    std::vector<double> shade(n, 0.0);
    const auto ni = static_cast<std::int64_t>(n);
    // Parallel by the work (the crowns' cells, each visiting the crowns over it), not the plant
    // count: a hectare's 2,500 crowns cover ~1e5 cells, worth a second thread once a refresh.
    const auto crown_cells = static_cast<std::int64_t>(start[cells]);
#pragma omp parallel if (crown_cells >= parallel_min_items())
    {
        // Each crown's leaf area above its mid-crown, cell by cell; then the light through it
        // by one vectorised pass of exponentials (fastmath.hpp), summed in the cells' order.
        std::vector<double> above, light_of;
#pragma omp for schedule(dynamic, 64)
        for (std::int64_t q = 0; q < ni; ++q) {
            const std::uint32_t p = by_row[static_cast<std::size_t>(q)];
            const double z = height[p] - 0.5 * depth[p];
            above.clear();
            for_each_cell(p, [&](std::size_t c) {
                double l = 0;
                for (std::uint32_t e = start[c]; e < start[c + 1]; ++e) {
                    const std::uint32_t o = ids[e];
                    if (!(height[o] > z)) break; // tallest first: no higher leaves remain
                    if (o != p) l += leaf_above(lai[o], height[o], depth[o], z);
                }
                above.push_back(l);
            });
            light_of.resize(above.size());
            fastmath::exp_of_scaled(static_cast<std::int64_t>(above.size()), above.data(), -k,
                                    light_of.data());
            double light = 0;
            for (const double f : light_of) light += f;
            shade[p] = 1.0 - light / crowns.cells[p];
        }
    }
    if (ground) *ground = ground_cover(g, start, ids, lai, k);
    return shade;
}
} // namespace

std::vector<double> compute_shading(const GridSpec& g, const CrownSet& crowns,
                                    const std::vector<double>& height,
                                    const std::vector<double>& lai, ShadingMode mode, double k,
                                    RasterD* ground, const std::vector<double>& depth) {
    if (mode == ShadingMode::crown_profile)
        return crown_profile_shading(g, crowns, height, lai, depth, k, ground);
    const std::size_t n = crowns.size();
    std::vector<double> shade(n, 0.0);
    std::vector<double> stack(static_cast<std::size_t>(g.size()), 0.0);
    std::vector<std::uint32_t> order(n);
    std::iota(order.begin(), order.end(), 0u);
    std::stable_sort(order.begin(), order.end(),
                     [&](std::uint32_t a, std::uint32_t b) { return height[a] > height[b]; });
    std::size_t i = 0;
    while (i < n) {
        std::size_t end = i + 1;
        while (end < n && height[order[end]] == height[order[i]]) ++end;
        for (std::size_t q = i; q < end; ++q) {
            const std::uint32_t p = order[q];
            double acc = 0;
            for (std::uint32_t s = crowns.offset[p]; s < crowns.offset[p + 1]; ++s) {
                const Span& sp = crowns.spans[s];
                const double* row = stack.data() + static_cast<std::int64_t>(sp.row) * g.nx;
                if (mode == ShadingMode::blocking) {
                    for (int x = sp.x0; x <= sp.x1; ++x) acc += row[x] > 0 ? 1.0 : 0.0;
                } else {
                    for (int x = sp.x0; x <= sp.x1; ++x) acc += 1.0 - std::exp(-k * row[x]);
                }
            }
            shade[p] = acc / crowns.cells[p];
        }
        for (std::size_t q = i; q < end; ++q) {
            const std::uint32_t p = order[q];
            for (std::uint32_t s = crowns.offset[p]; s < crowns.offset[p + 1]; ++s) {
                const Span& sp = crowns.spans[s];
                double* row = stack.data() + static_cast<std::int64_t>(sp.row) * g.nx;
                for (int x = sp.x0; x <= sp.x1; ++x) row[x] += lai[p];
            }
        }
        i = end;
    }
    if (ground) {
        *ground = RasterD(g, 0.0);
        for (std::int64_t c = 0; c < g.size(); ++c) {
            const double l = stack[static_cast<std::size_t>(c)];
            ground->data()[c] =
                mode == ShadingMode::blocking ? (l > 0 ? 1.0 : 0.0) : 1.0 - std::exp(-k * l);
        }
    }
    return shade;
}

} // namespace ecoterra::eco
