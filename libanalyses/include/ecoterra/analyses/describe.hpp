#pragma once
// Every catalogue of ecoterra in one place: `ecoterra describe` prints them and
// docs/parameters.md is generated from them (a test fails when the two differ).
#include <string>
#include <vector>

namespace ecoterra::analyses {

/// The catalogues of a topic as text (aligned columns) or as Markdown tables. InputError for an
/// unknown topic, naming the known ones.
std::string describe(const std::string& topic, bool markdown);

/// Every dotted key an ecosystem scene may set from the catalogues (climate, soil, vegetation,
/// hydrology, simulation), plus the keys that take objects or files (terrain.generate,
/// terrain.file, vegetation.ecosystem, vegetation.initial, climate.preset, soil.*). Terrain
/// generator keys below terrain.generate are not listed: they depend on the method.
std::vector<std::string> scene_keys();

/// The unit of a scene key ("hydrology.root_zone_depth_m" -> "m") or of a terrain generator's
/// parameter ("terrain.generate.params.d_high", "params.d_high"), from the catalogues; "" when
/// the key has none there.
std::string scene_key_unit(const std::string& key);

} // namespace ecoterra::analyses
