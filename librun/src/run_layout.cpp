#include "run_layout.hpp"

#include <limits>

#include "ecoterra/hydro/scene.hpp"
#include "ecoterra/hydro/soil_strength.hpp"
#include "ecoterra/io/hdf5_writer.hpp"
#include "ecoterra/terrain/io/raster_io.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <map>
#include <mutex>
#include <sstream>
#include <unistd.h>

namespace ecoterra::run::layout {

using namespace ecoterra::eco;

using nlohmann::json;

std::string snapshot_dir_name(const fs::path& output) {
    return output.stem().string() + ".snapshots";
}

std::string snapshot_file_name(int index) {
    char name[32];
    std::snprintf(name, sizeof name, "%04d.h5", index);
    return name;
}

std::uint64_t raster_hash(const RasterD& r) {
    return fnv1a64(r.data(), static_cast<std::size_t>(r.size()) * sizeof(double));
}

std::string snapshot_group(int index) {
    char name[32];
    std::snprintf(name, sizeof name, "/%04d", index);
    return name;
}

namespace {
/// Writes `rows` as one dataset per column under `group`.
template <class R>
void write_records(io::Hdf5Writer& h5, const std::string& group, const std::vector<R>& rows,
                   const std::vector<Column<R>>& columns) {
    for (const auto& c : columns) {
        const std::string dataset = group + "/" + c.name;
        auto write = [&]<class T>(T) {
            std::vector<T> v;
            v.reserve(rows.size());
            for (const auto& r : rows) v.push_back(static_cast<T>(c.get(r)));
            h5.series(dataset, v, c.unit, c.description);
        };
        if (c.type == ColumnType::int64)
            write(std::int64_t{});
        else if (c.type == ColumnType::int32)
            write(std::int32_t{});
        else
            write(double{});
    }
}
} // namespace

void write_snapshot(const Ecosystem& eco, const fs::path& path, int index) {
    io::Hdf5Writer h5(path);
    const std::string g = snapshot_group(index);
    const auto& w = eco.last_weather();
    std::vector<PlantRecord> rows;
    rows.reserve(eco.plants().size());
    const auto& species = eco.scene().ecosystem.species;
    for (const Plant& p : eco::rows(eco.plants()))
        rows.push_back(plant_record(p, species[p.species]));
    write_records(h5, g + "/plants", rows, plant_columns());
    std::vector<DeadWoodRecord> dead;
    dead.reserve(eco.dead_wood().pieces().size());
    for (const auto& d : eco.dead_wood().pieces())
        dead.push_back(deadwood_record(d, species[d.species]));
    write_records(h5, g + "/deadwood", dead, deadwood_columns());
    const auto& hy = eco.hydrology();
    write_layers(h5, g, hydro::water_state_layers(), hy);
    h5.raster(
        g + "/rating_cone_index_kpa",
        hydro::rating_cone_index_map_kpa(eco.scene().hydro.soil, hy.critical_layer_moisture()),
        "kPa",
        "rating cone index of the soil at its critical layer's water (Sullivan & Anderson "
        "2000 by texture class; docs/mobility.md s9)");
    h5.raster(g + "/shade_fraction", eco.ground_shade(), "1",
              "light intercepted by crowns above the ground (plant grid)");
    h5.raster(g + "/ground_cover", eco.ground_cover(), "1",
              "cover of the ground layer (grasses and herbs), fraction of the cell's ground");
    const auto& layer = eco.ground_layer().species();
    for (std::size_t k = 0; k < layer.size(); ++k) {
        const std::string ds = g + "/ground_cover_by_species/" + std::to_string(layer[k]);
        h5.raster(ds, eco.ground_cover(k), "1",
                  "cover of species " + std::to_string(layer[k]) + " (" +
                      eco.scene().ecosystem.species[layer[k]].name + "), fraction of the ground");
    }
    if (eco.scene().snapshot_checkpoints) {
        ArchiveWriter a;
        eco.save_state(a);
        h5.series(g + "/checkpoint/state", a.bytes(), "1",
                  "full model state at this snapshot (binary, ecoterra checkpoint format)");
        h5.attribute(g + "/checkpoint", "checksum_fnv1a64",
                     std::to_string(fnv1a64(a.bytes().data(), a.bytes().size())));
    }
    h5.integer_attribute(g, "year", eco.years_done());
    h5.integer_attribute(g, "day", eco.days_done());
    h5.attribute(g, "date",
                 "simulation year " + std::to_string(w.year) + ", day " + std::to_string(w.doy));
    h5.commit();
}

void write_main(const Ecosystem& eco, const fs::path& path, const json& provenance,
                const std::vector<std::string>& snapshot_checksums, const std::string& link_dir,
                io::ChunkCache* cache) {
    const int snapshots = static_cast<int>(snapshot_checksums.size());
    io::Hdf5Writer h5 = cache ? io::Hdf5Writer(path, *cache) : io::Hdf5Writer(path);
    const EcoScene& sc = eco.scene();
    h5.raster(terrain::io::kRunTerrainDataset, sc.hydro.dem, "m",
              "terrain elevation (hydrology grid)");
    h5.attribute(terrain::io::kRunTerrainDataset, "source_json", sc.hydro.terrain_source.dump());
    hydro::write_soil_maps(h5, sc.hydro.soil);
    json sp = json::array();
    std::string names;
    for (const auto& s : sc.ecosystem.species) {
        sp.push_back(species_to_json(s));
        names += (names.empty() ? "" : "\n") + s.name;
    }
    h5.attribute("/species", "json", sp.dump());
    h5.attribute("/species", "names", names);
    std::vector<std::string> list;
    for (const auto& s : sc.ecosystem.species) list.push_back(s.name);
    h5.strings("/species/name", list, "species names; plants/species is the 0-based index");
    std::vector<std::string> forms;
    for (const auto& s : sc.ecosystem.species) forms.push_back(life_form_name(s.life_form));
    h5.strings("/species/life_form", forms,
               "tree, shrub, grass (the ground layer: snapshot ground_cover) or object");
    h5.attribute("/species", "ecosystem", sc.ecosystem.name);
    h5.attribute("/provenance", "json", provenance.dump());
    h5.attribute("/diagnosis", "json", eco.diagnosis().json.dump());
    if (sc.seed <= static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()))
        h5.integer_attribute("/provenance", "seed", static_cast<std::int64_t>(sc.seed));
    else
        h5.attribute("/provenance", "seed", std::to_string(sc.seed)); // beyond int64: as text
    hydro::write_table(h5, "/series/yearly", eco.yearly());
    hydro::write_table(h5, "/series/daily", eco.daily());
    ArchiveWriter a;
    eco.save_state(a, Ecosystem::SeriesIn::run_file); // the series once, in /series
    h5.series("/checkpoint/state", a.bytes(), "1",
              "full model state at the last snapshot (binary, ecoterra checkpoint format)");
    h5.integer_attribute("/checkpoint", "year", eco.years_done());
    h5.attribute("/checkpoint", "terrain_hash", std::to_string(raster_hash(sc.hydro.dem)));
    h5.attribute("/checkpoint", "checksum_fnv1a64",
                 std::to_string(fnv1a64(a.bytes().data(), a.bytes().size())));
    const std::string dir = link_dir.empty() ? snapshot_dir_name(path) : link_dir;
    for (int k = 0; k < snapshots; ++k) {
        char link[32];
        std::snprintf(link, sizeof link, "/snapshots/%04d", k);
        h5.external_link(link, dir + "/" + snapshot_file_name(k), snapshot_group(k));
    }
    h5.integer_attribute("/snapshots", "count", snapshots);
    std::string sums;
    for (const auto& c : snapshot_checksums) sums += c + "\n";
    h5.attribute("/snapshots", "checksums_fnv1a64", sums);
    h5.attribute("/", "area_m2", eco.plant_grid().width_m() * eco.plant_grid().height_m());
    h5.commit();
}

