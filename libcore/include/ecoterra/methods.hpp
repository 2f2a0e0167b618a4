#pragma once
// The published methods a run used, named by author and year, for its provenance and its log
// (richdem's habit of printing the papers behind each command): a user can cite what made the
// world, and a reader of a run file can tell which options it was grown with.
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace ecoterra {

struct Method {
    std::string use;      ///< what it does in the run ("reference evapotranspiration")
    std::string citation; ///< the work ("Allen, Pereira, Raes & Smith (1998) FAO ... 56")
};
using Methods = std::vector<Method>;

/// [{"use": ..., "citation": ...}, ...] for a run's provenance.
nlohmann::json methods_json(const Methods& m);
/// One line per method, "  USE: CITATION", for a log.
std::string methods_text(const Methods& m);

} // namespace ecoterra
