// Loops over many values of fastmath.hpp's functions, cloned per vector width (AVX-512, AVX2,
// baseline x86-64; chosen when the program loads). CMakeLists.txt compiles this file with
// -fno-trapping-math (so selects stay branch-free) and -ffp-contract=off (no FMA), so every clone
// computes the scalar functions' bits on every machine (tests/unit/core/test_fastmath.cpp).
#include "ecoterra/fastmath.hpp"

namespace ecoterra::fastmath {

ECOTERRA_CLONES
void exp_of_scaled(std::int64_t n, const double* x, double scale, double* out) {
    for (std::int64_t i = 0; i < n; ++i) out[i] = exp_clamped(scale * x[i]);
}

ECOTERRA_CLONES
void cover_from_lai(std::int64_t n, const double* lai, double k, double* cover) {
    for (std::int64_t i = 0; i < n; ++i) cover[i] = beer_lambert_cover(lai[i], k);
}

} // namespace ecoterra::fastmath
