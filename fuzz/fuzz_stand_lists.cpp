// Fuzz target: the stand lists `ecoterra mobility` reads (a stem list and a dead-wood list, the
// CSVs of `ecoterra export vegetation` and `ecoterra export deadwood`): each input is tried as
// both.
#include "fuzz_common.hpp"

#include "ecoterra/mobility/stand.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const auto path = ecoterra::fuzz::as_file(data, size, ".csv");
    ecoterra::fuzz::expect_clean([&] { (void)ecoterra::mobility::read_stem_csv(path); });
    ecoterra::fuzz::expect_clean([&] { (void)ecoterra::mobility::read_deadwood_csv(path); });
    return 0;
}
