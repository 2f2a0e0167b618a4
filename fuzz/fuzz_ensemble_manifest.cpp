// Fuzz target: an ensemble manifest (`ecoterra ensemble MANIFEST.json`), read and checked as the
// command reads it, and its first and last members built (overrides, seeds, input hash). Files it
// names are looked up beside the shipped studies, so the seeds can name the shipped scenes.
#include "fuzz_common.hpp"

#include "ecoterra/ensemble/manifest.hpp"
#include "ecoterra/json_util.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    ecoterra::fuzz::expect_clean([&] {
        const std::string text(reinterpret_cast<const char*>(data), size);
        const nlohmann::json j = ecoterra::parse_json(text, "fuzz.json");
        const auto m = ecoterra::ensemble::manifest_from_document(
            j, "fuzz.json", ECOTERRA_DATA_DIR "/studies", nullptr);
        (void)ecoterra::ensemble::make_member(m, 0);
        (void)ecoterra::ensemble::make_member(m, m.members() - 1);
    });
    return 0;
}
