// fastmath.hpp against libm: the logarithm and exponential the drainage kernel uses, over a
// million random arguments each across their whole ranges and at the points where their range
// reductions switch (powers of two, sqrt(2), multiples of ln 2 / 2).
#include "ecoterra/fastmath.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

using namespace ecoterra::fastmath;

namespace {
/// |a - b| in units of the last place of b in T (b computed in double by libm; for float, the
/// ulp of the float nearest b).
template <class T>
double ulps_in(T a, double b) {
    if (static_cast<double>(a) == b) return 0;
    const T bt = static_cast<T>(b);
    const double ulp = static_cast<double>(
        std::nextafter(std::fabs(bt), std::numeric_limits<T>::infinity()) - std::fabs(bt));
    return std::fabs(static_cast<double>(a) - b) / ulp;
}
double ulps(double a, double b) {
    return ulps_in<double>(a, b);
}

/// The largest error seen and its argument, in ulps of T.
template <class T>
struct WorstIn {
    double error = 0, at = 0;
    void add(T got, double want, double x) {
        const double u = ulps_in<T>(got, want);
        if (u > error) error = u, at = x;
    }
};
using Worst = WorstIn<double>;
} // namespace

TEST_CASE("fastmath's log, log1p, exp and expm1 stay within a few ulps of libm", "[fastmath]") {
    std::mt19937_64 rng(20261127);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    Worst log_w, log1p_w, exp_w, expm1_w;
    for (int i = 0; i < 1000000; ++i) {
        const double x = std::exp(u01(rng) * 1400.0 - 700.0); // 1e-304 .. 1e304
        log_w.add(log_positive(x), std::log(x), x);
        const double z = u01(rng) * 1416.0 - 708.0;
        exp_w.add(exp_clamped(z), std::exp(z), z);
        // expm1 and log1p matter most near 0: arguments spread over 17 decades each side.
        const double small = (u01(rng) < 0.5 ? -1 : 1) * std::exp(-40.0 * u01(rng)) * 2.0;
        expm1_w.add(expm1_clamped(small), std::expm1(small), small);
        const double r = std::exp(-40.0 * u01(rng)) * 100.0;
        log1p_w.add(log1p_positive(r), std::log1p(r), r);
    }
    INFO("log " << log_w.error << " ulp at " << log_w.at << "; exp " << exp_w.error << " at "
                << exp_w.at << "; expm1 " << expm1_w.error << " at " << expm1_w.at << "; log1p "
                << log1p_w.error << " at " << log1p_w.at);
    CHECK(log_w.error <= 2);
    CHECK(exp_w.error <= 2);
    CHECK(expm1_w.error <= 3);
    CHECK(log1p_w.error <= 3);
}

TEST_CASE("fastmath at the seams of its range reductions", "[fastmath]") {
    CHECK(log_positive(1.0) == 0.0);
    CHECK(exp_clamped(0.0) == 1.0);
    CHECK(expm1_clamped(0.0) == 0.0);
    CHECK(log1p_positive(0.0) == 0.0);
    for (int e = -1020; e <= 1020; e += 17) {
        const double p = std::ldexp(1.0, e);
        // Powers of two, and the neighbours of sqrt(2) 2^e, where m and k switch.
        for (double x :
             {p, std::nextafter(p, 0.0), std::nextafter(p, 4.0), std::sqrt(2.0) * p,
              std::nextafter(std::sqrt(2.0) * p, 0.0), std::nextafter(std::sqrt(2.0) * p, 1e308)}) {
            INFO("x = " << x);
            CHECK(ulps(log_positive(x), std::log(x)) <= 2);
        }
    }
    const double half_ln2 = 0.5 * std::log(2.0);
    for (int k = -2040; k <= 2040; k += 7) {
        // Odd multiples of ln2 / 2, where the rounding of z / ln 2 switches k.
        for (double z : {k * half_ln2, std::nextafter(k * half_ln2, -1e9),
                         std::nextafter(k * half_ln2, 1e9)}) {
            if (z < -708 || z > 709) continue;
            INFO("z = " << z);
            CHECK(ulps(exp_clamped(z), std::exp(z)) <= 2);
            CHECK(ulps(expm1_clamped(z), std::expm1(z)) <= 3);
        }
    }
    // Outside the documented range the exponential clamps instead of overflowing.
    CHECK(exp_clamped(-1e6) == Approx(std::exp(-708.0)).epsilon(1e-15));
    CHECK(std::isfinite(exp_clamped(1e6)));
    CHECK(expm1_clamped(-1e6) == -1.0);
}

