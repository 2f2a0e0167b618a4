#pragma once
// Small scenes the engine and CLI tests share.
#include "support/temp_dir.hpp"

#include <nlohmann/json.hpp>

#include <string>

namespace ecoterra::test {

/// A 40 m x 40 m scene on the shipped broadleaf ecosystem, with an initial stand of 600 stems/ha.
inline nlohmann::json small_scene(int years, const std::string& competition = "coupled",
                                  int seed = 9, int snapshot_interval_years = 2) {
    return {
        {"terrain",
         {{"generate",
           {{"method", "fbm"},
            {"size", 20},
            {"cell_size_m", 2.0},
            {"seed", 5},
            {"params", {{"D", 2.3}, {"rms_m", 0.8}}}}}}},
        {"soil",
         {{"uniform", {{"sand_pct", 15}, {"silt_pct", 70}, {"clay_pct", 15}, {"ph", 6.2}}}}},
        {"climate", {{"preset", "humid_subtropical"}}},
        {"vegetation",
         {{"ecosystem", (data_dir() / "ecosystems/humid_subtropical_broadleaf.json").string()},
          {"competition", competition},
          {"initial", {{"random", {{"stems_per_ha", 600}, {"max_dbh_m", 0.3}}}}}}},
        {"simulation",
         {{"years", years}, {"seed", seed}, {"snapshot_interval_years", snapshot_interval_years}}}};
}

} // namespace ecoterra::test
