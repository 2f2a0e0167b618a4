#include "ecoterra/run/run_reader.hpp"

#include "run_layout.hpp"

#include <cmath>

#include "ecoterra/terrain/io/raster_io.hpp"
#include "ecoterra/units.hpp"

#include <algorithm>
#include <numbers>

namespace ecoterra::run {

using namespace ecoterra::eco;

using nlohmann::json;
using namespace layout;

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

int resolve_snapshot_index(const fs::path& run, int index) {
    const RunInfo info = read_run_info(run);
    if (info.snapshots == 0) throw InputError(run.string() + ": the run has no snapshots");
    const int k = index < 0 ? info.snapshots + index : index;
    if (k < 0 || k >= info.snapshots)
        throw InputError(run.string() + ": --snapshot " + std::to_string(index) +
                         " is outside 0.." + std::to_string(info.snapshots - 1));
    return k;
}

std::vector<Species> read_run_species(const fs::path& run) {
    H5::H5File f = open_run(run);
    try {
        const json j = json::parse(read_string_attr(f.openGroup("/species"), "json"));
        return parse_ecosystem({{"name", "run"}, {"Species", j}}, run.string() + ": /species")
            .species;
    } catch (const H5::Exception& e) {
        throw InputError(run.string() + ": incomplete ecoterra run file (" + e.getDetailMsg() +
                         ")");
    } catch (const json::exception& e) {
        throw InputError(run.string() + ": /species json is damaged (" + e.what() + ")");
    }
}

RasterD read_run_terrain(const fs::path& run) {
    open_run(run); // names the file if it is not a run
    return terrain::io::read_hdf5(run, terrain::io::kRunTerrainDataset);
}

RasterD read_run_soil(const fs::path& run, const std::string& name, const GridSpec& grid) {
    const std::string what = run.string() + ": /soil/" + name;
    bool has = false;
    {
        H5::H5File f = open_run(run);
        has = f.nameExists("soil") && f.openGroup("soil").nameExists(name);
    }
    if (!has) throw InputError(what + " is missing");
    RasterD r = terrain::io::read_hdf5(run, "/soil/" + name);
    if (r.nx() != grid.nx || r.ny() != grid.ny)
        throw InputError(what + " is " + std::to_string(r.ny()) + " x " + std::to_string(r.nx()) +
                         ", not " + std::to_string(grid.ny) + " x " + std::to_string(grid.nx) +
                         " (the terrain's grid)");
    return RasterD(grid, r.array());
}

SnapshotGround read_snapshot_ground(const fs::path& run, int index, const GridSpec& grid) {
    SnapshotGround g;
    if (snapshot_has_dataset(run, index, "rating_cone_index_kpa"))
        g.rci_kpa = read_snapshot_raster(run, index, "rating_cone_index_kpa", grid);
    if (snapshot_has_dataset(run, index, "surface_water_depth_m"))
        g.water_depth_m = read_snapshot_raster(run, index, "surface_water_depth_m", grid);
    g.fine_grained = mobility::fine_grained_mask(read_run_soil(run, "silt_pct", grid),
                                                 read_run_soil(run, "clay_pct", grid));
    return g;
}

mobility::GroundMaps SnapshotGround::maps() const {
    mobility::GroundMaps m;
    if (rci_kpa) m.rci_kpa = &*rci_kpa;
    if (water_depth_m) m.water_depth_m = &*water_depth_m;
    if (fine_grained) m.fine_grained = &*fine_grained;
    return m;
}

int snapshot_of_year(const fs::path& run, int year) {
    const int count = read_run_info(run).snapshots;
    std::string years;
    for (int k = 0; k < count; ++k) {
        int y = 0;
        open_snapshot(
            run, k, [&](const H5::Group& g) { y = static_cast<int>(read_double_attr(g, "year")); });
        if (y == year) return k;
        years += (years.empty() ? "" : ", ") + std::to_string(y);
    }
    throw InputError(run.string() + ": no snapshot of year " + std::to_string(year) +
                     " (the run's snapshots are of years " + years + ")");
}

bool snapshot_has_dataset(const fs::path& run, int index, const std::string& name) {
    bool has = false;
    open_snapshot(run, resolve_snapshot_index(run, index),
                  [&](const H5::Group& g) { has = g.nameExists(name); });
    return has;
}

RasterD read_snapshot_raster(const fs::path& run, int index, const std::string& name,
                             const GridSpec& grid) {
    const int k = resolve_snapshot_index(run, index);
    RasterD r(grid);
    open_snapshot(run, k, [&](const H5::Group& g) {
        const std::string what =
            run.string() + ": snapshot " + std::to_string(k) + ": dataset " + name;
        if (!g.nameExists(name)) throw InputError(what + " is missing");
        H5::DataSet ds = g.openDataSet(name);
        hsize_t dims[2] = {0, 0};
        if (ds.getSpace().getSimpleExtentNdims() != 2 ||
            (ds.getSpace().getSimpleExtentDims(dims),
             dims[0] != static_cast<hsize_t>(grid.ny) || dims[1] != static_cast<hsize_t>(grid.nx)))
            throw InputError(what + " is not " + std::to_string(grid.ny) + " x " +
                             std::to_string(grid.nx) + " (the terrain's grid)");
        // Row-major [ny][nx], row 0 the south edge, as the raster stores it.
        std::vector<double> v(static_cast<std::size_t>(grid.nx) * grid.ny);
        ds.read(v.data(), H5::PredType::NATIVE_DOUBLE);
        for (int j = 0; j < grid.ny; ++j)
            for (int i = 0; i < grid.nx; ++i)
                r(i, j) = v[static_cast<std::size_t>(j) * grid.nx + i];
    });
    return r;
}

SnapshotPlants read_snapshot_plants(const fs::path& run, int index) {
    const int k = resolve_snapshot_index(run, index);
    SnapshotPlants s;
    s.index = k;
    open_snapshot(run, k, [&](const H5::Group& g) {
        s.year = static_cast<int>(read_double_attr(g, "year"));
        H5::Group p = g.openGroup("plants");
        bool has_stem_diameter = true;
        for (const auto& c : plant_columns()) {
            if ((c.name == "life_form" || c.name == "stem_diameter_m") &&
                !H5Lexists(p.getId(), c.name.c_str(), H5P_DEFAULT)) {
                // Runs before life forms: every plant a tree, the stem diameter its DBH.
                has_stem_diameter = has_stem_diameter && c.name != "stem_diameter_m";
                continue;
            }
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
        if (!has_stem_diameter)
            for (auto& r : s.plants) r.stem_diameter_m = r.dbh_m;
        // What the engine writes is finite, sizes are not negative and life forms are known: a
        // file that says otherwise was damaged or edited, and is refused before it skews metrics.
        for (const auto& r : s.plants) {
            auto bad = [&](const std::string& column, double v, const std::string& why) {
                throw InputError(run.string() + ": snapshot " + std::to_string(k) + ": plant " +
                                 std::to_string(r.id) + ": " + column + " = " + format_number(v) +
                                 " " + why);
            };
            for (const auto& [column, v] : {std::pair{"x_m", r.x_m},
                                            {"y_m", r.y_m},
                                            {"z_m", r.z_m},
                                            {"carbohydrate_kg", r.carbohydrate_kg}})
                if (!std::isfinite(v)) bad(column, v, "is not a finite number");
            for (const auto& [column, v] : {std::pair{"height_m", r.height_m},
                                            {"dbh_m", r.dbh_m},
                                            {"stem_diameter_m", r.stem_diameter_m},
                                            {"crown_radius_m", r.crown_radius_m},
                                            {"age_yr", r.age_yr}})
                if (!(std::isfinite(v) && v >= 0)) bad(column, v, "is not a size (finite, >= 0)");
            if (r.life_form != 0 && r.life_form != 1 && r.life_form != 3)
                bad("life_form", r.life_form, "is not 0 (tree), 1 (shrub) or 3 (object)");
        }
    });
    return s;
}

SnapshotDeadWood read_snapshot_deadwood(const fs::path& run, int index) {
    const int k = resolve_snapshot_index(run, index);
    SnapshotDeadWood s;
    s.index = k;
    open_snapshot(run, k, [&](const H5::Group& g) {
        s.year = static_cast<int>(read_double_attr(g, "year"));
        if (!H5Lexists(g.getId(), "deadwood", H5P_DEFAULT)) return;
        const H5::Group p = g.openGroup("deadwood");
        for (const auto& c : deadwood_columns()) {
            auto read = [&]<class T>(const H5::PredType& type, T) {
                const auto v = read_vector<T>(p, c.name, type);
                if (&c == &deadwood_columns().front()) s.pieces.resize(v.size());
                if (v.size() != s.pieces.size())
                    throw InputError(run.string() + ": snapshot " + std::to_string(k) +
                                     ": deadwood/" + c.name + " has " + std::to_string(v.size()) +
                                     " rows, deadwood/id " + std::to_string(s.pieces.size()));
                for (std::size_t r = 0; r < v.size(); ++r) {
                    const double x = static_cast<double>(v[r]);
                    if (!std::isfinite(x))
                        throw InputError(run.string() + ": snapshot " + std::to_string(k) +
                                         ": deadwood/" + c.name + " row " + std::to_string(r) +
                                         " is not a finite number");
                    c.set(s.pieces[r], x);
                }
            };
            if (c.type == ColumnType::int64)
                read(H5::PredType::NATIVE_INT64, std::int64_t{});
            else if (c.type == ColumnType::int32)
                read(H5::PredType::NATIVE_INT32, std::int32_t{});
            else
                read(H5::PredType::NATIVE_DOUBLE, double{});
        }
        for (const auto& r : s.pieces)
            for (const auto& [column, v] : {std::pair{"dbh_m", r.dbh_m},
                                            {"length_m", r.length_m},
                                            {"height_m", r.height_m},
                                            {"mass_kg", r.mass_kg},
                                            {"volume_m3", r.volume_m3}})
                if (v < 0)
                    throw InputError(run.string() + ": snapshot " + std::to_string(k) +
                                     ": dead wood of plant " + std::to_string(r.id) + ": " +
                                     column + " = " + format_number(v) + " is negative");
    });
    return s;
}

UndergrowthMetrics read_snapshot_undergrowth(const fs::path& run, int index) {
    const RunInfo info = read_run_info(run);
    const SnapshotPlants s = read_snapshot_plants(run, index);
    UndergrowthCounter count;
    for (const auto& p : s.plants)
        count.add(static_cast<LifeForm>(p.life_form), p.crown_radius_m, p.height_m);
    UndergrowthMetrics u = count.metrics(info.area_m2);
    open_snapshot(run, s.index, [&](const H5::Group& g) {
        if (!g.nameExists("ground_cover_by_species")) return;
        H5::Group layer = g.openGroup("ground_cover_by_species");
        std::vector<int> species;
        for (hsize_t k = 0; k < layer.getNumObjs(); ++k) {
            const std::string name = layer.getObjnameByIdx(k);
            if (name.empty() || name.find_first_not_of("0123456789") != std::string::npos ||
                name.size() > 5)
                throw InputError(run.string() + ": snapshot " + std::to_string(s.index) +
                                 ": ground_cover_by_species/" + name +
                                 " is not named by a species index");
            species.push_back(std::stoi(name));
        }
        std::sort(species.begin(), species.end());
        for (const int sp : species) {
            H5::DataSet ds = layer.openDataSet(std::to_string(sp));
            std::vector<double> v(static_cast<std::size_t>(ds.getSpace().getSimpleExtentNpoints()));
            ds.read(v.data(), H5::PredType::NATIVE_DOUBLE);
            double sum = 0;
            for (const double x : v) sum += x;
            const double mean = v.empty() ? 0.0 : sum / static_cast<double>(v.size());
            u.ground_cover_by_species.push_back({sp, mean});
            u.ground_cover_fraction += mean;
        }
    });
    return u;
}

std::vector<mobility::StandStem> stand_stems(const std::vector<PlantRecord>& plants) {
    std::vector<mobility::StandStem> stems;
    stems.reserve(plants.size());
    for (const auto& p : plants) {
        mobility::StandStem s{p.x_m, p.y_m, p.dbh_m, p.height_m};
        if (p.life_form == static_cast<std::int32_t>(LifeForm::shrub)) {
            s.kind = mobility::StemKind::shrub;
            s.base_diameter_m = p.stem_diameter_m;
        } else if (p.life_form == static_cast<std::int32_t>(LifeForm::object)) {
            s.kind = mobility::StemKind::object;
            s.base_diameter_m = p.stem_diameter_m;
        }
        stems.push_back(s);
    }
    return stems;
}

mobility::StandDeadWood stand_deadwood(const std::vector<DeadWoodRecord>& pieces) {
    mobility::StandDeadWood out;
    for (const auto& p : pieces)
        out.add(p.piece, p.standing != 0, {p.x_m, p.y_m}, {p.end_x_m, p.end_y_m}, p.dbh_m,
                p.height_m, p.end_height_m);
    return out;
}

DrivingWorld read_driving_world(const fs::path& run, int index, bool deadwood, bool soil) {
    DrivingWorld w;
    w.dem = read_run_terrain(run);
    w.stems = stand_stems(read_snapshot_plants(run, index).plants);
    if (deadwood) w.dead = stand_deadwood(read_snapshot_deadwood(run, index).pieces);
    w.stems.insert(w.stems.end(), w.dead.snags.begin(), w.dead.snags.end());
    if (soil) w.ground = read_snapshot_ground(run, index, w.dem.grid());
    mobility::carve_pits(w.dem, w.dead.pits);
    return w;
}

} // namespace ecoterra::run
