#include "ecoterra/json_util.hpp"

#include <algorithm>
#include <sstream>

namespace ecoterra {

std::string format_number(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
}

std::size_t edit_distance(const std::string& a, const std::string& b) {
    std::vector<std::size_t> prev(b.size() + 1), cur(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
        cur[0] = i;
        for (std::size_t j = 1; j <= b.size(); ++j)
            cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] != b[j - 1])});
        std::swap(prev, cur);
    }
    return prev[b.size()];
}

namespace {
std::string key_path(const std::string& where, const std::string& key) {
    return where.empty() ? key : where + "." + key;
}
} // namespace

void require_known_keys(const nlohmann::json& obj, const std::vector<std::string>& allowed,
                        const std::string& where) {
    if (!obj.is_object())
        throw InputError((where.empty() ? std::string("configuration") : where) +
                         " must be a JSON object");
    for (auto it = obj.begin(); it != obj.end(); ++it) {
        if (std::find(allowed.begin(), allowed.end(), it.key()) != allowed.end()) continue;
        std::string best;
        std::size_t best_d = 3;
        for (const auto& a : allowed) {
            const std::size_t d = edit_distance(it.key(), a);
            if (d < best_d) best_d = d, best = a;
        }
        throw InputError("unknown key '" + key_path(where, it.key()) + "'" +
                         (best.empty() ? "" : " (did you mean '" + key_path(where, best) + "'?)"));
    }
}

double get_number(const nlohmann::json& obj, const std::string& key, double fallback,
                  const std::string& where, double min, double max) {
    if (!obj.contains(key)) return fallback;
    const auto& v = obj.at(key);
    if (!v.is_number())
        throw InputError(key_path(where, key) + " must be a number, got " + v.dump());
    const double d = v.get<double>();
    if (!(d >= min && d <= max))
        throw InputError(key_path(where, key) + " = " + format_number(d) + " is outside [" +
                         format_number(min) + ", " + format_number(max) + "]");
    return d;
}

long long get_integer(const nlohmann::json& obj, const std::string& key, long long fallback,
                      const std::string& where, long long min, long long max) {
    if (!obj.contains(key)) return fallback;
    const auto& v = obj.at(key);
    if (!v.is_number_integer() &&
        !(v.is_number() && v.get<double>() == std::floor(v.get<double>())))
        throw InputError(key_path(where, key) + " must be an integer, got " + v.dump());
    // A whole number written as a float (1e300) is checked before it is converted: beyond the
    // range of long long the conversion is undefined (it gave -9223372036854775808).
    bool out_of_range = false;
    if (v.is_number_float()) {
        const double x = v.get<double>();
        constexpr double kTwo63 = 9223372036854775808.0; // the first double past long long
        out_of_range =
            !(x >= static_cast<double>(min) && x < kTwo63 && x <= static_cast<double>(max));
    } else if (v.is_number_unsigned()) {
        const auto u = v.get<unsigned long long>();
        out_of_range = u > static_cast<unsigned long long>(std::max(max, 0LL)) ||
                       (min > 0 && u < static_cast<unsigned long long>(min));
    } else {
        const long long x = v.get<long long>();
        out_of_range = x < min || x > max;
    }
    if (out_of_range)
        throw InputError(key_path(where, key) + " = " + v.dump() + " is outside [" +
                         std::to_string(min) + ", " + std::to_string(max) + "]");
    return v.get<long long>();
}

bool get_bool(const nlohmann::json& obj, const std::string& key, bool fallback,
              const std::string& where) {
    if (!obj.contains(key)) return fallback;
    const auto& v = obj.at(key);
    if (!v.is_boolean())
        throw InputError(key_path(where, key) + " must be true or false, got " + v.dump());
    return v.get<bool>();
}

std::string get_string(const nlohmann::json& obj, const std::string& key,
                       const std::string& fallback, const std::string& where) {
    if (!obj.contains(key)) return fallback;
    const auto& v = obj.at(key);
    if (!v.is_string())
        throw InputError(key_path(where, key) + " must be a string, got " + v.dump());
    return v.get<std::string>();
}

std::size_t get_choice(const nlohmann::json& obj, const std::string& key,
                       const std::vector<std::string>& choices, std::size_t fallback,
                       const std::string& where) {
    const std::string v = get_string(obj, key, choices.at(fallback), where);
    for (std::size_t k = 0; k < choices.size(); ++k)
        if (choices[k] == v) return k;
    std::string list;
    for (std::size_t k = 0; k < choices.size(); ++k)
        list += (k == 0 ? "" : k + 1 == choices.size() ? " or " : ", ") + choices[k];
    throw InputError(key_path(where, key) + " must be " + list + ", got '" + v + "'");
}

nlohmann::json parse_json(const std::string& text, const std::string& source) {
    try {
        return nlohmann::json::parse(text);
    } catch (const nlohmann::json::exception& e) { // syntax, and numbers out of range (1e400)
        throw InputError(source + ": not valid JSON: " + e.what());
    }
}

void set_dotted(nlohmann::json& j, const std::string& key, const nlohmann::json& value) {
    nlohmann::json* node = &j;
    std::size_t start = 0;
    for (;;) {
        const auto dot = key.find('.', start);
        const std::string part = key.substr(start, dot - start);
        if (dot == std::string::npos) {
            (*node)[part] = value;
            return;
        }
        if (!node->contains(part) || !(*node)[part].is_object())
            (*node)[part] = nlohmann::json::object();
        node = &(*node)[part];
        start = dot + 1;
    }
}

void apply_overrides(nlohmann::json& j, const std::vector<std::string>& overrides) {
    for (const auto& o : overrides) {
        const auto eq = o.find('=');
        if (eq == std::string::npos || eq == 0)
            throw InputError("--set takes KEY=VALUE, got '" + o + "'");
        const std::string key = o.substr(0, eq), value = o.substr(eq + 1);
        nlohmann::json v;
        try {
            v = nlohmann::json::parse(value);
        } catch (const nlohmann::json::out_of_range&) {
            throw InputError("--set " + key + ": the value " + value +
                             " is out of range for a number");
        } catch (const nlohmann::json::parse_error&) {
            v = value;
        }
        set_dotted(j, key, v);
    }
}

} // namespace ecoterra
