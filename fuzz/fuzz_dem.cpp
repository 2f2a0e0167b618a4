// Fuzz target: a DEM file in the format of its extension (ECOTERRA_FUZZ_EXTENSION: .asc, .png,
// .tif or .h5; one binary per format), read as `terrain convert`, `hydro pond` and the scenes'
// `terrain.file` read it.
#include "fuzz_common.hpp"

#include "ecoterra/terrain/io/raster_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const auto path = ecoterra::fuzz::as_file(data, size, ECOTERRA_FUZZ_EXTENSION);
    ecoterra::fuzz::expect_clean([&] {
        std::vector<std::string> warnings;
        (void)ecoterra::terrain::io::read_raster(path, &warnings);
    });
    return 0;
}
