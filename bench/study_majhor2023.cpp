// Reproduces the roughness-class study of Majhor & Bos s3.1 (Fig. 5): median class areas of
// multifractal terrains for D_high = 2.3, 2.45, 2.6 over N seeds, for a given relief and filter.
// Usage: study_majhor2023 [seeds=20] [relief_m=19.2] [sigma_m=0.025]
#include "ecoterra/terrain/roughness.hpp"
#include "ecoterra/terrain/weierstrass.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <vector>

using namespace ecoterra;
using namespace ecoterra::terrain;

int main(int argc, char** argv) {
    const int seeds = argc > 1 ? std::atoi(argv[1]) : 20;
    const double relief = argc > 2 ? std::atof(argv[2]) : MultifractalParams{}.relief_m;
    const double sigma = argc > 3 ? std::atof(argv[3]) : MultifractalParams{}.filter_sigma_m;
    std::printf("majhor2023 study: %d seeds, relief %.3g m, filter sigma %.3g m, "
                "thresholds %.4f / %.4f, 5 m border, classes before closing\n",
                seeds, relief, sigma, kDefaultLowThreshold, kDefaultHighThreshold);
    std::printf("%-8s %10s %10s %10s   (median %% of area)\n", "D_high", "low", "semi", "high");
    double prev[3] = {0, 0, 0};
    bool first = true;
    for (double d : {2.3, 2.45, 2.6}) {
        std::vector<double> a[3];
        for (int s = 1; s <= seeds; ++s) {
            MultifractalParams p = majhor2023_params(d);
            p.relief_m = relief;
            p.filter_sigma_m = sigma;
            const auto z = multifractal_generate(majhor2023_grid(), p, s).z;
            const auto c = class_areas(classify_gradient(max_gradient_map(z)), 5.0);
            a[0].push_back(c.low_pct);
            a[1].push_back(c.semi_pct);
            a[2].push_back(c.high_pct);
        }
        double med[3];
        for (int k = 0; k < 3; ++k) {
            std::sort(a[k].begin(), a[k].end());
            const std::size_t n = a[k].size();
            med[k] = n % 2 ? a[k][n / 2] : 0.5 * (a[k][n / 2 - 1] + a[k][n / 2]);
        }
        std::printf("%-8.2f %10.2f %10.2f %10.2f", d, med[0], med[1], med[2]);
        if (!first)
            std::printf("   change %+.2f %+.2f %+.2f points", med[0] - prev[0], med[1] - prev[1],
                        med[2] - prev[2]);
        std::printf("\n");
        std::copy(med, med + 3, prev);
        first = false;
    }
    std::printf("paper (Majhor & Bos s3.1): low -13.8 then -7.16, semi +11.7 then +5.63, "
                "high +1.54 then +3.33 points\n");
    return 0;
}
