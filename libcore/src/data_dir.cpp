#include "ecoterra/data_dir.hpp"

#include "ecoterra/error.hpp"

#include <cstdlib>

namespace ecoterra {

namespace fs = std::filesystem;

fs::path data_dir() {
    if (const char* env = std::getenv("ECOTERRA_DATA"); env && *env) return env;
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    std::string searched;
    if (!ec) {
        fs::path dir = exe.parent_path();
        for (int up = 0; up <= 3 && !dir.empty(); ++up) {
            const fs::path candidate = dir / "share" / "ecoterra" / "data";
            if (fs::is_directory(candidate, ec)) return candidate;
            searched += (searched.empty() ? "" : ", ") + candidate.string();
            if (dir == dir.parent_path()) break;
            dir = dir.parent_path();
        }
    }
    throw IoError(
        "cannot find ecoterra's data folder (searched " +
        (searched.empty() ? std::string("nothing: /proc/self/exe unreadable") : searched) +
        "); set ECOTERRA_DATA to the data/ folder of the source tree or the install");
}

} // namespace ecoterra