TEST_CASE("fastmath's vector loops compute the scalar functions' bits", "[fastmath]") {
    // The loops run this machine's widest clone (AVX-512, AVX2 or baseline); the scalar calls
    // here are baseline code. Lengths that are not multiples of any vector width, values across
    // the range the callers use (leaf area above a crown, leaf area index) and beyond.
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    for (const std::int64_t n : {1, 3, 7, 100003}) {
        std::vector<double> x(static_cast<std::size_t>(n)), out(x.size());
        for (double& v : x) v = u01(rng) < 0.1 ? 0.0 : std::exp(20 * u01(rng) - 12) * 10;
        x[0] = n > 3 ? -1.0 : x[0]; // no leaves: no cover
        exp_of_scaled(n, x.data(), -0.5, out.data());
        int differ = 0;
        for (std::size_t i = 0; i < x.size(); ++i) {
            const double one = exp_clamped(-0.5 * x[i]);
            differ += std::memcmp(&one, &out[i], sizeof one) != 0;
        }
        CHECK(differ == 0);
        cover_from_lai(n, x.data(), 0.5, out.data());
        differ = 0;
        for (std::size_t i = 0; i < x.size(); ++i) {
            const double one = beer_lambert_cover(x[i], 0.5);
            differ += std::memcmp(&one, &out[i], sizeof one) != 0;
            CHECK(out[i] >= 0);
            CHECK(out[i] <= 1);
            if (x[i] > 0) CHECK(ulps(out[i], -std::expm1(-0.5 * x[i])) <= 3);
        }
        CHECK(differ == 0);
        if (n > 3) CHECK(out[0] == 0.0);
    }
}

TEST_CASE("fastmath's single-precision log, log1p, exp and expm1 stay within a few float ulps of "
          "libm",
          "[fastmath]") {
    // The drainage kernel's float functions against double libm, over a million arguments each
    // across their ranges (log: 1e-37 .. 1e38; exp: [-87, 88]; log1p and expm1 near 0 too), and
    // at the seams: powers of two and sqrt(2) 2^e for log, odd multiples of ln 2 / 2 for exp.
    std::mt19937_64 rng(20261128);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    WorstIn<float> log_w, log1p_w, exp_w, expm1_w;
    for (int i = 0; i < 1000000; ++i) {
        const float x = static_cast<float>(std::exp(u01(rng) * 172.0 - 85.0));
        log_w.add(log_positive_f(x), std::log(static_cast<double>(x)), x);
        const float z = static_cast<float>(u01(rng) * 175.0 - 87.0);
        exp_w.add(exp_clamped_f(z), std::exp(static_cast<double>(z)), z);
        const float small =
            static_cast<float>((u01(rng) < 0.5 ? -1 : 1) * std::exp(-30.0 * u01(rng)) * 2.0);
        expm1_w.add(expm1_clamped_f(small), std::expm1(static_cast<double>(small)), small);
        const float r = static_cast<float>(std::exp(-30.0 * u01(rng)) * 1e4);
        log1p_w.add(log1p_positive_f(r), std::log1p(static_cast<double>(r)), r);
    }
    for (int e = -125; e <= 126; ++e) {
        const float p = std::ldexp(1.0f, e), q = std::sqrt(2.0f) * p;
        for (float x : {p, std::nextafter(p, 0.0f), std::nextafter(p, 4.0f), q,
                        std::nextafter(q, 0.0f), std::nextafter(q, 1e38f)})
            log_w.add(log_positive_f(x), std::log(static_cast<double>(x)), x);
    }
    const double half_ln2 = 0.5 * std::log(2.0);
    for (int k = -251; k <= 253; k += 2) {
        const float c = static_cast<float>(k * half_ln2);
        for (float z : {c, std::nextafter(c, -1e9f), std::nextafter(c, 1e9f)}) {
            if (z < -87 || z > 88) continue;
            exp_w.add(exp_clamped_f(z), std::exp(static_cast<double>(z)), z);
            expm1_w.add(expm1_clamped_f(z), std::expm1(static_cast<double>(z)), z);
        }
    }
    INFO("log " << log_w.error << " float ulp at " << log_w.at << "; exp " << exp_w.error << " at "
                << exp_w.at << "; expm1 " << expm1_w.error << " at " << expm1_w.at << "; log1p "
                << log1p_w.error << " at " << log1p_w.at);
    CHECK(log_w.error <= 2);
    CHECK(exp_w.error <= 2);
    CHECK(expm1_w.error <= 3);
    CHECK(log1p_w.error <= 3);
    CHECK(log_positive_f(1.0f) == 0.0f);
    CHECK(exp_clamped_f(0.0f) == 1.0f);
    CHECK(expm1_clamped_f(0.0f) == 0.0f);
    // Outside the range the exponential clamps, still a normal float.
    CHECK(exp_clamped_f(-1e6f) >= std::numeric_limits<float>::min());
    CHECK(std::isfinite(exp_clamped_f(1e6f)));
    CHECK(expm1_clamped_f(-1e6f) == -1.0f);
}
