#pragma once
// The width and height of a PNG file, read from its IHDR chunk (bytes 16-23, big-endian).
#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <utility>

namespace ecoterra::test {

inline std::pair<std::uint32_t, std::uint32_t> png_size(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::array<unsigned char, 24> b{};
    in.read(reinterpret_cast<char*>(b.data()), b.size());
    if (in.gcount() != 24 || b[1] != 'P' || b[2] != 'N' || b[3] != 'G') return {0, 0};
    auto be = [&](int k) {
        return (std::uint32_t{b[k]} << 24) | (std::uint32_t{b[k + 1]} << 16) |
               (std::uint32_t{b[k + 2]} << 8) | b[k + 3];
    };
    return {be(16), be(20)};
}

} // namespace ecoterra::test
