#pragma once
// Branch-free logarithm and exponential for the daily per-cell kernels (gravity drainage), written
// so the compiler can inline them and vectorise the loops that call them, where a call into libm
// cannot be. Plain IEEE double arithmetic in a fixed order: the same bits on every x86-64 machine
// and at every thread count (no FMA unless the build asks for -march=native). Accuracy: a few units
// in the last place over the ranges stated (tests/unit/core/test_fastmath.cpp checks them against
// libm on a million arguments each).
//
// Method (textbook range reduction, e.g. Muller, Elementary Functions, 3rd ed., 2016, ch. 11):
//   log: x = 2^k m with m in [sqrt(1/2), sqrt(2)); log m = 2 atanh(s), s = (m - 1) / (m + 1),
//        |s| <= 0.1716, by its Taylor series 2 (s + s^3/3 + ... + s^23/23) (remainder < 1e-18);
//   exp: z = k ln2 + r, |r| <= ln2 / 2; e^r - 1 by its Taylor series to r^13 / 13! (remainder
//        < 5e-18); e^z = 2^k (1 + (e^r - 1)).
// ln 2 is split in two (hi with 11 trailing zero bits, so k ln2_hi is exact for |k| < 2^11).

#include <algorithm>
#include <bit>
#include <cstdint>

/// Put before a function whose loops call these functions: one clone per vector width (AVX-512,
/// AVX2, baseline), chosen when the program loads. Its file must be compiled with
/// -ffp-contract=off so the clones give the same bits, and -fno-trapping-math so they vectorise.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(ECOTERRA_NO_TARGET_CLONES)
#define ECOTERRA_CLONES __attribute__((target_clones("avx512f", "avx2", "default")))
#else
#define ECOTERRA_CLONES
#endif

/// Put before a loop whose arrays never overlap, so that GCC vectorises it without run-time
/// overlap checks (it makes at most 10, and a loop over a dozen arrays would stay scalar).
#if defined(__GNUC__) && !defined(__clang__)
#define ECOTERRA_IVDEP _Pragma("GCC ivdep")
#else
#define ECOTERRA_IVDEP
#endif

