#pragma once
// Declarative catalogues: every parameter of a struct written once, with its key, unit, default,
// valid range or choices and description, and every output column with its name, unit, type and
// description. From one catalogue follow the strict JSON reader (unknown keys with "did you
// mean", range errors naming the key and the value), the resolved JSON written into runs (and read
// back on resume), `ecoterra describe`, and the tables in docs/parameters.md.
//
// A parameter catalogue for a struct S:
//
//   static const ParamCatalog<HydrologyOptions> c("hydrology", {
//       number("root_zone_depth_m", &HydrologyOptions::root_zone_depth_m, "m", 0.01, 10,
//              "depth of the root zone whose water the model tracks"),
//       choice("routing", &HydrologyOptions::routing, {{"d8", Routing::d8}, ...}, "..."),
//   });
//   HydrologyOptions o = c.read(json, HydrologyOptions{});   // defaults from the second argument
//   json resolved = c.to_json(o);
//
// Keys may be dotted ("dispersal.mean_distance_m"): the JSON holds nested objects, and a member
// is then reached by an accessor instead of a member pointer. Checks between keys (an optimum
// above a base) stay in the struct's validate().
#include "ecoterra/json_util.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace ecoterra {

enum class ParamKind { number, integer, flag, choice, text, choices };

/// One parameter of struct S.
template <class S>
struct Param {
    std::string key; ///< dotted path below the catalogue's section
    ParamKind kind = ParamKind::number;
    std::string unit; ///< SI unit ("m", "m3/m3", "1" for a pure number, "" for text and flags)
    double min = -std::numeric_limits<double>::infinity();
    double max = std::numeric_limits<double>::infinity();
    std::vector<std::string> choices; ///< choice: the accepted strings
    std::string description;
    std::string default_note; ///< shown instead of the default value when it depends on others
    bool required = false;    ///< the key must be present (no default)
    bool optional = false;    ///< absent means "none" (to_json leaves it out when unset)
    /// The value as JSON (null when an optional value is unset).
    std::function<nlohmann::json(const S&)> get;
    /// Sets the value from JSON already checked for type, range or choice.
    std::function<void(S&, const nlohmann::json&)> set;

    Param&& with_note(std::string note) && {
        default_note = std::move(note);
        return std::move(*this);
    }
    Param&& mandatory() && {
        required = true;
        return std::move(*this);
    }
};

namespace catalog_detail {
inline std::vector<std::string> split_key(const std::string& key) {
    std::vector<std::string> parts;
    std::size_t start = 0;
    for (;;) {
        const auto dot = key.find('.', start);
        parts.push_back(key.substr(start, dot - start));
        if (dot == std::string::npos) return parts;
        start = dot + 1;
    }
}
inline std::string join(const std::string& a, const std::string& b) {
    return a.empty() ? b : b.empty() ? a : a + "." + b;
}
/// Turns a member pointer or an accessor (T& (*)(S&)) into one accessor.
template <class S, class T>
auto accessor(T S::*m) {
    return [m](S& s) -> T& { return s.*m; };
}
template <class S, class T>
auto accessor(T& (*f)(S&)) {
    return f;
}
/// A parameter's identity and limits, without its accessors.
template <class S>
Param<S> param(std::string key, ParamKind kind, std::string unit, double min, double max,
               std::string description) {
    Param<S> p;
    p.key = std::move(key);
    p.kind = kind;
    p.unit = std::move(unit);
    p.min = min;
    p.max = max;
    p.description = std::move(description);
    return p;
}
/// A parameter stored in the member `ref` reaches, read from JSON as type J.
template <class J, class S, class Ref>
Param<S> bound(Param<S> p, Ref ref) {
    auto acc = accessor(ref);
    p.get = [acc](const S& s) { return nlohmann::json(acc(const_cast<S&>(s))); };
    p.set = [acc](S& s, const nlohmann::json& v) {
        using T = std::remove_reference_t<decltype(acc(s))>;
        acc(s) = static_cast<T>(v.get<J>());
    };
    return p;
}
constexpr double kNoLimit = std::numeric_limits<double>::infinity();
} // namespace catalog_detail

