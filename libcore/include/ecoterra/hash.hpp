#pragma once
// The one hash of ecoterra: FNV-1a 64 (Fowler, Noll & Vo; IETF draft-eastlake-fnv). Checksums of
// checkpoints and snapshots, fingerprints of inputs (terrain, observed weather, ensemble members)
// and the names of random streams. Not cryptographic: it detects damage and change, not intent.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string_view>

namespace ecoterra {

inline constexpr std::uint64_t kFnvOffsetBasis = 0xcbf29ce484222325ULL;
inline constexpr std::uint64_t kFnvPrime = 0x100000001b3ULL;

/// FNV-1a of `n` bytes; pass a previous result as `h` to continue a hash over several pieces.
inline std::uint64_t fnv1a64(const void* data, std::size_t n, std::uint64_t h = kFnvOffsetBasis) {
    const auto* b = static_cast<const unsigned char*>(data);
    for (std::size_t k = 0; k < n; ++k) h = (h ^ b[k]) * kFnvPrime;
    return h;
}

/// FNV-1a of the characters of `s` (usable at compile time; named apart from the byte overload so
/// that a string literal never binds to `const void*`).
constexpr std::uint64_t fnv1a64_text(std::string_view s, std::uint64_t h = kFnvOffsetBasis) {
    for (const char c : s) h = (h ^ static_cast<unsigned char>(c)) * kFnvPrime;
    return h;
}

/// One FNV-1a step with a whole 64-bit word: folds another hash into `h`.
constexpr std::uint64_t fnv1a64_fold(std::uint64_t h, std::uint64_t word) {
    return (h ^ word) * kFnvPrime;
}

/// FNV-1a of a file's bytes; IoError naming the file when it cannot be read.
std::uint64_t fnv1a64_file(const std::filesystem::path& file);

} // namespace ecoterra
