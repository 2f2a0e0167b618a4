// Reproduces the roughness-class study of Majhor & Bos s3.1 (Fig. 5): median class areas of
// multifractal terrains for D_high = 2.3, 2.45, 2.6 over N seeds, for a given reading of the
// generator. Terrain s of every level shares its phases (the same seed), so the study reports the
// change of the medians (unpaired, as the paper) and the mean and standard deviation of the
// per-seed changes (paired).
// Usage: study_majhor2023 [--seeds N=20] [--relief M=19.2] [--sigma M=0.025]
//                         [--scaling zero_mean|unit_interval] [--offset C=0] [--phase RAD=pi]
//                         [--phase-low|--phase-mid|--phase-high RAD] (one layer's phase range)
//                         [--n-max N] (frequency terms of every layer; 0 = the grid's Nyquist)
#include "ecoterra/random.hpp"
#include "ecoterra/terrain/roughness.hpp"
#include "ecoterra/terrain/weierstrass.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

using namespace ecoterra;
using namespace ecoterra::terrain;

namespace {

struct Options {
    int seeds = 20;
    MultifractalParams params;
};

Options parse(int argc, char** argv) {
    Options o;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--help") {
            std::printf("study_majhor2023 [--seeds N=20] [--relief M=19.2] [--sigma M=0.025]\n"
                        "  [--scaling zero_mean|unit_interval] [--offset C=0] [--phase RAD=pi]\n"
                        "  [--phase-low|--phase-mid|--phase-high RAD] [--n-max N=0 (Nyquist)]\n");
            std::exit(0);
        }
        if (i + 1 >= argc) {
            std::fprintf(stderr, "study_majhor2023: %s needs a value\n", a.c_str());
            std::exit(2);
        }
        const char* v = argv[++i];
        if (a == "--seeds")
            o.seeds = std::atoi(v);
        else if (a == "--relief")
            o.params.relief_m = std::atof(v);
        else if (a == "--sigma")
            o.params.filter_sigma_m = std::atof(v);
        else if (a == "--offset")
            o.params.layer_offset = std::atof(v);
        else if (a == "--phase")
            o.params.low.phase_max_rad = o.params.mid.phase_max_rad = o.params.high.phase_max_rad =
                std::atof(v);
        else if (a == "--phase-low")
            o.params.low.phase_max_rad = std::atof(v);
        else if (a == "--phase-mid")
            o.params.mid.phase_max_rad = std::atof(v);
        else if (a == "--phase-high")
            o.params.high.phase_max_rad = std::atof(v);
        else if (a == "--n-max")
            o.params.low.n_max = o.params.mid.n_max = o.params.high.n_max = std::atoi(v);
        else if (a == "--scaling" && std::strcmp(v, "unit_interval") == 0)
            o.params.layer_scaling = LayerScaling::unit_interval;
        else if (a == "--scaling" && std::strcmp(v, "zero_mean") == 0)
            o.params.layer_scaling = LayerScaling::zero_mean;
        else {
            std::fprintf(stderr, "study_majhor2023: unknown option %s %s\n", a.c_str(), v);
            std::exit(2);
        }
    }
    if (o.seeds < 2) {
        std::fprintf(stderr, "study_majhor2023: --seeds must be at least 2\n");
        std::exit(2);
    }
    return o;
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// The spread of a change of medians between two sets of N terrains drawn independently (as
/// the paper's): the standard deviation of median(resample of b) - median(resample of a) over
/// bootstrap resamples.
double bootstrap_sd_of_change(const std::vector<double>& a, const std::vector<double>& b) {
    constexpr int kResamples = 2000;
    Rng rng(1, "study.bootstrap");
    auto resample = [&](const std::vector<double>& v) {
        std::vector<double> r(v.size());
        for (double& x : r) x = v[rng.below(v.size())];
        return median(r);
    };
    double sum = 0, sum2 = 0;
    for (int k = 0; k < kResamples; ++k) {
        const double d = resample(b) - resample(a);
        sum += d, sum2 += d * d;
    }
    const double mean = sum / kResamples;
    return std::sqrt(std::max(0.0, sum2 / kResamples - mean * mean));
}

} // namespace

int main(int argc, char** argv) {
    const Options o = parse(argc, argv);
    const MultifractalParams& q = o.params;
    std::printf("majhor2023 study: %d seeds, relief %.3g m, filter sigma %.3g m, layers %s with "
                "offset %g, phases in [0, %.3g] / [0, %.3g] / [0, %.3g] rad, thresholds %.4f / "
                "%.4f, 5 m border, classes "
                "before closing\n",
                o.seeds, q.relief_m, q.filter_sigma_m,
                q.layer_scaling == LayerScaling::unit_interval ? "unit_interval" : "zero_mean",
                q.layer_offset, q.low.phase_max_rad, q.mid.phase_max_rad, q.high.phase_max_rad,
                kDefaultLowThreshold, kDefaultHighThreshold);
    const double levels[3] = {2.3, 2.45, 2.6};
    std::vector<double> area[3][3]; // [level][class], one entry per seed
    for (int l = 0; l < 3; ++l)
        for (int s = 1; s <= o.seeds; ++s) {
            MultifractalParams p = q;
            p.high.D = levels[l];
            const auto z = multifractal_generate(majhor2023_grid(), p, s).z;
            const auto c = class_areas(classify_gradient(max_gradient_map(z)), 5.0);
            area[l][0].push_back(c.low_pct);
            area[l][1].push_back(c.semi_pct);
            area[l][2].push_back(c.high_pct);
        }
    std::printf("%-8s %8s %8s %8s   (median %% of area)\n", "D_high", "low", "semi", "high");
    for (int l = 0; l < 3; ++l)
        std::printf("%-8.2f %8.2f %8.2f %8.2f\n", levels[l], median(area[l][0]), median(area[l][1]),
                    median(area[l][2]));
    const char* names[3] = {"low", "semi", "high"};
    std::printf("change, points: unpaired (of the medians, +/- its bootstrap sd for independent "
                "sets of terrains) | paired (mean +/- sd of the per-seed changes)\n");
    for (int k = 0; k < 3; ++k)
        for (int l = 1; l < 3; ++l) {
            std::vector<double> d;
            for (int s = 0; s < o.seeds; ++s) d.push_back(area[l][k][s] - area[l - 1][k][s]);
            double mean = 0, var = 0;
            for (double x : d) mean += x / d.size();
            for (double x : d) var += (x - mean) * (x - mean) / (d.size() - 1);
            std::printf("%-5s %.2f -> %.2f: %+7.2f +/- %.2f | %+7.2f +/- %.2f\n", names[k],
                        levels[l - 1], levels[l], median(area[l][k]) - median(area[l - 1][k]),
                        bootstrap_sd_of_change(area[l - 1][k], area[l][k]), mean, std::sqrt(var));
        }
    std::printf("paper (Majhor & Bos s3.1): low -13.8 then -7.16, semi +11.7 then +5.63, "
                "high +1.54 then +3.33 points\n");
    return 0;
}