std::string file_checksum(const fs::path& file) {
    return std::to_string(fnv1a64_file(file));
}

std::vector<std::string> read_snapshot_checksums(const fs::path& run, int snapshots) {
    std::vector<std::string> out(static_cast<std::size_t>(std::max(snapshots, 0)));
    H5::H5File f = open_run(run);
    if (!f.nameExists("/snapshots")) return out;
    const H5::Group g = f.openGroup("/snapshots");
    if (!g.attrExists("checksums_fnv1a64")) return out;
    std::istringstream in(read_string_attr(g, "checksums_fnv1a64"));
    std::string line;
    for (std::size_t k = 0; k < out.size() && std::getline(in, line); ++k) out[k] = line;
    return out;
}

void verify_snapshot(const fs::path& run, int k, const fs::path& file, const std::string& what) {
    struct Seen {
        std::uintmax_t size;
        fs::file_time_type time;
        std::string checksum;
    };
    static std::mutex mutex;
    static std::map<std::string, Seen> seen; // files hashed in this process
    std::string expected;
    try {
        expected = read_snapshot_checksums(run, k + 1)[static_cast<std::size_t>(k)];
    } catch (const H5::Exception& e) {
        throw InputError(run.string() + ": cannot read /snapshots (" + e.getDetailMsg() + ")");
    }
    if (expected.empty()) return; // written before snapshots had checksums
    std::error_code ec;
    const auto size = fs::file_size(file, ec);
    const auto time = fs::last_write_time(file, ec);
    const std::string key = fs::absolute(file).lexically_normal().string();
    std::string actual;
    {
        const std::lock_guard lock(mutex);
        const auto it = seen.find(key);
        if (it != seen.end() && it->second.size == size && it->second.time == time)
            actual = it->second.checksum;
    }
    if (actual.empty()) {
        actual = file_checksum(file);
        const std::lock_guard lock(mutex);
        seen[key] = {size, time, actual};
    }
    if (actual != expected)
        throw InputError(what +
                         "is damaged: its bytes do not match the checksum the run file "
                         "holds for it (FNV-1a 64 " +
                         actual + ", expected " + expected +
                         "); it was changed or corrupted after the run wrote it");
}