namespace ecoterra::fastmath {

inline constexpr double kLn2Hi = 6.93147180369123816490e-01; // 0x3FE62E42FEE00000
inline constexpr double kLn2Lo = 1.90821492927058770002e-10; // ln 2 - kLn2Hi
inline constexpr double kInvLn2 = 1.44269504088896338700e+00;
// The same for single precision (the float functions below): hi (0x3f317200) has 9 trailing zero
// bits, so k hi is exact for |k| < 2^9.
inline constexpr float kLn2HiF = 0.693145751953125f;
inline constexpr float kLn2LoF = 1.42860676533018570e-06f; // ln 2 - kLn2HiF
inline constexpr float kInvLn2F = 1.44269504088896341f;

/// ln(m) for m in [sqrt(1/2), sqrt(2)] (see above).
inline double log_reduced(double m) {
    const double f = m - 1.0; // exact here (Sterbenz)
    const double s = f / (2.0 + f), z = s * s;
    double p = 1.0 / 23;
    p = p * z + 1.0 / 21;
    p = p * z + 1.0 / 19;
    p = p * z + 1.0 / 17;
    p = p * z + 1.0 / 15;
    p = p * z + 1.0 / 13;
    p = p * z + 1.0 / 11;
    p = p * z + 1.0 / 9;
    p = p * z + 1.0 / 7;
    p = p * z + 1.0 / 5;
    p = p * z + 1.0 / 3;
    // 2 atanh(s) = 2s + 2s z p, written as f - s f + 2 s z p (2s = f - s f exactly in reals)
    // keeps the leading term exact.
    return f - s * f + 2.0 * s * (z * p);
}

/// ln(x) for positive normal x (0 < x < infinity; subnormals, zero and NaN are the caller's).
inline double log_positive(double x) {
    // x = 2^k m with m in [sqrt(1/2), sqrt(2)): subtracting the bits of sqrt(1/2) leaves k in the
    // top 12 bits (two's complement), and m is x with k taken off its exponent field. Integer
    // operations only, so the loop stays free of branches and selects.
    constexpr std::uint64_t sqrt_half_bits = 0x3fe6a09e667f3bcdULL;
    const std::uint64_t bits = std::bit_cast<std::uint64_t>(x);
    const std::uint64_t offset = bits - sqrt_half_bits;
    const double m = std::bit_cast<double>(bits - (offset & 0xfff0000000000000ULL));
    // k + 2048 (the 12-bit two's complement with its sign bit flipped) as a double without an
    // int64 conversion: the bits of 2^52 + (k + 2048), less 2^52 + 2048.
    const double k = std::bit_cast<double>(((offset >> 52) ^ 0x800ULL) | 0x4330000000000000ULL) -
                     4503599627372544.0;
    return k * kLn2Hi + (log_reduced(m) + k * kLn2Lo);
}

/// ln(1 + r) for r > -1 (r + 1 normal), accurate for small r: the rounding of 1 + r corrected to
/// first order (Goldberg 1991, ACM Computing Surveys 23:5, Theorem 4's idea).
inline double log1p_positive(double r) {
    const double u = 1.0 + r;
    return log_positive(u) + (r - (u - 1.0)) / u;
}

namespace detail {
/// e^r - 1 for |r| <= ln2 / 2.
inline double expm1_reduced(double r) {
    double p = 1.0 / 6227020800.0; // 1/13!
    p = p * r + 1.0 / 479001600.0;
    p = p * r + 1.0 / 39916800.0;
    p = p * r + 1.0 / 3628800.0;
    p = p * r + 1.0 / 362880.0;
    p = p * r + 1.0 / 40320.0;
    p = p * r + 1.0 / 5040.0;
    p = p * r + 1.0 / 720.0;
    p = p * r + 1.0 / 120.0;
    p = p * r + 1.0 / 24.0;
    p = p * r + 1.0 / 6.0;
    p = p * r + 0.5;
    return r + (r * r) * p;
}
/// The exponential's constants for double (and, below, float).
template <class T>
struct ExpFormat;
template <>
struct ExpFormat<double> {
    using Bits = std::uint64_t;
    static constexpr double shifter = 6755399441055744.0; // 1.5 * 2^52: adding it rounds
    static constexpr Bits bias = 1023;
    static constexpr int mantissa_bits = 52;
    static constexpr double lowest = -708, highest = 709; // the clamp
    static constexpr double inv_ln2 = kInvLn2, ln2_hi = kLn2Hi, ln2_lo = kLn2Lo;
};
/// e^r - 1 for |r| <= ln2 / 2, in float (the series to r^7 / 7!).
inline float expm1_reduced(float r) {
    float p = 1.0f / 5040;
    p = p * r + 1.0f / 720;
    p = p * r + 1.0f / 120;
    p = p * r + 1.0f / 24;
    p = p * r + 1.0f / 6;
    p = p * r + 0.5f;
    return r + (r * r) * p;
}
template <>
struct ExpFormat<float> {
    using Bits = std::uint32_t;
    static constexpr float shifter = 12582912.0f; // 1.5 * 2^23
    static constexpr Bits bias = 127;
    static constexpr int mantissa_bits = 23;
    static constexpr float lowest = -87, highest = 88; // e^-87 is still a normal float
    static constexpr float inv_ln2 = kInvLn2F, ln2_hi = kLn2HiF, ln2_lo = kLn2LoF;
};
/// z = k ln2 + r: r returned, 2^k in `scale`. z within the format's clamp.
template <class T>
inline T reduce(T z, T& scale) {
    using F = ExpFormat<T>;
    using Bits = typename F::Bits;
    const T t = z * F::inv_ln2 + F::shifter;
    const T k = t - F::shifter;
    const Bits kbits = std::bit_cast<Bits>(t) - std::bit_cast<Bits>(F::shifter);
    scale = std::bit_cast<T>((kbits + F::bias) << F::mantissa_bits);
    return (z - k * F::ln2_hi) - k * F::ln2_lo;
}
/// e^z (Minus1 = false) or e^z - 1 (true), z clamped to the format's range first.
template <class T, bool Minus1>
inline T exp_clamped_any(T z) {
    z = std::min(std::max(z, ExpFormat<T>::lowest), ExpFormat<T>::highest);
    T scale;
    const T r = reduce(z, scale);
    if constexpr (Minus1)
        return (scale - T(1)) + scale * expm1_reduced(r);
    else
        return scale + scale * expm1_reduced(r);
}
} // namespace detail

/// e^z; arguments below -708 give e^-708 (about 3e-308), above 709 e^709. Callers here use it
/// for fractions in (0, 1] and growth factors far inside that range.
inline double exp_clamped(double z) {
    return detail::exp_clamped_any<double, false>(z);
}

/// e^z - 1, accurate for small |z| (same clamping as exp_clamped).
inline double expm1_clamped(double z) {
    return detail::exp_clamped_any<double, true>(z);
}

// Single precision, for kernels whose result needs float accuracy only (the gravity drainage's
// daily fraction: drainage.cpp). The same methods with shorter series: log's atanh series to s^9
// (remainder < 3e-9 relative), e^r - 1 to r^7 / 7! (remainder < 6e-9 for |r| <= ln2 / 2); the
// result is within a few float ulps of libm (tests/unit/core/test_fastmath.cpp). Twice the lanes
// of the double functions, and about half the operations.

/// ln(x) for positive normal float x (the caller keeps x away from 0, subnormals and NaN).
inline float log_positive_f(float x) {
    constexpr std::uint32_t sqrt_half_bits = 0x3f3504f3U;
    const std::uint32_t bits = std::bit_cast<std::uint32_t>(x);
    const std::uint32_t offset = bits - sqrt_half_bits;
    const float m = std::bit_cast<float>(bits - (offset & 0xff800000U)); // in [sqrt(1/2), sqrt(2))
    const float k = static_cast<float>(static_cast<std::int32_t>(offset) >> 23);
    const float f = m - 1.0f;
    const float s = f / (2.0f + f), z = s * s;
    float p = 1.0f / 9;
    p = p * z + 1.0f / 7;
    p = p * z + 1.0f / 5;
    p = p * z + 1.0f / 3;
    return k * kLn2HiF + ((f - s * f + 2.0f * s * (z * p)) + k * kLn2LoF);
}

/// ln(1 + r) for r > -1 (1 + r a normal float), accurate for small r (as log1p_positive).
inline float log1p_positive_f(float r) {
    const float u = 1.0f + r;
    return log_positive_f(u) + (r - (u - 1.0f)) / u;
}

/// e^z in float; arguments below -87 give e^-87 (about 1.6e-38, still normal), above 88 e^88.
inline float exp_clamped_f(float z) {
    return detail::exp_clamped_any<float, false>(z);
}

/// e^z - 1 in float, accurate for small |z| (same clamping as exp_clamped_f).
inline float expm1_clamped_f(float z) {
    return detail::exp_clamped_any<float, true>(z);
}

/// The ground covered by leaf area index `lai` with extinction coefficient `k` (Beer-Lambert):
/// 1 - e^(-k lai) as -expm1(-k lai), 0 where there are no leaves.
inline double beer_lambert_cover(double lai, double k) {
    const double cover = -expm1_clamped(-k * lai);
    return lai > 0 ? cover : 0.0;
}

/// out[i] = exp_clamped(scale x[i]) for i < n, vectorised for the machine (vector_math.cpp; the
/// same bits as the scalar function).
void exp_of_scaled(std::int64_t n, const double* x, double scale, double* out);

/// cover[i] = beer_lambert_cover(lai[i], k) for i < n, vectorised likewise.
void cover_from_lai(std::int64_t n, const double* lai, double k, double* cover);

} // namespace ecoterra::fastmath
