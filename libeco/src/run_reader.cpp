#include "ecoterra/eco/run_reader.hpp"

#include "run_layout.hpp"

namespace ecoterra::eco {

using nlohmann::json;
using namespace run_layout;

RunInfo read_run_info(const fs::path& run) {
    H5::H5File f = open_run(run);
    RunInfo info;
    try {
        info.provenance = json::parse(read_string_attr(f.openGroup("/provenance"), "json"));
        std::string names = read_string_attr(f.openGroup("/species"), "names");
        std::size_t start = 0;
        for (;;) {
            const auto nl = names.find('\n', start);
            info.species.push_back(names.substr(start, nl - start));
            if (nl == std::string::npos) break;
            start = nl + 1;
        }
        info.snapshots = static_cast<int>(read_double_attr(f.openGroup("/snapshots"), "count"));
        info.area_m2 = read_double_attr(f.openGroup("/"), "area_m2");
    } catch (const H5::Exception& e) {
        throw InputError(run.string() + ": incomplete ecoterra run file (" + e.getDetailMsg() +
                         ")");
    } catch (const json::exception& e) {
        throw InputError(run.string() + ": /provenance json is damaged (" + e.what() + ")");
    }
    return info;
}

std::vector<double> SnapshotPlants::values(const std::string& name) const {
    for (const auto& c : plant_columns())
        if (c.name == name) {
            std::vector<double> v;
            v.reserve(plants.size());
            for (const auto& p : plants) v.push_back(c.get(p));
            return v;
        }
    throw Error("snapshot plants: no column '" + name + "'");
}

SnapshotPlants read_snapshot_plants(const fs::path& run, int index) {
    const RunInfo info = read_run_info(run);
    if (info.snapshots == 0) throw InputError(run.string() + ": the run has no snapshots");
    const int k = index < 0 ? info.snapshots + index : index;
    if (k < 0 || k >= info.snapshots)
        throw InputError(run.string() + ": --snapshot " + std::to_string(index) +
                         " is outside 0.." + std::to_string(info.snapshots - 1));
    SnapshotPlants s;
    s.index = k;
    open_snapshot(run, k, [&](const H5::Group& g) {
        s.year = static_cast<int>(read_double_attr(g, "year"));
        H5::Group p = g.openGroup("plants");
        for (const auto& c : plant_columns()) {
            auto read = [&]<class T>(const H5::PredType& type, T) {
                const auto v = read_vector<T>(p, c.name, type);
                if (&c == &plant_columns().front()) s.plants.resize(v.size());
                if (v.size() != s.plants.size())
                    throw InputError(run.string() + ": snapshot " + std::to_string(k) +
                                     ": plants/" + c.name + " has " + std::to_string(v.size()) +
                                     " rows, plants/" + plant_columns().front().name + " " +
                                     std::to_string(s.plants.size()));
                for (std::size_t r = 0; r < v.size(); ++r)
                    c.set(s.plants[r], static_cast<double>(v[r]));
            };
            if (c.type == ColumnType::int64)
                read(H5::PredType::NATIVE_INT64, std::int64_t{});
            else if (c.type == ColumnType::int32)
                read(H5::PredType::NATIVE_INT32, std::int32_t{});
            else
                read(H5::PredType::NATIVE_DOUBLE, double{});
        }
    });
    return s;
}

} // namespace ecoterra::eco
