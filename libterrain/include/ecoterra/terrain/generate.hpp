#pragma once
// One entry point for every terrain generator, driven by a JSON specification (the same one the
// command line builds from its flags). docs/terrain.md lists every key with its unit and default.
//
// {
//   "method": "multifractal" | "wm" | "perlin" | "gaussian" | "variable" | "fbm",
//   "preset": "majhor2023"            (optional; multifractal on 1009 x 1009 at 0.05 m),
//   "nx": 1009, "ny": 1009, "cell_size_m": 0.05, "origin_x_m": 0, "origin_y_m": 0,
//   "seed": 7,
//   "params": { method-specific keys, see docs/terrain.md }
// }
#include "ecoterra/raster.hpp"

#include "ecoterra/catalog.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace ecoterra::terrain {

struct GeneratedTerrain {
    RasterD z; ///< elevation, m
    std::vector<std::string> warnings;
    nlohmann::json resolved; ///< the specification with every default filled in
    nlohmann::json info = nlohmann::json::object(); ///< derived values, e.g. the n_max used
};

/// The methods and the parameter keys each accepts.
const std::vector<std::string>& terrain_methods();
std::vector<std::string> terrain_param_keys(const std::string& method);
/// Every generator parameter per method (key, unit, default, range, description), for
/// `ecoterra describe terrain` and docs/parameters.md.
std::vector<std::pair<std::string, std::vector<ParamInfo>>> describe_terrain_params();

/// Fills defaults (including a preset's) and checks every key and range; throws InputError.
nlohmann::json resolve_terrain_spec(const nlohmann::json& spec);

/// Generates the terrain a (resolved or not) specification describes.
GeneratedTerrain generate_terrain(const nlohmann::json& spec);

} // namespace ecoterra::terrain
