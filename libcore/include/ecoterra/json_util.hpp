#pragma once
// Helpers for reading configuration JSON strictly: unknown keys are errors with a "did you mean",
// and every value is checked for type and range with the key's full dotted path in the message.
#include "ecoterra/error.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace ecoterra {

/// Levenshtein edit distance (for "did you mean").
std::size_t edit_distance(const std::string& a, const std::string& b);

/// Throws InputError if `obj` (at dotted path `where`) has a key not in `allowed`.
void require_known_keys(const nlohmann::json& obj, const std::vector<std::string>& allowed,
                        const std::string& where);

/// Reads obj[key] as a number if present (else `fallback`), checking min <= v <= max.
double get_number(const nlohmann::json& obj, const std::string& key, double fallback,
                  const std::string& where, double min = -1e300, double max = 1e300);
/// Reads obj[key] as an integer if present (else `fallback`), checking the range.
long long get_integer(const nlohmann::json& obj, const std::string& key, long long fallback,
                      const std::string& where, long long min = -(1LL << 62),
                      long long max = 1LL << 62);
bool get_bool(const nlohmann::json& obj, const std::string& key, bool fallback,
              const std::string& where);
std::string get_string(const nlohmann::json& obj, const std::string& key,
                       const std::string& fallback, const std::string& where);

/// Parses JSON text, naming `source` in the error.
/// A string that must be one of `choices`; returns its index. The error lists the choices.
std::size_t get_choice(const nlohmann::json& obj, const std::string& key,
                       const std::vector<std::string>& choices, std::size_t fallback,
                       const std::string& where);

nlohmann::json parse_json(const std::string& text, const std::string& source);

/// Sets `value` at the dotted path `key` of `j` ("vegetation.initial.random.stems_per_ha"),
/// making the objects on the way (a non-object on the way is replaced by one): the one setter of
/// `--set KEY=VALUE`, ensemble axes and ensemble `set` entries.
void set_dotted(nlohmann::json& j, const std::string& key, const nlohmann::json& value);

/// Applies `--set KEY=VALUE` overrides in order: VALUE is parsed as JSON, and taken as a string
/// when it is not JSON ("--set climate.preset=temperate"). InputError for a missing '=' or a
/// number out of range.
void apply_overrides(nlohmann::json& j, const std::vector<std::string>& overrides);

} // namespace ecoterra
