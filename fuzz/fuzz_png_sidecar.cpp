// Fuzz target: the JSON sidecar (FILE.png.json) of a 16-bit PNG DEM, beside a valid PNG.
#include "fuzz_common.hpp"

#include "ecoterra/terrain/io/raster_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    namespace io = ecoterra::terrain::io;
    static const std::filesystem::path png = [] {
        ecoterra::RasterD r(ecoterra::GridSpec{5, 4, 2.0, 10.0, 20.0});
        for (std::int64_t k = 0; k < r.size(); ++k) r.data()[k] = 100.0 + 0.5 * double(k % 7);
        const auto p = ecoterra::fuzz::as_file(nullptr, 0, ".png");
        io::write_raster(r, p);
        return p;
    }();
    std::filesystem::path sidecar = png;
    sidecar += ".json";
    std::ofstream(sidecar, std::ios::binary | std::ios::trunc)
        .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    ecoterra::fuzz::expect_clean([&] {
        std::vector<std::string> warnings;
        (void)io::read_raster(png, &warnings);
    });
    return 0;
}
