// Fuzz target: an observed-weather CSV file (`climate.csv`).
#include "fuzz_common.hpp"

#include "ecoterra/hydro/weather.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const auto path = ecoterra::fuzz::as_file(data, size, ".csv");
    ecoterra::fuzz::expect_clean([&] {
        const auto ws = ecoterra::hydro::read_weather_csv(path, 45.0, 100.0);
        (void)ecoterra::hydro::fill_report(ws);
    });
    return 0;
}
