// Fuzz target: a scene JSON file (`ecoterra run SCENE.json`), loaded as the run loads it (terrain
// built, soil mapped, species and weather files read), without running years. Files it names are
// looked up beside the shipped scenes, so the seeds can name the shipped ecosystems.
#include "fuzz_common.hpp"

#include "ecoterra/eco/scene_config.hpp"
#include "ecoterra/json_util.hpp"

namespace {
/// Scenes whose terrain would take long to build are skipped: their size checks are tested
/// elsewhere, and a fuzzer needs many inputs per second.
bool small_enough(const nlohmann::json& j) {
    const auto* t = j.is_object() && j.contains("terrain") ? &j["terrain"] : nullptr;
    if (!t || !t->is_object() || !t->contains("generate")) return true;
    const auto& g = (*t)["generate"];
    if (!g.is_object() || !g.contains("size")) return true;
    return !g["size"].is_number() || g["size"].get<double>() <= 96;
}
} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    ecoterra::fuzz::expect_clean([&] {
        const std::string text(reinterpret_cast<const char*>(data), size);
        const nlohmann::json j = ecoterra::parse_json(text, "fuzz.json");
        if (!small_enough(j)) return;
        (void)ecoterra::eco::load_eco_scene(j, ECOTERRA_DATA_DIR "/scenes");
    });
    return 0;
}
