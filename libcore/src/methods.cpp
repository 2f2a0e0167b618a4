#include "ecoterra/methods.hpp"

namespace ecoterra {

nlohmann::json methods_json(const Methods& m) {
    nlohmann::json out = nlohmann::json::array();
    for (const auto& x : m) out.push_back({{"use", x.use}, {"citation", x.citation}});
    return out;
}

std::string methods_text(const Methods& m) {
    std::string out;
    for (const auto& x : m) out.append("  ").append(x.use).append(": ").append(x.citation) += '\n';
    return out;
}

} // namespace ecoterra
