#pragma once
// Shared by the fuzz targets: each target feeds one input to one reader users give files to, and
// accepts only ecoterra's own errors (InputError, IoError: a clear message naming the file) as an
// outcome besides success. Anything else (another exception, a crash, a leak or undefined
// behaviour under the sanitizers) is a finding.
#include "ecoterra/error.hpp"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

namespace ecoterra::fuzz {

/// A file holding `data`, named with `extension` (the readers choose the format by it), in a
/// folder of this process that is removed at exit.
inline std::filesystem::path as_file(const std::uint8_t* data, std::size_t size,
                                     const std::string& extension) {
    static const std::filesystem::path dir = [] {
        std::filesystem::path d = std::filesystem::temp_directory_path() /
                                  ("ecoterra-fuzz-" + std::to_string(::getpid()));
        std::filesystem::create_directories(d);
        static struct Cleanup {
            std::filesystem::path d;
            ~Cleanup() {
                std::error_code ec;
                std::filesystem::remove_all(d, ec);
            }
        } cleanup{d};
        return d;
    }();
    const std::filesystem::path p = dir / ("input" + extension);
    std::ofstream(p, std::ios::binary | std::ios::trunc)
        .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    return p;
}

/// Runs `f`; ecoterra's errors are expected outcomes, any other exception aborts (a finding).
template <class F>
void expect_clean(F&& f) {
    try {
        f();
    } catch (const ecoterra::Error&) {
    } catch (const std::exception& e) {
        std::fprintf(stderr, "fuzz: an exception that is not an ecoterra error: %s\n", e.what());
        std::abort();
    }
}

} // namespace ecoterra::fuzz
