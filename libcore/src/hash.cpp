#include "ecoterra/hash.hpp"

#include "ecoterra/error.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <vector>

namespace ecoterra {

std::uint64_t fnv1a64_file(const std::filesystem::path& file) {
    std::FILE* f = std::fopen(file.c_str(), "rb");
    if (!f) throw IoError(file.string() + ": cannot read (" + std::strerror(errno) + ")");
    std::uint64_t h = kFnvOffsetBasis;
    std::vector<char> buf(1 << 20);
    std::size_t n = 0;
    while ((n = std::fread(buf.data(), 1, buf.size(), f)) > 0) h = fnv1a64(buf.data(), n, h);
    const bool failed = std::ferror(f) != 0;
    std::fclose(f);
    if (failed) throw IoError(file.string() + ": read failed");
    return h;
}

} // namespace ecoterra
