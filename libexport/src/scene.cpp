#include "ecoterra/export/scene.hpp"
#include "ecoterra/export/mesh.hpp"

#include "ecoterra/eco/deadwood.hpp"
#include "ecoterra/eco/dispersal.hpp"
#include "ecoterra/error.hpp"
#include "ecoterra/random.hpp"
#include "ecoterra/run/run_reader.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

namespace ecoterra::exporter {

const char* stage_name(Stage s) {
    switch (s) {
    case Stage::young:
        return "young";
    case Stage::medium:
        return "medium";
    case Stage::adult:
        return "adult";
    }
    return "adult";
}

Stage stage_of(double height_m, double max_height_m) {
    if (height_m < max_height_m / 3) return Stage::young;
    if (height_m < 2 * max_height_m / 3) return Stage::medium;
    return Stage::adult;
}

namespace {
/// Comma-separated finite numbers; InputError naming `option` and the text otherwise.
std::vector<double> parse_numbers(const std::string& text, const std::string& option) {
    std::vector<double> v;
    std::stringstream in(text);
    std::string part;
    while (std::getline(in, part, ',')) {
        std::size_t used = 0;
        double d = 0;
        try {
            d = std::stod(part, &used);
        } catch (const std::exception&) {
            used = 0;
        }
        if (used == 0 || used != part.size() || !std::isfinite(d))
            throw InputError(option + " " + text + ": '" + part + "' is not a number");
        v.push_back(d);
    }
    return v;
}
} // namespace

std::array<double, 2> parse_origin(const std::string& text, const std::string& option) {
    const auto v = parse_numbers(text, option);
    if (v.size() != 2) throw InputError(option + " " + text + ": give two numbers X,Y (m)");
    return {v[0], v[1]};
}

nlohmann::json LocalFrame::to_json() const {
    return {{"origin_x_m", origin_x_m},
            {"origin_y_m", origin_y_m},
            {"crs_wkt", crs_wkt},
            {"meaning", "positions in this export are local, metres: x_run = x + origin_x_m, "
                        "y_run = y + origin_y_m (east, north; z unchanged) in the run's frame" +
                            std::string(crs_wkt.empty() ? " (local metres: the run's terrain had "
                                                          "no coordinate system)"
                                                        : ", whose coordinate system is crs_wkt")}};
}

Scene in_local_frame(const Scene& s, const std::optional<std::array<double, 2>>& origin) {
    Scene out = s;
    const double ox = origin ? (*origin)[0] : s.run_corner_x_m;
    const double oy = origin ? (*origin)[1] : s.run_corner_y_m;
    // Shift from the scene's present frame to the new one.
    const double dx = ox - s.frame.origin_x_m, dy = oy - s.frame.origin_y_m;
    GridSpec g = s.terrain.grid();
    g.origin_x_m -= dx;
    g.origin_y_m -= dy;
    out.terrain = RasterD(g, s.terrain.array());
    out.terrain.set_crs_wkt(s.terrain.crs_wkt());
    for (auto& t : out.trees) t.x_m -= dx, t.y_m -= dy;
    for (auto& t : out.tufts) t.x_m -= dx, t.y_m -= dy;
    for (auto& d : out.deadwood) d.x_m -= dx, d.y_m -= dy;
    if (out.region) {
        out.region->x0_m -= dx, out.region->x1_m -= dx;
        out.region->y0_m -= dy, out.region->y1_m -= dy;
    }
    out.frame.origin_x_m = ox;
    out.frame.origin_y_m = oy;
    out.frame.crs_wkt = s.terrain.crs_wkt();
    return out;
}

Region parse_region(const std::string& text, const std::string& option) {
    const auto v = parse_numbers(text, option);
    if (v.size() != 4)
        throw InputError(option + " " + text + ": give four numbers X0,Y0,X1,Y1 (m)");
    if (!(v[2] > v[0] && v[3] > v[1]))
        throw InputError(option + " " + text + ": X1 must exceed X0 and Y1 exceed Y0");
    return {v[0], v[1], v[2], v[3]};
}

double tree_yaw_rad(std::uint64_t seed, std::int64_t id) {
    Rng rng(seed, "export.yaw", static_cast<std::uint64_t>(id));
    return rng.uniform(0, 2 * std::numbers::pi);
}

std::array<int, 4> region_window(const GridSpec& g, const Region& r, const std::string& what) {
    const double x1 = g.origin_x_m + g.width_m(), y1 = g.origin_y_m + g.height_m();
    if (r.x1_m <= g.origin_x_m || r.y1_m <= g.origin_y_m || r.x0_m >= x1 || r.y0_m >= y1)
        throw InputError(what + " " + format_number(r.x0_m) + "," + format_number(r.y0_m) + "," +
                         format_number(r.x1_m) + "," + format_number(r.y1_m) +
                         " lies outside the terrain [" + format_number(g.origin_x_m) + ", " +
                         format_number(x1) + "] x [" + format_number(g.origin_y_m) + ", " +
                         format_number(y1) + "] m");
    auto cell = [&](double v, double origin, int n) {
        // Clamped as a double: a region far past the terrain (1e308) must not overflow the cast.
        return static_cast<int>(
            std::clamp(std::floor((v - origin) / g.cell_size_m), 0.0, static_cast<double>(n - 1)));
    };
    const int i0 = cell(r.x0_m, g.origin_x_m, g.nx), j0 = cell(r.y0_m, g.origin_y_m, g.ny);
    // The last cell that the region enters (a region ending on a cell edge stops before it).
    const int i1 = cell(std::nextafter(r.x1_m, r.x0_m), g.origin_x_m, g.nx);
    const int j1 = cell(std::nextafter(r.y1_m, r.y0_m), g.origin_y_m, g.ny);
    if (i1 - i0 < 1 || j1 - j0 < 1)
        throw InputError(what + ": the region covers fewer than 2 x 2 terrain cells of " +
                         format_number(g.cell_size_m) + " m");
    return {i0, j0, i1 - i0 + 1, j1 - j0 + 1};
}

namespace {

/// The tufts of the snapshot's ground layer inside the scene (see kTuftAreaM2).
void add_tufts(Scene& s, const RasterD& full, const std::vector<eco::Species>& species) {
    if (!run::snapshot_has_dataset(s.run, s.snapshot, "ground_cover")) return;
    const GridSpec& g = full.grid();
    const double cell = g.cell_size_m * g.cell_size_m;
    const double radius = std::sqrt(kTuftAreaM2 / std::numbers::pi);
    const int i0 = s.cut_i0, j0 = s.cut_j0;
    const int i1 = i0 + s.terrain.nx(), j1 = j0 + s.terrain.ny();
    for (std::size_t k = 0; k < species.size(); ++k) {
        if (species[k].life_form != eco::LifeForm::grass) continue;
        const RasterD cover = run::read_snapshot_raster(
            s.run, s.snapshot, "ground_cover_by_species/" + std::to_string(k), g);
        for (int j = j0; j < j1; ++j)
            for (int i = i0; i < i1; ++i) {
                const double a = cover(i, j);
                if (!(a > 0)) continue;
                const auto index =
                    (static_cast<std::uint64_t>(j) * static_cast<std::uint64_t>(g.nx) +
                     static_cast<std::uint64_t>(i)) *
                        species.size() +
                    k;
                Rng rng(s.seed, "export.grass", index);
                const std::int64_t n = eco::poisson(rng, a * cell / kTuftAreaM2);
                for (std::int64_t q = 0; q < n; ++q) {
                    Tuft t;
                    t.species = static_cast<int>(k);
                    t.x_m = g.x_of(i) + (rng.uniform() - 0.5) * g.cell_size_m;
                    t.y_m = g.y_of(j) + (rng.uniform() - 0.5) * g.cell_size_m;
                    t.yaw_rad = rng.uniform(0, 2 * std::numbers::pi);
                    if (s.region && (t.x_m < s.region->x0_m || t.x_m >= s.region->x1_m ||
                                     t.y_m < s.region->y0_m || t.y_m >= s.region->y1_m))
                        continue;
                    t.z_m = full.sample_bilinear(t.x_m, t.y_m);
                    if (std::isnan(t.z_m)) t.z_m = full(i, j);
                    t.height_m = species[k].max_height_m;
                    t.radius_m = radius;
                    s.tufts.push_back(t);
                }
            }
    }
}

} // namespace

namespace {
/// The snapshot's dead wood whose base lies on the scene's terrain (and region).
void add_deadwood(Scene& s, const RasterD& full) {
    for (const auto& r : run::read_snapshot_deadwood(s.run, s.snapshot).pieces) {
        if (s.region && (r.x_m < s.region->x0_m || r.x_m >= s.region->x1_m ||
                         r.y_m < s.region->y0_m || r.y_m >= s.region->y1_m))
            continue;
        DeadPiece d;
        d.z_m = full.sample_bilinear(r.x_m, r.y_m);
        if (std::isnan(d.z_m)) continue; // slash whose thick end lies past the edge
        d.id = r.id;
        d.species = r.species;
        d.piece = r.piece;
        d.standing = r.standing != 0;
        d.decay_class = r.decay_class;
        d.x_m = r.x_m;
        d.y_m = r.y_m;
        d.azimuth_rad = r.azimuth_rad;
        d.length_m = r.length_m;
        d.top_height_m = r.height_m;
        // A lying piece's top is its diameter sunk by its class; a standing one keeps its DBH.
        d.diameter_m =
            d.standing ? r.dbh_m : r.height_m / eco::deadwood::log_collapse(r.decay_class);
        s.deadwood.push_back(d);
    }
}
} // namespace

const char* dead_piece_name(int piece) {
    constexpr const char* kKinds[] = {"stem", "stump", "top", "snapped", "root_plate"};
    return kKinds[std::clamp(piece, 0, 4)];
}

std::string tuft_mesh_name(const Scene& s, int k) {
    return file_safe(s.species[static_cast<std::size_t>(k)].name) + "_grass";
}

std::vector<std::pair<int, std::vector<std::size_t>>> tuft_groups(const Scene& s) {
    std::vector<std::pair<int, std::vector<std::size_t>>> out;
    for (std::size_t i = 0; i < s.tufts.size(); ++i) { // ordered by species
        if (out.empty() || out.back().first != s.tufts[i].species)
            out.emplace_back(s.tufts[i].species, std::vector<std::size_t>{});
        out.back().second.push_back(i);
    }
    return out;
}

Scene load_scene(const std::filesystem::path& run, int snapshot,
                 const std::optional<Region>& region) {
    Scene s;
    s.run = run;
    s.source = run.string();
    const auto info = run::read_run_info(run);
    const auto plants = run::read_snapshot_plants(run, snapshot);
    s.snapshot = plants.index;
    s.year = plants.year;
    if (info.provenance.contains("seed") && info.provenance["seed"].is_number_unsigned())
        s.seed = info.provenance["seed"].get<std::uint64_t>();
    const auto species = run::read_run_species(run);
    for (const auto& sp : species)
        s.species.push_back(
            {sp.name, sp.crown_shape, sp.max_height_m, sp.evergreen, sp.leaf_area_per_crown_area});
    const RasterD full = run::read_run_terrain(run);
    s.run_corner_x_m = full.grid().origin_x_m;
    s.run_corner_y_m = full.grid().origin_y_m;
    s.frame.crs_wkt = full.crs_wkt();
    s.region = region;
    if (region) {
        const auto w = region_window(full.grid(), *region, run.string() + ": --region");
        s.cut_i0 = w[0];
        s.cut_j0 = w[1];
        s.terrain = full.crop(w[0], w[1], w[2], w[3]);
    } else {
        s.terrain = full;
    }
    for (const auto& p : plants.plants) {
        if (region && (p.x_m < region->x0_m || p.x_m >= region->x1_m || p.y_m < region->y0_m ||
                       p.y_m >= region->y1_m))
            continue;
        if (p.species < 0 || static_cast<std::size_t>(p.species) >= s.species.size())
            throw InputError(run.string() + ": snapshot " + std::to_string(s.snapshot) +
                             ": plant " + std::to_string(p.id) + " has species " +
                             std::to_string(p.species) + ", the run has " +
                             std::to_string(s.species.size()));
        Tree t;
        t.id = p.id;
        t.species = p.species;
        t.x_m = p.x_m;
        t.y_m = p.y_m;
        t.z_m = full.sample_bilinear(p.x_m, p.y_m);
        if (std::isnan(t.z_m))
            throw InputError(run.string() + ": plant " + std::to_string(p.id) + " at (" +
                             format_number(p.x_m) + ", " + format_number(p.y_m) +
                             ") stands outside the terrain");
        t.height_m = p.height_m;
        t.dbh_m = p.dbh_m;
        t.crown_radius_m = p.crown_radius_m;
        t.life_form = static_cast<eco::LifeForm>(p.life_form);
        if (t.life_form != eco::LifeForm::tree) t.base_diameter_m = p.stem_diameter_m;
        if (t.life_form == eco::LifeForm::object) t.crown_radius_m = 0; // a column, no crown
        t.stage = stage_of(p.height_m, s.species[static_cast<std::size_t>(p.species)].max_height_m);
        t.yaw_rad = tree_yaw_rad(s.seed, p.id);
        s.trees.push_back(t);
    }
    std::sort(s.trees.begin(), s.trees.end(),
              [](const Tree& a, const Tree& b) { return a.id < b.id; });
    add_tufts(s, full, species);
    add_deadwood(s, full);
    return s;
}

} // namespace ecoterra::exporter
