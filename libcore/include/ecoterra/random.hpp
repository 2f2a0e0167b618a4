#pragma once
// Seeded, portable random numbers. Every draw in ecoterra comes from an Rng built from the run seed
// and a stream name, so adding a component does not shift the draws of another, and results do not
// depend on the standard library's distribution implementations or on the thread count.
//
// Generator: xoshiro256** 1.0 (Blackman & Vigna 2018, "Scrambled linear pseudorandom number
// generators", ACM TOMS 47(4) 2021), state seeded with SplitMix64 (Steele, Lea & Flood 2014).
#include "ecoterra/hash.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <string_view>

namespace ecoterra {

/// SplitMix64 step: a well-mixed 64-bit output from a 64-bit counter state.
constexpr std::uint64_t splitmix64(std::uint64_t& state) {
    std::uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

/// The hash of a stream name, used to derive independent streams from one seed.
constexpr std::uint64_t hash_name(std::string_view name) {
    return fnv1a64_text(name);
}

class Rng {
public:
    using result_type = std::uint64_t;

    /// A generator for `seed`, in the stream named `stream` with sub-index `index` (e.g. a row).
    explicit Rng(std::uint64_t seed, std::string_view stream = "", std::uint64_t index = 0) {
        std::uint64_t sm = seed ^ hash_name(stream);
        sm = splitmix64(sm) ^ (index * 0xd1342543de82ef95ULL);
        for (auto& s : m_state) s = splitmix64(sm);
    }

    static constexpr result_type min() { return 0; }
    static constexpr result_type max() { return ~result_type{0}; }

    result_type operator()() {
        const std::uint64_t result = rotl(m_state[1] * 5, 7) * 9;
        const std::uint64_t t = m_state[1] << 17;
        m_state[2] ^= m_state[0];
        m_state[3] ^= m_state[1];
        m_state[1] ^= m_state[2];
        m_state[0] ^= m_state[3];
        m_state[2] ^= t;
        m_state[3] = rotl(m_state[3], 45);
        return result;
    }

    /// Uniform in [0, 1) with 53 random bits.
    double uniform() { return static_cast<double>((*this)() >> 11) * 0x1.0p-53; }
    /// Uniform in [a, b).
    double uniform(double a, double b) { return a + (b - a) * uniform(); }
    /// Uniform integer in [0, n), n > 0 (Lemire's nearly divisionless method, unbiased).
    std::uint64_t below(std::uint64_t n) {
        __uint128_t m = static_cast<__uint128_t>((*this)()) * n;
        auto low = static_cast<std::uint64_t>(m);
        if (low < n) {
            const std::uint64_t threshold = (0 - n) % n;
            while (low < threshold) {
                m = static_cast<__uint128_t>((*this)()) * n;
                low = static_cast<std::uint64_t>(m);
            }
        }
        return static_cast<std::uint64_t>(m >> 64);
    }
    /// Standard normal by the Marsaglia polar method (no cached second value, so draws stay
    /// aligned with calls).
    double normal() {
        for (;;) {
            const double u = 2.0 * uniform() - 1.0;
            const double v = 2.0 * uniform() - 1.0;
            const double s = u * u + v * v;
            if (s > 0.0 && s < 1.0) return u * std::sqrt(-2.0 * std::log(s) / s);
        }
    }
    double normal(double mean, double sd) { return mean + sd * normal(); }

    std::array<std::uint64_t, 4> state() const { return m_state; }
    void set_state(const std::array<std::uint64_t, 4>& s) { m_state = s; }

private:
    static constexpr std::uint64_t rotl(std::uint64_t x, int k) {
        return (x << k) | (x >> (64 - k));
    }
    std::array<std::uint64_t, 4> m_state{};
};

} // namespace ecoterra
