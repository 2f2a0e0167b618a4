#include "ecoterra/ensemble/manifest.hpp"

#include "ecoterra/analyses/analyses.hpp"
#include "ecoterra/analyses/describe.hpp"
#include "ecoterra/error.hpp"
#include "ecoterra/io/atomic_file.hpp"
#include "ecoterra/json_util.hpp"
#include "ecoterra/mobility/vehicle.hpp"
#include "ecoterra/provenance.hpp"
#include "ecoterra/random.hpp"
#include "ecoterra/terrain/generate.hpp"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <map>
#include <mutex>
#include <set>

namespace ecoterra::ensemble {

namespace fs = std::filesystem;
using nlohmann::json;

const char* base_kind_name(BaseKind k) {
    switch (k) {
    case BaseKind::run:
        return "run";
    case BaseKind::terrain:
        return "terrain";
    case BaseKind::mobility:
        return "mobility";
    }
    return "?";
}

std::size_t Manifest::combinations() const {
    std::size_t n = 1;
    for (const auto& a : axes) n *= a.values.size();
    return n;
}

std::string value_text(const json& v) {
    if (v.is_string()) return v.get<std::string>();
    return v.dump();
}

std::uint64_t derive_seed(std::uint64_t seed, const std::string& stream, std::uint64_t index) {
    Rng r(seed, "ensemble." + stream, index);
    return r() >> 11; // 53 bits
}

namespace {

constexpr std::size_t kMaxMembers = 10000000;

/// The dotted paths of every leaf and object of `j` (prefix included).
void dotted_paths(const json& j, const std::string& prefix, std::set<std::string>& out) {
    if (!j.is_object()) return;
    for (auto it = j.begin(); it != j.end(); ++it) {
        const std::string k = prefix.empty() ? it.key() : prefix + "." + it.key();
        out.insert(k);
        dotted_paths(it.value(), k, out);
    }
}

/// The keys each analysis takes, and whether it needs a vehicle.

std::vector<std::string> analyses_for(BaseKind k) {
    switch (k) {
    case BaseKind::run:
        return {"stand", "mobility", "mobility_map", "terrain", "traverse", "export", "pictures"};
    case BaseKind::terrain:
        return {"terrain", "traverse"};
    case BaseKind::mobility:
        return {"mobility"};
    }
    return {};
}

void check_analyses(const json& a, BaseKind kind, const std::string& where) {
    require_known_keys(a, analyses_for(kind), where);
    for (const auto& [name, keys] : analyses::analysis_keys()) {
        if (!a.contains(name)) continue;
        const json& v = a[name];
        if (name == "pictures") {
            if (!v.is_boolean())
                throw InputError(where + ".pictures must be true or false, got " + v.dump());
            continue;
        }
        require_known_keys(v, keys, where + "." + name);
        if ((name == "mobility" || name == "mobility_map" || name == "traverse") &&
            !v.contains("vehicle"))
            throw InputError(where + "." + name +
                             ": missing key 'vehicle' (a vehicle file, e.g. "
                             "../vehicles/mrzr4.json)");
        // Values too, from the catalogues, before any member runs.
        if (name == "mobility") analyses::mobility_catalog().read(v, {});
        if (name == "mobility_map") analyses::mobility_map_catalog().read(v, {});
        if (name == "traverse") analyses::traverse_catalog().read(v, {});
        if (name == "terrain") analyses::terrain_catalog().read(v, {});
        if (name == "export") analyses::export_catalog().read(v, {});
    }
}

/// Every vehicle file a member may use (the analyses', a fixed override's, an axis's values)
/// loads: a missing or bad vehicle is refused before any member runs, not by every member.
void check_vehicle_files(const Manifest& m) {
    for (const char* analysis : {"mobility", "mobility_map", "traverse"}) {
        const std::string key = std::string("analyses.") + analysis + ".vehicle";
        // The values members use: an axis's override the fixed `set`, which overrides the
        // analyses' own (a placeholder there that every member overrides is not checked).
        std::vector<std::pair<std::string, json>> values; // where named, value
        for (std::size_t a = 0; a < m.axes.size(); ++a)
            if (m.axes[a].key == key)
                for (const auto& v : m.axes[a].values)
                    values.emplace_back("axes[" + std::to_string(a) + "] (" + key + ")", v);
        if (values.empty())
            for (const auto& [k, v] : m.set)
                if (k == key) values.emplace_back("set." + key, v);
        if (values.empty() && m.analyses.contains(analysis) &&
            m.analyses[analysis].contains("vehicle"))
            values.emplace_back(key, m.analyses[analysis]["vehicle"]);
        std::set<std::string> checked;
        for (const auto& [where, v] : values) {
            if (!v.is_string())
                throw InputError(where + " = " + v.dump() + ": give a vehicle file's path");
            const std::string name = v.get<std::string>();
            if (!checked.insert(name).second) continue;
            const fs::path file = fs::path(name).is_absolute() ? fs::path(name) : m.dir / name;
            try {
                mobility::load_vehicle(file);
            } catch (const Error& e) {
                throw InputError(where + " = '" + name + "': " + e.what());
            }
        }
    }
}

/// Every key an override may name for a base of this kind: the catalogue's scene keys, the
/// base's own keys, the terrain generator's resolved keys, and the analyses' keys.
std::set<std::string> known_keys(const Manifest& m) {
    std::set<std::string> keys;
    dotted_paths(m.base, "", keys);
    auto terrain_keys = [&](const json& spec, const std::string& prefix) {
        json resolved;
        try {
            resolved = terrain::resolve_terrain_spec(spec);
        } catch (const InputError&) {
            return; // the base's own error shows when a member loads it
        }
        std::set<std::string> t;
        dotted_paths(resolved, "", t);
        for (const auto& k : t) keys.insert(prefix + k);
        // Any parameter of the method, set or not.
        for (const auto& p : terrain::terrain_param_keys(resolved.value("method", "")))
            keys.insert(prefix + "params." + p);
    };
    if (m.kind == BaseKind::run) {
        for (const auto& k : analyses::scene_keys()) keys.insert(k);
        if (m.base.contains("terrain") && m.base["terrain"].contains("generate"))
            terrain_keys(m.base["terrain"]["generate"], "terrain.generate.");
    } else if (m.kind == BaseKind::terrain) {
        terrain_keys(m.base, "");
    }
    for (const auto& [name, k] : analyses::analysis_keys()) {
        keys.insert("analyses." + name);
        for (const auto& s : k) keys.insert("analyses." + name + "." + s);
    }
    return keys;
}

void check_key(const Manifest& m, const std::set<std::string>& known, const std::string& key,
               const std::string& where) {
    if (known.count(key)) return;
    std::string best;
    std::size_t best_d = 4;
    for (const auto& k : known) {
        const std::size_t d = edit_distance(key, k);
        if (d < best_d) best_d = d, best = k;
    }
    throw InputError(where + " = '" + key + "' is not a key of the " + base_kind_name(m.kind) +
                     " base" + (best.empty() ? "" : " (did you mean '" + best + "'?)") +
                     "; `ecoterra describe scene` lists the scene keys");
}

std::string name_of(const json& doc, const std::string& file) {
    const std::string n = get_string(doc, "name", "", "");
    if (n.empty()) throw InputError(file + ": missing key 'name' (a short name of the ensemble)");
    for (char c : n)
        if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.'))
            throw InputError(file + ": name '" + n +
                             "' may hold only letters, digits, '_', '-' and '.'");
    return n;
}

/// Folds in the contents of every file the JSON names (strings that are paths of existing files,
/// relative to `dir`), in key order, so an edited ecosystem or vehicle file reruns the member.
/// FNV-1a of a file's bytes, remembered by path, size and modification time (an ensemble of
/// many members names the same few files in each).
std::uint64_t file_hash(const fs::path& p) {
    struct Seen {
        std::uintmax_t size;
        fs::file_time_type time;
        std::uint64_t hash;
    };
    static std::map<std::string, Seen> cache;
    static std::mutex lock;
    std::error_code ec;
    const auto size = fs::file_size(p, ec);
    const auto time = fs::last_write_time(p, ec);
    const std::string key = fs::absolute(p).lexically_normal().string();
    {
        const std::lock_guard<std::mutex> g(lock);
        const auto it = cache.find(key);
        if (it != cache.end() && it->second.size == size && it->second.time == time)
            return it->second.hash;
    }
    const std::uint64_t h = fnv1a64_file(p);
    const std::lock_guard<std::mutex> g(lock);
    cache[key] = {size, time, h};
    return h;
}

void hash_files(const json& j, const fs::path& dir, std::uint64_t& h) {
    if (j.is_object() || j.is_array()) {
        for (const auto& v : j) hash_files(v, dir, h);
    } else if (j.is_string()) {
        const std::string s = j.get<std::string>();
        if (s.empty() || s.size() > 4096) return;
        std::error_code ec;
        const fs::path p = fs::path(s).is_absolute() ? fs::path(s) : dir / s;
        if (!fs::is_regular_file(p, ec)) return;
        h = fnv1a64_fold(fnv1a64_text(s, h), file_hash(p));
    }
}

} // namespace

Manifest load_manifest(const fs::path& file) {
    return manifest_from_document(parse_json(io::read_text(file), file.string()), file,
                                  fs::absolute(file).parent_path(), nullptr);
}

namespace {

/// The base: its kind and its scene, terrain or stems (a file beside the manifest, or inline).
void read_base(const json& d, const json* base_copy, Manifest& m) {
    if (!d.contains("base") || !d["base"].is_object() || d["base"].size() != 1)
        throw InputError("base must be an object with one key: run (a scene file or object), "
                         "terrain (a terrain specification) or mobility ({stems, dem})");
    // (Not a structured binding of items(): it would refer into a temporary.)
    const auto first = d["base"].begin();
    const std::string kind_name = first.key();
    const json& base = first.value();
    if (kind_name == "run")
        m.kind = BaseKind::run;
    else if (kind_name == "terrain")
        m.kind = BaseKind::terrain;
    else if (kind_name == "mobility")
        m.kind = BaseKind::mobility;
    else
        throw InputError("base." + kind_name + ": the base is run, terrain or mobility");
    if (base.is_string() && base_copy) {
        m.base = *base_copy;
        m.base_dir = fs::absolute(m.dir / base.get<std::string>()).parent_path();
    } else if (base.is_string()) {
        const fs::path p = m.dir / base.get<std::string>();
        m.base = with_context("base." + kind_name,
                              [&] { return parse_json(io::read_text(p), p.string()); });
        m.base_dir = fs::absolute(p).parent_path();
    } else if (base.is_object()) {
        m.base = base;
        m.base_dir = m.dir;
    } else {
        throw InputError("base." + kind_name + " must be a file name or an object, got " +
                         base.dump());
    }
    if (m.kind == BaseKind::mobility)
        require_known_keys(m.base, {"stems", "dem", "deadwood"}, "base.mobility");
}

/// The axes: each a known key, given once, with at least one value.
void read_axes(const json& d, const std::set<std::string>& known, Manifest& m) {
    if (!d.contains("axes")) return;
    if (!d["axes"].is_array()) throw InputError("axes must be an array of {key, values}");
    std::set<std::string> seen;
    for (std::size_t i = 0; i < d["axes"].size(); ++i) {
        const json& a = d["axes"][i];
        const std::string w = "axes[" + std::to_string(i) + "]";
        require_known_keys(a, {"key", "values"}, w);
        Axis ax;
        ax.key = get_string(a, "key", "", w);
        if (ax.key.empty()) throw InputError(w + ": missing key 'key'");
        check_key(m, known, ax.key, w + ".key");
        if (!seen.insert(ax.key).second)
            throw InputError(w + ".key '" + ax.key + "' is already an axis");
        if (!a.contains("values") || !a["values"].is_array())
            throw InputError(w + " (" + ax.key + "): values must be an array");
        if (a["values"].empty())
            throw InputError(w + " (" + ax.key +
                             "): values is empty; an axis needs at least one value");
        for (const auto& v : a["values"]) ax.values.push_back(v);
        m.axes.push_back(std::move(ax));
        // Checked as it grows, so that a product past the limit cannot wrap around.
        if (m.combinations() > kMaxMembers)
            throw InputError("the axes make more than 10 000 000 combinations");
    }
}

/// One picture of the summary: a line over an axis, or the mean histograms.
PictureSpec read_picture(const json& p, const std::string& w,
                         const std::set<std::string>& axis_keys, BaseKind kind) {
    require_known_keys(
        p, {"name", "title", "x", "y", "series", "histogram", "x_label", "y_label", "x_scale"}, w);
    PictureSpec s;
    s.name = get_string(p, "name", "", w);
    s.title = get_string(p, "title", "", w);
    s.x = get_string(p, "x", "", w);
    s.y = get_string(p, "y", "", w);
    s.series = get_string(p, "series", "", w);
    s.histogram = get_bool(p, "histogram", false, w);
    s.x_label = get_string(p, "x_label", "", w);
    s.y_label = get_string(p, "y_label", "", w);
    s.x_scale = get_number(p, "x_scale", 1, w, 1e-300, 1e300);
    if (s.name.empty() || s.name.find('/') != std::string::npos)
        throw InputError(w + ".name must be a file name (without .png)");
    if (!s.x.empty() && !axis_keys.count(s.x))
        throw InputError(w + ".x = '" + s.x + "' is not an axis of this manifest");
    if (!s.series.empty() && !axis_keys.count(s.series))
        throw InputError(w + ".series = '" + s.series + "' is not an axis of this manifest");
    if (!s.histogram && (s.x.empty() || s.y.empty()))
        throw InputError(w + ": a line picture needs x (an axis) and y (a metric)");
    if (s.histogram && !(kind == BaseKind::run))
        throw InputError(w + ": histograms need a run base");
    return s;
}

void read_pictures(const json& d, Manifest& m) {
    if (!d.contains("pictures")) return;
    if (!d["pictures"].is_array())
        throw InputError("pictures must be an array of {name, x, y, series, title}");
    std::set<std::string> axis_keys;
    for (const auto& a : m.axes) axis_keys.insert(a.key);
    for (std::size_t i = 0; i < d["pictures"].size(); ++i)
        m.pictures.push_back(read_picture(d["pictures"][i], "pictures[" + std::to_string(i) + "]",
                                          axis_keys, m.kind));
}

} // namespace

Manifest manifest_from_document(const json& doc, const fs::path& file, const fs::path& dir,
                                const json* base_copy) {
    const std::string f = file.string();
    Manifest m;
    m.file = file;
    m.dir = dir;
    m.document = doc;
    const json& d = m.document;
    return with_context(f, [&] {
        require_known_keys(d,
                           {"name", "description", "base", "seed", "seeds", "replicates", "axes",
                            "set", "analyses", "keep_files", "pictures"},
                           "");
        m.name = name_of(d, f);
        m.description = get_string(d, "description", "", "");
        read_base(d, base_copy, m);
        m.seed = static_cast<std::uint64_t>(get_integer(d, "seed", 1, "", 0, 1LL << 53));
        const std::size_t per = get_choice(d, "seeds", {"per_replicate", "per_member"}, 0, "");
        m.seed_per_member = per == 1;
        m.replicates = static_cast<int>(get_integer(d, "replicates", 1, "", 1, 1000000));
        m.keep_files = get_bool(d, "keep_files", false, "");
        m.analyses = d.value("analyses", json::object());
        check_analyses(m.analyses, m.kind, "analyses");
        const auto known = known_keys(m);
        if (d.contains("set")) {
            if (!d["set"].is_object())
                throw InputError("set must be an object of dotted keys and values");
            for (auto it = d["set"].begin(); it != d["set"].end(); ++it) {
                check_key(m, known, it.key(), "set key");
                m.set.emplace_back(it.key(), it.value());
            }
        }
        read_axes(d, known, m);
        if (m.members() > kMaxMembers)
            throw InputError("the axes and replicates make " + std::to_string(m.members()) +
                             " members; at most 10 000 000");
        read_pictures(d, m);
        check_vehicle_files(m);
        return m;
    });
}

Member make_member(const Manifest& m, std::size_t index) {
    if (index >= m.members())
        throw InputError("member " + std::to_string(index) + " is out of range: " +
                         m.file.string() + " has members 0 to " + std::to_string(m.members() - 1));
    Member mb;
    mb.index = index;
    const auto reps = static_cast<std::size_t>(m.replicates);
    mb.combination = index / reps;
    mb.replicate = static_cast<int>(index % reps);
    std::size_t c = mb.combination;
    std::vector<std::size_t> pick(m.axes.size());
    for (std::size_t k = m.axes.size(); k-- > 0;) {
        pick[k] = c % m.axes[k].values.size();
        c /= m.axes[k].values.size();
    }
    mb.seed = derive_seed(m.seed, "member",
                          m.seed_per_member ? index : static_cast<std::uint64_t>(mb.replicate));
    mb.scene = m.base;
    mb.analyses = m.analyses;
    // Seeds first, so that a seed the manifest sets (in `set` or an axis) wins.
    auto seed_key = [&](const std::string& key, const std::string& stream) {
        const std::uint64_t s = stream.empty() ? mb.seed : derive_seed(mb.seed, stream, 0);
        set_dotted(mb.scene, key, s);
        mb.seeds[key] = s;
    };
    if (m.kind == BaseKind::run) {
        seed_key("simulation.seed", "");
        if (m.base.contains("terrain") && m.base["terrain"].contains("generate"))
            seed_key("terrain.generate.seed", "terrain");
    } else if (m.kind == BaseKind::terrain) {
        seed_key("seed", "");
    }
    for (const char* a : {"mobility", "traverse"})
        if (mb.analyses.contains(a)) {
            const std::uint64_t s = derive_seed(mb.seed, a, 0);
            mb.analyses[a]["seed"] = s;
            mb.seeds["analyses." + std::string(a) + ".seed"] = s;
        }
    auto apply = [&](const std::string& key, const json& v) {
        if (key.rfind("analyses.", 0) == 0)
            set_dotted(mb.analyses, key.substr(9), v);
        else
            set_dotted(mb.scene, key, v);
        if (mb.seeds.contains(key)) mb.seeds[key] = v;
    };
    for (const auto& [k, v] : m.set) apply(k, v);
    for (std::size_t k = 0; k < m.axes.size(); ++k) {
        mb.axes.emplace_back(m.axes[k].key, m.axes[k].values[pick[k]]);
        apply(m.axes[k].key, m.axes[k].values[pick[k]]);
    }
    std::uint64_t h = fnv1a64_text(std::string("ecoterra ") + version());
    h = fnv1a64_text(base_kind_name(m.kind), h);
    h = fnv1a64_text(mb.scene.dump(), h);
    h = fnv1a64_text(mb.analyses.dump(), h);
    h = fnv1a64_text(m.keep_files ? "keep" : "drop", h);
    // The metrics' names and units: a member recorded under other names runs again.
    for (const auto& metric : analyses::describe_metrics())
        h = fnv1a64_text(metric.name + metric.unit, h);
    hash_files(mb.scene, m.base_dir, h);
    hash_files(mb.analyses, m.dir, h);
    char hex[17];
    std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
    mb.input_hash = hex;
    return mb;
}

} // namespace ecoterra::ensemble
