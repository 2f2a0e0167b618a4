#pragma once
// Crowns on the plant grid and asymmetric light competition (paper 002 s3, Fig 2).
//
// A crown covers the cells whose centres lie within its radius of the stem, and always the cell
// holding the stem. Plants are taken from the tallest down; L(c) is the leaf area index already
// stacked over cell c by taller crowns (plants of equal height do not shade each other).
//   blocking      shade_p = (cells of p with L > 0) / (cells of p)     (paper 002 Fig 2: a crown
//   with
//                 one of its four cells under a taller crown is 1/4 shaded)
//   beer_lambert  shade_p = 1 - mean over cells of exp(-k L(c))       (Monsi & Saeki 1953; k = 0.5,
//                 iLand and 3-PG)
//   crown_profile shade_p = 1 - mean over cells of exp(-k L_p(c)), L_p(c) the leaf area index of
//                 the other crowns over cell c above p's mid-crown z_p = H_p - d_p / 2, each crown
//                 q holding its leaf area evenly over its depth d_q (wind::crown_depth_m, the
//                 ForestGALES crown depth): L_p(c) = sum_q LAI_q clamp((H_q - z_p) / d_q, 0, 1).
//                 Light through a layered canopy, as SORTIE-ND's light through crowns (Canham et
//                 al. 1994) and iLand's light influence patterns (Seidl et al. 2012) see it: a
//                 codominant of nearly the same height shades a plant with its upper crown only,
//                 and each of two equal crowns shades the other.
// The ground shade raster is 1 where any crown covers a cell (blocking) or 1 - exp(-k L_total).
#include "ecoterra/parallel.hpp"
#include "ecoterra/raster.hpp"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace ecoterra::eco {

/// Inclusive run of columns [x0, x1] in one row of the plant grid.
struct Span {
    std::int32_t row = 0, x0 = 0, x1 = 0;
};

/// The crown (= root) cells of every plant, as runs of cells.
struct CrownSet {
    std::vector<Span> spans;
    std::vector<std::uint32_t> offset; ///< plant i's spans are [offset[i], offset[i+1])
    std::vector<std::int32_t> cells;   ///< number of cells of plant i
    void clear() {
        spans.clear();
        offset.assign(1, 0);
        cells.clear();
    }
    /// Appends the crown of radius r (m) centred at (x, y) (m).
    void add(const GridSpec& g, double x, double y, double r);
    std::size_t size() const { return cells.size(); }
    /// Appends `other`'s crowns after these.
    void append(const CrownSet& other);
};

/// Plants per block of the parallel builds (crown_set, root_cells): each block's part is built
/// alone and the parts joined in order.
inline constexpr std::size_t kCrownBlock = 4096;

/// The number of blocks of kCrownBlock plants that n plants fill.
inline std::size_t plant_blocks(std::size_t n) {
    return (n + kCrownBlock - 1) / kCrownBlock;
}

/// Calls f(block, first, end) for each block [first, end) of kCrownBlock plants of n, in parallel
/// from parallel_min_items() plants.
template <class F>
void for_each_plant_block(std::size_t n, F&& f) {
    const bool parallel = static_cast<std::int64_t>(n) >= parallel_min_items();
    const auto nb = static_cast<std::int64_t>(plant_blocks(n));
#pragma omp parallel for schedule(dynamic, 1) if (parallel)
    for (std::int64_t b = 0; b < nb; ++b) {
        const std::size_t first = static_cast<std::size_t>(b) * kCrownBlock;
        f(static_cast<std::size_t>(b), first, std::min(n, first + kCrownBlock));
    }
}

/// The crowns of radius r[p] (m) centred at (x[p], y[p]) (m), in plant order: CrownSet::add of
/// each in turn, built in fixed blocks of plants in parallel and joined (the same set).
CrownSet crown_set(const GridSpec& g, const std::vector<double>& x, const std::vector<double>& y,
                   const std::vector<double>& r);

enum class ShadingMode { blocking, beer_lambert, crown_profile };

/// Shade fraction per plant (in the order of `crowns`) and the ground shade raster.
/// `height_m` and `lai` (leaf area per crown area) are per plant; `crown_depth_m` (per plant, m)
/// is read by crown_profile only and may be empty for the other modes.
std::vector<double> compute_shading(const GridSpec& g, const CrownSet& crowns,
                                    const std::vector<double>& height_m,
                                    const std::vector<double>& lai, ShadingMode mode,
                                    double extinction, RasterD* ground_shade,
                                    const std::vector<double>& crown_depth_m = {});

} // namespace ecoterra::eco
