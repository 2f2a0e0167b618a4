#include "ecoterra/eco/roots.hpp"

namespace ecoterra::eco {

void scatter_demand(const CrownSet& roots, const std::vector<double>& demand, const CellMap& map,
                    std::vector<double>& request) {
    // Serial on purpose: the sum order per cell must not depend on the thread count.
    for (std::size_t p = 0; p < roots.size(); ++p) {
        if (!(demand[p] > 0)) continue;
        const double share = demand[p] / roots.cells[p];
        for (std::uint32_t s = roots.offset[p]; s < roots.offset[p + 1]; ++s) {
            const Span& sp = roots.spans[s];
            if (map.factor == 1) {
                double* row = request.data() + static_cast<std::int64_t>(sp.row) * map.hydro_nx;
                for (int x = sp.x0; x <= sp.x1; ++x) row[x] += share;
            } else {
                for (int x = sp.x0; x <= sp.x1; ++x) request[map.hydro(sp.row, x)] += share;
            }
        }
    }
}

void gather_supply(const CrownSet& roots, const CellMap& map, const std::vector<double>& ratio,
                   std::vector<double>& fraction) {
    const auto n = static_cast<std::int64_t>(roots.size());
    fraction.resize(static_cast<std::size_t>(n));
#pragma omp parallel for schedule(static)
    for (std::int64_t p = 0; p < n; ++p) {
        double acc = 0;
        for (std::uint32_t s = roots.offset[p]; s < roots.offset[p + 1]; ++s) {
            const Span& sp = roots.spans[s];
            if (map.factor == 1) {
                const double* row = ratio.data() + static_cast<std::int64_t>(sp.row) * map.hydro_nx;
                for (int x = sp.x0; x <= sp.x1; ++x) acc += row[x];
            } else {
                for (int x = sp.x0; x <= sp.x1; ++x) acc += ratio[map.hydro(sp.row, x)];
            }
        }
        fraction[static_cast<std::size_t>(p)] = acc / roots.cells[static_cast<std::size_t>(p)];
    }
}

} // namespace ecoterra::eco