/// A real number in [min, max].
template <class S, class Ref>
Param<S> number(std::string key, Ref ref, std::string unit, double min, double max,
                std::string description) {
    return catalog_detail::bound<double>(catalog_detail::param<S>(std::move(key), ParamKind::number,
                                                                  std::move(unit), min, max,
                                                                  std::move(description)),
                                         ref);
}

/// An optional real number: absent means "none".
template <class S, class Ref>
Param<S> optional_number(std::string key, Ref ref, std::string unit, double min, double max,
                         std::string description) {
    auto p = catalog_detail::param<S>(std::move(key), ParamKind::number, std::move(unit), min, max,
                                      std::move(description));
    p.optional = true;
    p.default_note = "none";
    auto acc = catalog_detail::accessor(ref);
    p.get = [acc](const S& s) {
        const std::optional<double>& v = acc(const_cast<S&>(s));
        return v ? nlohmann::json(*v) : nlohmann::json();
    };
    p.set = [acc](S& s, const nlohmann::json& v) { acc(s) = v.get<double>(); };
    return p;
}

/// A whole number in [min, max] (any integer member type).
template <class S, class Ref>
Param<S> integer(std::string key, Ref ref, std::string unit, double min, double max,
                 std::string description) {
    return catalog_detail::bound<long long>(
        catalog_detail::param<S>(std::move(key), ParamKind::integer, std::move(unit), min, max,
                                 std::move(description)),
        ref);
}

template <class S, class Ref>
Param<S> flag(std::string key, Ref ref, std::string description) {
    using catalog_detail::kNoLimit;
    return catalog_detail::bound<bool>(catalog_detail::param<S>(std::move(key), ParamKind::flag, "",
                                                                -kNoLimit, kNoLimit,
                                                                std::move(description)),
                                       ref);
}

template <class S, class Ref>
Param<S> text(std::string key, Ref ref, std::string description) {
    using catalog_detail::kNoLimit;
    return catalog_detail::bound<std::string>(
        catalog_detail::param<S>(std::move(key), ParamKind::text, "", -kNoLimit, kNoLimit,
                                 std::move(description)),
        ref);
}

/// One of named values (an enum, or any type with ==).
template <class S, class Ref, class E>
Param<S> choice(std::string key, Ref ref, std::vector<std::pair<std::string, E>> values,
                std::string description) {
    using catalog_detail::kNoLimit;
    auto acc = catalog_detail::accessor(ref);
    auto p = catalog_detail::param<S>(std::move(key), ParamKind::choice, "", -kNoLimit, kNoLimit,
                                      std::move(description));
    for (const auto& v : values) p.choices.push_back(v.first);
    p.get = [acc, values](const S& s) {
        const auto& cur = acc(const_cast<S&>(s));
        for (const auto& v : values)
            if (v.second == cur) return nlohmann::json(v.first);
        return nlohmann::json(); // a value with no name: cannot happen for a catalogued enum
    };
    p.set = [acc, values](S& s, const nlohmann::json& v) {
        const std::string name = v.get<std::string>();
        for (const auto& x : values)
            if (x.first == name) acc(s) = x.second;
    };
    return p;
}

/// A list of named values, each one of `names` (a std::vector<std::string> member), in any order,
/// each at most once.
template <class S, class Ref>
Param<S> choice_list(std::string key, Ref ref, std::vector<std::string> names,
                     std::string description) {
    using catalog_detail::kNoLimit;
    auto acc = catalog_detail::accessor(ref);
    auto p = catalog_detail::param<S>(std::move(key), ParamKind::choices, "", -kNoLimit, kNoLimit,
                                      std::move(description));
    p.choices = std::move(names);
    p.get = [acc](const S& s) { return nlohmann::json(acc(const_cast<S&>(s))); };
    p.set = [acc](S& s, const nlohmann::json& v) { acc(s) = v.get<std::vector<std::string>>(); };
    return p;
}

/// The parameters of struct S, read from and written to the JSON object of one section.
template <class S>
class ParamCatalog {
public:
    ParamCatalog(std::string section, std::vector<Param<S>> params)
        : m_section(std::move(section)), m_params(std::move(params)) {}

    const std::string& section() const { return m_section; }
    const std::vector<Param<S>>& params() const { return m_params; }

