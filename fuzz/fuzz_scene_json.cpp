// Fuzz target: a scene JSON file (`ecoterra run SCENE.json`), loaded as the run loads it (terrain
// built, soil mapped, species and weather files read), without running years. Files it names are
// looked up beside the shipped scenes, so the seeds can name the shipped ecosystems.
#include "fuzz_common.hpp"

#include "ecoterra/eco/scene_config.hpp"
#include "ecoterra/json_util.hpp"

namespace {
/// True when some W-M layer under `g` asks for many terms (M ridges times the frequencies up to
/// the Nyquist cutoff, which grow as 1 / ln(gamma)): M up to 4096 and gamma near 1 are valid but
/// cost minutes under the sanitizers.
bool many_terms(const nlohmann::json& g) {
    if (g.is_array()) {
        for (const auto& v : g)
            if (many_terms(v)) return true;
        return false;
    }
    if (!g.is_object()) return false;
    for (const auto& [key, v] : g.items()) {
        if (v.is_number()) {
            const double x = v.get<double>();
            if ((key == "M" && x > 128) || (key == "n_max" && x > 64) ||
                (key == "gamma" && x < 1.2))
                return true;
        } else if (many_terms(v)) {
            return true;
        }
    }
    return false;
}

/// Scenes whose terrain would take long to build are skipped: their size checks are tested
/// elsewhere, and a fuzzer needs many inputs per second.
bool small_enough(const nlohmann::json& j) {
    const auto* t = j.is_object() && j.contains("terrain") ? &j["terrain"] : nullptr;
    if (!t || !t->is_object() || !t->contains("generate")) return true;
    const auto& g = (*t)["generate"];
    if (many_terms(g)) return false;
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