std::string read_string_attr(const H5::H5Object& o, const std::string& name) {
    H5::Attribute a = o.openAttribute(name);
    std::string v;
    a.read(a.getStrType(), v);
    return v;
}

double read_double_attr(const H5::H5Object& o, const std::string& name) {
    double v = 0;
    o.openAttribute(name).read(H5::PredType::NATIVE_DOUBLE, &v);
    return v;
}

H5::H5File open_run(const fs::path& run) {
    H5::Exception::dontPrint();
    if (!fs::exists(run)) throw InputError(run.string() + ": no such run file");
    bool hdf5 = false;
    try {
        hdf5 = H5::H5File::isHdf5(run.string());
    } catch (const H5::Exception&) {
    }
    if (!hdf5)
        throw InputError(run.string() + ": not an HDF5 file; give an ecoterra run file (the " +
                         "RUN.h5 that `ecoterra run -o` wrote)");
    try {
        H5::H5File f(run.string(), H5F_ACC_RDONLY);
        if (!f.nameExists("/provenance") || !f.nameExists("/checkpoint"))
            throw InputError(run.string() + ": not an ecoterra ecosystem run (no /checkpoint)");
        return f;
    } catch (const H5::Exception& e) {
        throw InputError(run.string() + ": the HDF5 file is damaged or truncated (" +
                         e.getDetailMsg() + ")");
    }
}

RunCheckpoint read_run_checkpoint(const fs::path& run, const EcoScene& sc, bool state) {
    H5::H5File f = open_run(run);
    RunCheckpoint c;
    std::vector<std::uint8_t>& bytes = c.bytes;
    std::string hash, checksum;
    try {
        if (state)
            bytes = read_vector<std::uint8_t>(f.openGroup("/checkpoint"), "state",
                                              H5::PredType::NATIVE_UINT8);
        hash = read_string_attr(f.openGroup("/checkpoint"), "terrain_hash");
        checksum = read_string_attr(f.openGroup("/checkpoint"), "checksum_fnv1a64");
        f.openGroup("/checkpoint").openAttribute("year").read(H5::PredType::NATIVE_INT, &c.year);
    } catch (const H5::Exception& e) {
        throw InputError(run.string() + ": cannot read /checkpoint (" + e.getDetailMsg() + ")");
    }
    if (state && checksum != std::to_string(fnv1a64(bytes.data(), bytes.size())))
        throw InputError(run.string() + ": /checkpoint/state is damaged (its checksum_fnv1a64 " +
                         checksum + " does not match its " + std::to_string(bytes.size()) +
                         " bytes)");
    if (hash != std::to_string(raster_hash(sc.hydro.dem)))
        throw InputError(run.string() + ": the terrain rebuilt from the stored scene differs "
                                        "from the run's (was the terrain file changed?)");
    return c;
}

std::vector<double> read_series_column(const H5::H5File& f, const fs::path& run,
                                       const std::string& table, const std::string& column) {
    const std::string name = "/series/" + table + "/" + column;
    try {
        return read_vector<double>(f.openGroup("/series/" + table), column,
                                   H5::PredType::NATIVE_DOUBLE);
    } catch (const H5::Exception& e) {
        throw InputError(run.string() + ": cannot read " + name + " (" + e.getDetailMsg() + ")");
    }
}

/// Creates `dir` if needed and writes and removes a file in it: IoError naming it if that fails.
void require_writable_folder(const fs::path& dir, const std::string& what) {
    io::create_folder(dir, what);
    std::error_code ec;
    std::string probe(".write-test-");
    probe.append(std::to_string(::getpid()));
    const fs::path file = dir / probe;
    const int fd = ::open(file.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0)
        throw IoError(dir.string() + ": cannot write in " + what + ": " + std::strerror(errno));
    ::close(fd);
    fs::remove(file, ec);
}

} // namespace ecoterra::run::layout