    /// Every key the catalogue accepts directly in the object at dotted path `sub` ("" = the
    /// section's own object), plus `extra`.
    std::vector<std::string> keys_at(const std::string& sub,
                                     const std::vector<std::string>& extra = {}) const {
        std::vector<std::string> out = extra;
        for (const auto& p : m_params) {
            const auto parts = catalog_detail::split_key(p.key);
            std::string prefix;
            for (std::size_t k = 0; k < parts.size(); ++k) {
                if (prefix == sub) {
                    if (std::find(out.begin(), out.end(), parts[k]) == out.end())
                        out.push_back(parts[k]);
                    break;
                }
                prefix = catalog_detail::join(prefix, parts[k]);
            }
        }
        return out;
    }

    /// Reads the keys present in `j` over `s` (whose members are the defaults). Unknown keys,
    /// wrong types, values out of range and unknown choices are InputErrors naming the dotted
    /// key (prefixed by `where`, default the section) and the value. `extra` keys are allowed at
    /// the top level and left to the caller.
    S read(const nlohmann::json& j, S s, const std::vector<std::string>& extra = {},
           const std::string& where = {}) const {
        const std::string root = where.empty() ? m_section : where;
        check_keys(j, "", root, extra);
        for (const auto& p : m_params) {
            const auto parts = catalog_detail::split_key(p.key);
            const nlohmann::json* node = &j;
            std::string at = root;
            for (std::size_t k = 0; k + 1 < parts.size() && node; ++k) {
                node = node->contains(parts[k]) ? &(*node)[parts[k]] : nullptr;
                at = catalog_detail::join(at, parts[k]);
            }
            const std::string& leaf = parts.back();
            if (!node || !node->contains(leaf)) {
                if (p.required)
                    throw InputError("missing key '" + catalog_detail::join(at, leaf) + "'" +
                                     (p.description.empty() ? "" : " (" + p.description + ")"));
                continue;
            }
            p.set(s, checked(p, *node, leaf, at));
        }
        return s;
    }

    /// Every key that `j` does not give (the defaulted ones), dotted below the section.
    std::vector<std::string> absent(const nlohmann::json& j) const {
        std::vector<std::string> out;
        for (const auto& p : m_params) {
            const nlohmann::json* node = &j;
            for (const auto& part : catalog_detail::split_key(p.key)) {
                node = node && node->is_object() && node->contains(part) ? &(*node)[part] : nullptr;
            }
            if (!node) out.push_back(p.key);
        }
        return out;
    }

    /// Checks every numeric value of `s` against its range (for structs built in code rather
    /// than read from JSON): InputError "section.key = value is outside [min, max]".
    void check(const S& s, const std::string& where = {}) const {
        const std::string root = where.empty() ? m_section : where;
        for (const auto& p : m_params) {
            if (p.kind != ParamKind::number && p.kind != ParamKind::integer) continue;
            const nlohmann::json v = p.get(s);
            if (v.is_null()) continue;
            const double d = v.get<double>();
            if (!(d >= p.min && d <= p.max))
                throw InputError(catalog_detail::join(root, p.key) + " = " + format_number(d) +
                                 " is outside [" + format_number(p.min) + ", " +
                                 format_number(p.max) + "]");
        }
    }

    /// Every parameter of `s` as nested JSON (unset optional values left out).
    nlohmann::json to_json(const S& s) const {
        nlohmann::json j = nlohmann::json::object();
        for (const auto& p : m_params) {
            nlohmann::json v = p.get(s);
            if (v.is_null()) continue;
            nlohmann::json* node = &j;
            const auto parts = catalog_detail::split_key(p.key);
            for (std::size_t k = 0; k + 1 < parts.size(); ++k) node = &(*node)[parts[k]];
            (*node)[parts.back()] = std::move(v);
        }
        return j;
    }

private:
    void check_keys(const nlohmann::json& j, const std::string& sub, const std::string& at,
                    const std::vector<std::string>& extra) const {
        require_known_keys(j, keys_at(sub, sub.empty() ? extra : std::vector<std::string>{}), at);
        for (auto it = j.begin(); it != j.end(); ++it) {
            const std::string child = catalog_detail::join(sub, it.key());
            if (is_group(child))
                check_keys(it.value(), child, catalog_detail::join(at, it.key()), {});
        }
    }
    bool is_group(const std::string& sub) const {
        for (const auto& p : m_params)
            if (p.key.size() > sub.size() && p.key.compare(0, sub.size(), sub) == 0 &&
                p.key[sub.size()] == '.')
                return true;
        return false;
    }
    static nlohmann::json checked(const Param<S>& p, const nlohmann::json& obj,
                                  const std::string& leaf, const std::string& at) {
        switch (p.kind) {
        case ParamKind::number:
            return get_number(obj, leaf, 0, at, p.min, p.max);
        case ParamKind::integer:
            return get_integer(obj, leaf, 0, at, static_cast<long long>(p.min),
                               static_cast<long long>(p.max));
        case ParamKind::flag:
            return get_bool(obj, leaf, false, at);
        case ParamKind::choice:
            return p.choices[get_choice(obj, leaf, p.choices, 0, at)];
        case ParamKind::text:
            return get_string(obj, leaf, "", at);
        case ParamKind::choices:
            return checked_list(p, obj.at(leaf), catalog_detail::join(at, leaf));
        }
        return nullptr;
    }

