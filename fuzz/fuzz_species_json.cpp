// Fuzz target: an ecosystem (species) JSON file, as `vegetation.ecosystem` names it.
#include "fuzz_common.hpp"

#include "ecoterra/eco/species.hpp"
#include "ecoterra/json_util.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    ecoterra::fuzz::expect_clean([&] {
        const std::string text(reinterpret_cast<const char*>(data), size);
        ecoterra::eco::parse_ecosystem(ecoterra::parse_json(text, "fuzz.json"), "fuzz.json");
    });
    return 0;
}
