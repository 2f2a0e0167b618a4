#pragma once
// An ensemble manifest (docs/ensembles.md): a base scene, axes of overrides, replicates and the
// analyses each member runs. Members are numbered 0 .. members()-1; member i is a pure function of
// (manifest, i): its overrides, its seeds and the hash of its inputs are computed here, so any
// process on any machine that reads the same manifest builds the same member.
#include <nlohmann/json.hpp>

#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace ecoterra::ensemble {

/// What a member starts from: an ecosystem scene it grows (`run`), a terrain specification it
/// generates (`terrain`), or a stand given as a stem list over a DEM (`mobility`).
enum class BaseKind { run, terrain, mobility };
const char* base_kind_name(BaseKind k);

struct Axis {
    std::string key; ///< dotted scene key, or analyses.NAME.KEY
    std::vector<nlohmann::json> values;
};

/// A summary picture: y (a metric column) against x (an axis), one line per value of `series`
/// (an axis, optional); or, with `histogram`, the mean diameter histograms of each series.
struct PictureSpec {
    std::string name, title, x, y, series;
    std::string x_label, y_label; ///< default: the key and the metric with its unit
    double x_scale = 1;           ///< x shown = axis value x_scale (e.g. m2/ha to ft2/acre)
    bool histogram = false;
};

struct Manifest {
    std::filesystem::path file; ///< as given
    std::string name, description;
    BaseKind kind = BaseKind::run;
    nlohmann::json base;            ///< the scene (run), spec (terrain) or {stems, dem} (mobility)
    std::filesystem::path base_dir; ///< the folder the base's relative paths start from
    std::filesystem::path dir;      ///< the manifest's folder (analyses' paths start from it)
    std::uint64_t seed = 1;
    bool seed_per_member = false; ///< false: replicate r of every combination shares its seeds
    int replicates = 1;
    std::vector<Axis> axes;
    std::vector<std::pair<std::string, nlohmann::json>> set; ///< fixed overrides, in order
    nlohmann::json analyses = nlohmann::json::object();
    bool keep_files = false; ///< keep each member's run.h5 (run) or terrain.h5 (terrain)
    std::vector<PictureSpec> pictures;
    nlohmann::json document; ///< the manifest as read (copied into the output folder)

    std::size_t combinations() const;
    std::size_t members() const { return combinations() * static_cast<std::size_t>(replicates); }
};

/// Reads and checks a manifest: unknown keys, axes over unknown scene keys, empty axes, a
/// replicate count below 1 and unreadable bases are InputErrors naming the file, key and value.
Manifest load_manifest(const std::filesystem::path& file);
/// The same from a manifest already parsed (`file` names it in messages, `dir` is its folder);
/// with `base_copy`, a base given as a file name is taken from the copy instead of the file.
Manifest manifest_from_document(const nlohmann::json& doc, const std::filesystem::path& file,
                                const std::filesystem::path& dir, const nlohmann::json* base_copy);

struct Member {
    std::size_t index = 0, combination = 0;
    int replicate = 0;
    std::vector<std::pair<std::string, nlohmann::json>> axes; ///< this member's axis values
    std::uint64_t seed = 0;                                   ///< the member's seed
    nlohmann::json seeds = nlohmann::json::object();          ///< every seed key set, and its value
    nlohmann::json scene;    ///< the base with the overrides applied
    nlohmann::json analyses; ///< the analyses with the overrides applied
    std::string input_hash;  ///< 16 hex digits over everything that decides the outputs
};

/// Member `index` (InputError naming the range when out of it).
Member make_member(const Manifest& m, std::size_t index);

/// A seed below 2^53 (exact in JSON, CSV and doubles) derived from `seed`, a stream name and an
/// index, through the same xoshiro256** streams as every other draw.
std::uint64_t derive_seed(std::uint64_t seed, const std::string& stream, std::uint64_t index);

/// A cell text of a JSON value for tables: strings as they are, numbers in full precision.
std::string value_text(const nlohmann::json& v);

} // namespace ecoterra::ensemble