    /// An array of distinct names, each one of p.choices; InputError naming the key and the item.
    static nlohmann::json checked_list(const Param<S>& p, const nlohmann::json& v,
                                       const std::string& key) {
        std::string known;
        for (std::size_t k = 0; k < p.choices.size(); ++k) known += (k ? ", " : "") + p.choices[k];
        if (!v.is_array())
            throw InputError(key + " must be an array of names (" + known + "), got " + v.dump());
        std::vector<std::string> seen;
        for (const auto& item : v) {
            if (!item.is_string())
                throw InputError(key + ": " + item.dump() + " is not a name (" + known + ")");
            const std::string name = item.get<std::string>();
            if (std::find(p.choices.begin(), p.choices.end(), name) == p.choices.end())
                throw InputError(key + ": '" + name + "' is not one of " + known);
            if (std::find(seen.begin(), seen.end(), name) != seen.end())
                throw InputError(key + ": '" + name + "' is given twice");
            seen.push_back(name);
        }
        return v;
    }

    std::string m_section;
    std::vector<Param<S>> m_params;
};

/// What `ecoterra describe` and the docs show of one parameter.
struct ParamInfo {
    std::string key, unit, default_value, range, description;
};

template <class S>
std::vector<ParamInfo> describe(const ParamCatalog<S>& c, const S& defaults) {
    std::vector<ParamInfo> out;
    for (const auto& p : c.params()) {
        ParamInfo i;
        i.key = catalog_detail::join(c.section(), p.key);
        i.unit = p.unit;
        if (p.required)
            i.default_value = "required";
        else if (!p.default_note.empty())
            i.default_value = p.default_note;
        else {
            const nlohmann::json v = p.get(defaults);
            i.default_value = v.is_string()         ? v.get<std::string>()
                              : v.is_number_float() ? format_number(v.get<double>())
                                                    : v.dump();
        }
        switch (p.kind) {
        case ParamKind::number:
        case ParamKind::integer: {
            const bool lo = std::isfinite(p.min), hi = std::isfinite(p.max);
            if (lo && hi)
                i.range = "[" + format_number(p.min) + ", " + format_number(p.max) + "]";
            else if (lo)
                i.range = ">= " + format_number(p.min);
            else if (hi)
                i.range = "<= " + format_number(p.max);
            if (p.kind == ParamKind::integer) i.range += i.range.empty() ? "integer" : " integer";
            break;
        }
        case ParamKind::flag:
            i.range = "true, false";
            break;
        case ParamKind::choice:
            for (std::size_t k = 0; k < p.choices.size(); ++k)
                i.range += (k ? ", " : "") + p.choices[k];
            break;
        case ParamKind::text:
            i.range = "text";
            break;
        case ParamKind::choices:
            i.range = "array of:";
            for (std::size_t k = 0; k < p.choices.size(); ++k)
                i.range += (k ? ", " : " ") + p.choices[k];
            break;
        }
        i.description = p.description;
        out.push_back(std::move(i));
    }
    return out;
}

/// One output column (an HDF5 dataset or a CSV column) of rows of type R.
enum class ColumnType { float64, int64, int32, text };

template <class R>
struct Column {
    std::string name, unit, description;
    ColumnType type = ColumnType::float64;
    std::function<double(const R&)> get; ///< numeric columns
    std::function<void(R&, double)> set; ///< numeric columns, for readers
};

