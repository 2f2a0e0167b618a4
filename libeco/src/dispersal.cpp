#include "ecoterra/eco/dispersal.hpp"

#include <cmath>

namespace ecoterra::eco {

namespace {
constexpr double kReferenceDbhCm = 30.0; ///< SORTIE-ND's STR parent size
constexpr double kPoissonNormalAbove = 30.0;
} // namespace

double seeds_per_year(const Species& s, double dbh_m, double vigor) {
    const double r = dbh_m * 100.0 / kReferenceDbhCm;
    return s.seeds_per_yr_at_30cm * r * r * vigor;
}

double sample_dispersal_distance(const DispersalKernel& k, Rng& rng) {
    const double a = rng.uniform() < k.long_fraction ? k.long_distance_m : k.mean_distance_m;
    return -a * std::log1p(-rng.uniform());
}

std::int64_t poisson(Rng& rng, double mean) {
    if (!(mean > 0)) return 0;
    if (mean < kPoissonNormalAbove) {
        const double limit = std::exp(-mean);
        std::int64_t k = 0;
        double prod = rng.uniform();
        while (prod > limit) {
            ++k;
            prod *= rng.uniform();
        }
        return k;
    }
    const double x = std::round(rng.normal(mean, std::sqrt(mean)));
    return x < 0 ? 0 : static_cast<std::int64_t>(x);
}

} // namespace ecoterra::eco