/// A double member of a row struct as a column.
template <class R, class T>
Column<R> column(std::string name, T R::*m, std::string unit, std::string description,
                 ColumnType type = ColumnType::float64) {
    Column<R> c;
    c.name = std::move(name);
    c.unit = std::move(unit);
    c.description = std::move(description);
    c.type = type;
    c.get = [m](const R& r) { return static_cast<double>(r.*m); };
    c.set = [m](R& r, double v) { r.*m = static_cast<T>(v); };
    return c;
}

/// What `ecoterra describe outputs` shows of one column.
struct ColumnInfo {
    std::string name, unit, type, description;
};

inline const char* column_type_name(ColumnType t) {
    switch (t) {
    case ColumnType::float64:
        return "float64";
    case ColumnType::int64:
        return "int64";
    case ColumnType::int32:
        return "int32";
    case ColumnType::text:
        return "text";
    }
    return "";
}

template <class R>
std::vector<ColumnInfo> describe(const std::string& group, const std::vector<Column<R>>& cols) {
    std::vector<ColumnInfo> out;
    for (const auto& c : cols)
        out.push_back({group + c.name, c.unit, column_type_name(c.type), c.description});
    return out;
}

namespace io {
class Hdf5Writer;
}

/// One raster output of a source object (a soil map, the water state): its dataset name, unit,
/// stored type and description, and how to write it into an HDF5 group.
template <class Src>
struct RasterLayer {
    std::string name, unit, type, description;
    std::function<void(io::Hdf5Writer&, const std::string& group, const Src&)> write;
};

/// A raster layer whose raster is `get(src)` (any Raster<T>; doubles are stored as float32).
template <class Src, class Get>
RasterLayer<Src> raster_layer(std::string name, std::string unit, std::string type,
                              std::string description, Get get) {
    RasterLayer<Src> l{
        std::move(name), std::move(unit), std::move(type), std::move(description), {}};
    // A generic lambda: its body is compiled where the writer is a complete type.
    l.write = [get, name = l.name, unit = l.unit,
               d = l.description](auto& h5, const std::string& group, const Src& s) {
        h5.raster(group + "/" + name, get(s), unit, d);
    };
    return l;
}

/// Writes every layer of `src` into `group` ("" = the file's root).
template <class Src>
void write_layers(io::Hdf5Writer& h5, const std::string& group,
                  const std::vector<RasterLayer<Src>>& layers, const Src& src) {
    for (const auto& l : layers) l.write(h5, group, src);
}

template <class Src>
std::vector<ColumnInfo> describe(const std::string& group,
                                 const std::vector<RasterLayer<Src>>& layers) {
    std::vector<ColumnInfo> out;
    for (const auto& l : layers) out.push_back({group + l.name, l.unit, l.type, l.description});
    return out;
}

/// A table of equal-length double columns with names, units and descriptions, built from a
/// column catalogue and filled a whole row at a time.
struct Table {
    std::vector<std::string> names, units, descriptions;
    std::vector<ColumnType> types; ///< how each column is stored (integers as integers)
    std::vector<std::vector<double>> columns;
    template <class R>
    static Table of(const std::vector<Column<R>>& cols) {
        Table t;
        for (const auto& c : cols) {
            t.names.push_back(c.name);
            t.units.push_back(c.unit);
            t.descriptions.push_back(c.description);
            t.types.push_back(c.type);
            t.columns.emplace_back();
        }
        return t;
    }
    template <class R>
    void push(const R& row, const std::vector<Column<R>>& cols) {
        if (cols.size() != columns.size())
            throw Error("table: a row of " + std::to_string(cols.size()) + " columns pushed into " +
                        std::to_string(columns.size()));
        for (std::size_t k = 0; k < cols.size(); ++k) columns[k].push_back(cols[k].get(row));
    }
    std::size_t rows() const { return columns.empty() ? 0 : columns.front().size(); }
    /// The column called `name`; Error if there is none.
    const std::vector<double>& column(const std::string& name) const {
        for (std::size_t k = 0; k < names.size(); ++k)
            if (names[k] == name) return columns[k];
        throw Error("table: no column '" + name + "'");
    }
};

} // namespace ecoterra
