#include "ecoterra/hydro/scene.hpp"

#include "ecoterra/hydro/pictures.hpp"

#include "ecoterra/io/hdf5_writer.hpp"
#include "ecoterra/json_util.hpp"
#include "ecoterra/terrain/generate.hpp"
#include "ecoterra/terrain/io/dem_window.hpp"
#include "ecoterra/terrain/io/raster_io.hpp"
#include "ecoterra/terrain/picture.hpp"

#include <chrono>
#include <cstdio>

namespace ecoterra::hydro {

namespace {

using nlohmann::json;
namespace fs = std::filesystem;

fs::path resolve(const fs::path& base, const std::string& p) {
    const fs::path q(p);
    return q.is_absolute() ? q : base / q;
}

/// How a raster's grid differs from the terrain's, and the gdalwarp command that puts it there.
std::string grid_mismatch(const GridSpec& x, const GridSpec& g) {
    char b[640];
    std::snprintf(b, sizeof b,
                  "is %d x %d cells of %.10g m from (%.10g, %.10g); the terrain is %d x %d cells "
                  "of %.10g m from (%.10g, %.10g). Put it on the terrain's grid, e.g. gdalwarp "
                  "-te %.10g %.10g %.10g %.10g -ts %d %d -r bilinear IN.tif OUT.tif",
                  x.nx, x.ny, x.cell_size_m, x.origin_x_m, x.origin_y_m, g.nx, g.ny, g.cell_size_m,
                  g.origin_x_m, g.origin_y_m, g.origin_x_m, g.origin_y_m,
                  g.origin_x_m + g.width_m(), g.origin_y_m + g.height_m(), g.nx, g.ny);
    return b;
}

/// `n` finite numbers from `v`, or an InputError naming `key` and what was given.
template <std::size_t N>
std::array<double, N> numbers(const json& v, const std::string& key, const char* form) {
    std::array<double, N> a{};
    if (!v.is_array() || v.size() != N) throw InputError(key + " = " + v.dump() + ": give " + form);
    for (std::size_t k = 0; k < N; ++k) {
        if (!v[k].is_number()) throw InputError(key + " = " + v.dump() + ": give " + form);
        a[k] = v[k].get<double>();
    }
    return a;
}

terrain::io::DemWindow read_window(const json& w) {
    terrain::io::DemWindow win;
    if (!w.is_object()) throw InputError("terrain.window = " + w.dump() + ": give an object");
    require_known_keys(w, {"bounds", "pixels", "centre", "size_m"}, "terrain.window");
    if (w.contains("bounds"))
        win.bounds = numbers<4>(w["bounds"], "terrain.window.bounds",
                                "[x_min, y_min, x_max, y_max] in the DEM's coordinate system");
    if (w.contains("pixels"))
        win.pixels = numbers<4>(w["pixels"], "terrain.window.pixels",
                                "[column, row, columns, rows] of the DEM's pixels");
    if (w.contains("centre")) {
        win.centre = numbers<2>(w["centre"], "terrain.window.centre",
                                "[x, y] in the DEM's coordinate system");
        if (!w.contains("size_m"))
            throw InputError("terrain.window: a centre needs size_m (metres, one number or "
                             "[width, height])");
        const json& z = w["size_m"];
        win.size_m = z.is_number() ? std::array<double, 2>{z.get<double>(), z.get<double>()}
                                   : numbers<2>(z, "terrain.window.size_m",
                                                "one number or [width, height] in metres");
    } else if (w.contains("size_m")) {
        throw InputError("terrain.window.size_m: only with a centre");
    }
    if (w.size() == 0)
        throw InputError("terrain.window: give 'bounds', 'pixels' or 'centre' with 'size_m'");
    return win;
}

RasterD load_terrain(const json& t, const fs::path& base, json& resolved, json& record,
                     std::vector<std::string>& notes) {
    require_known_keys(t, {"generate", "file", "window", "cell_m", "resampling", "crs"}, "terrain");
    if (t.contains("generate") == t.contains("file"))
        throw InputError("terrain: give exactly one of 'generate' (a terrain specification) or "
                         "'file' (a raster)");
    if (t.contains("file")) {
        terrain::io::DemRequest req;
        req.path = resolve(base, get_string(t, "file", "", "terrain"));
        if (t.contains("window")) req.window = read_window(t["window"]);
        req.cell_m = get_number(t, "cell_m", 0.0, "terrain");
        req.resampling = get_string(t, "resampling", "auto", "terrain");
        req.crs = get_string(t, "crs", "", "terrain");
        resolved["terrain"] = {{"file", req.path.string()}};
        if (!terrain::io::dem_request_resamples(req) && !t.contains("resampling")) {
            record = {{"file", req.path.string()}, {"method", "read as it is"}};
            return terrain::io::read_raster(req.path, &notes);
        }
        terrain::io::DemRead d = terrain::io::read_dem(req, &notes);
        json& r = resolved["terrain"];
        if (t.contains("window")) r["window"] = t["window"];
        r["cell_m"] = d.z.cell_size();
        r["resampling"] = d.resampling;
        if (!d.crs.empty()) r["crs"] = d.crs;
        record = std::move(d.record);
        return std::move(d.z);
    }
    for (const char* k : {"window", "cell_m", "resampling", "crs"})
        if (t.contains(k))
            throw InputError(std::string("terrain.") + k + ": only with 'file' (a DEM to read)");
    auto g = terrain::generate_terrain(t.at("generate"));
    resolved["terrain"] = {{"generate", g.resolved}};
    return std::move(g.z);
}

/// A raster on the terrain's grid: read as it is when it lies on it (to 1e-6), otherwise put on
/// it by GDAL's warper (bilinear, from its own system to the terrain's), with a note. An
/// InputError names `key` and the file where it does not cover the terrain.
RasterD read_onto_terrain(const fs::path& path, const RasterD& dem, const std::string& key,
                          std::vector<std::string>& notes) {
    RasterD x = terrain::io::read_raster(path);
    const GridSpec& g = dem.grid();
    if (x.grid().matches(g)) return x;
    terrain::io::DemRequest req;
    req.path = path;
    req.key = key;
    req.onto = g;
    req.onto_crs_wkt = dem.crs_wkt();
    req.resampling = "bilinear";
    terrain::io::DemRead d = terrain::io::read_dem(req);
    std::int64_t uncovered = 0;
    for (std::int64_t k = 0; k < g.size(); ++k)
        uncovered += std::isnan(d.z.data()[k]) && !std::isnan(dem.data()[k]) ? 1 : 0;
    if (uncovered > 0)
        throw InputError(key + ": " + path.string() + " " + grid_mismatch(x.grid(), g) +
                         "; put "
                         "on it, it leaves " +
                         std::to_string(uncovered) + " terrain cells without a value");
    char b[200];
    std::snprintf(b, sizeof b,
                  " (%d x %d cells of %.6g) resampled bilinearly onto the terrain's "
                  "grid by GDAL's warper",
                  x.nx(), x.ny(), x.cell_size());
    notes.push_back(key + ": " + path.string() + b);
    return std::move(d.z);
}

SoilMap load_soil(const json& s, const fs::path& base, const RasterD& dem, std::uint64_t seed,
                  SoilSpec& spec, json& resolved, std::vector<std::string>& notes) {
    const GridSpec& g = dem.grid();
    require_known_keys(s, {"uniform", "random", "rasters"}, "soil");
    if (s.size() != 1) throw InputError("soil: give exactly one of 'uniform', 'random', 'rasters'");
    spec.kind = s.begin().key();
    if (spec.kind == "uniform") {
        spec.uniform = soil_composition_catalog().read(s["uniform"], SoilComposition{});
        spec.uniform.validate("soil.uniform");
        resolved["soil"] = {{"uniform", soil_composition_catalog().to_json(spec.uniform)}};
        return uniform_soil(g, spec.uniform);
    }
    if (spec.kind == "random") {
        spec.random = random_soil_catalog().read(s["random"], RandomSoilParams{});
        spec.random.mean.validate("soil.random");
        resolved["soil"] = {{"random", random_soil_catalog().to_json(spec.random)}};
        return random_soil(g, spec.random, seed);
    }
    SoilRasterFiles& files = spec.rasters;
    files = soil_rasters_catalog().read(s["rasters"], SoilRasterFiles{});
    auto read = [&](std::string& file, const char* key) {
        const fs::path path = resolve(base, file);
        file = path.string(); // resolved: a resume finds the same file
        return read_onto_terrain(path, dem, "soil.rasters." + std::string(key), notes);
    };
    const auto sand = read(files.sand_pct, "sand_pct"), silt = read(files.silt_pct, "silt_pct"),
               clay = read(files.clay_pct, "clay_pct");
    std::optional<RasterD> ph;
    if (!files.ph.empty()) ph = read(files.ph, "ph");
    resolved["soil"] = {{"rasters", soil_rasters_catalog().to_json(files)}};
    return soil_from_rasters(sand, silt, clay, ph ? &*ph : nullptr, "soil.rasters");
}

RasterD load_vegetation_cover(const json& v, const fs::path& base, const RasterD& dem,
                              VegetationCover& cover, json& resolved,
                              std::vector<std::string>& notes) {
    const GridSpec& g = dem.grid();
    cover = vegetation_cover_catalog().read(v, VegetationCover{});
    if (v.contains("density") && v.contains("density_file"))
        throw InputError("vegetation: give 'density' or 'density_file', not both");
    resolved["vegetation"] = json::object();
    if (cover.density_file.empty()) {
        resolved["vegetation"]["density"] = cover.density;
        return RasterD(g, cover.density);
    }
    const auto path = resolve(base, cover.density_file);
    cover.density_file = path.string();
    RasterD d = read_onto_terrain(path, dem, "vegetation.density_file", notes);
    resolved["vegetation"]["density_file"] = cover.density_file;
    return d;
}

Climate load_climate(const json& c, const fs::path& base, HydroScene& scene, json& resolved) {
    const std::string preset = get_string(c, "preset", "humid_subtropical", "climate");
    Climate cl = climate_catalog().read(c, climate_preset(preset), {"preset", "csv"});
    cl.validate();
    resolved["climate"] = climate_catalog().to_json(cl);
    resolved["climate"]["preset"] = cl.name;
    if (c.contains("csv")) {
        const auto path = resolve(base, get_string(c, "csv", "", "climate"));
        resolved["climate"]["csv"] = path.string();
        scene.observed = read_weather_csv(path, cl.latitude_deg, cl.elevation_m);
    }
    return cl;
}

HydrologyOptions load_options(const json& h, json& resolved) {
    HydrologyOptions o = hydrology_catalog().read(h, HydrologyOptions{});
    o.validate();
    resolved["hydrology"] = hydrology_catalog().to_json(o);
    return o;
}

} // namespace

const ParamCatalog<SoilRasterFiles>& soil_rasters_catalog() {
    using F = SoilRasterFiles;
    static const ParamCatalog<F> c(
        "soil.rasters",
        {text<F>("sand_pct", &F::sand_pct,
                 "raster of sand, % (put on the terrain grid if on another)")
             .mandatory(),
         text<F>("silt_pct", &F::silt_pct,
                 "raster of silt, % (put on the terrain grid if on another)")
             .mandatory(),
         text<F>("clay_pct", &F::clay_pct,
                 "raster of clay, % (put on the terrain grid if on another)")
             .mandatory(),
         text<F>(
             "ph", &F::ph,
             "raster of soil pH (put on the terrain grid if on another); empty: uniform pH 6.5")});
    return c;
}

const ParamCatalog<VegetationCover>& vegetation_cover_catalog() {
    using V = VegetationCover;
    static const ParamCatalog<V> c(
        "vegetation",
        {number<V>("density", &V::density, "1", 0, 1,
                   "uniform vegetation density for the rain partition (hydro run only)"),
         text<V>("density_file", &V::density_file,
                 "raster of densities 0..1 (put on the terrain's grid if on another) instead of "
                 "`density`")});
    return c;
}

const ParamCatalog<HydroScene>& hydro_simulation_catalog() {
    using H = HydroScene;
    static const ParamCatalog<H> c(
        "simulation",
        {integer<H>("years", &H::years, "yr", 1, 10000,
                    "simulated years (hydro run with observed weather: the series' length; "
                    "ecosystem runs replay it)"),
         integer<H>("seed", &H::seed, "1", 0, 4.611686018427388e18,
                    "seed of every random stream of the run"),
         integer<H>("snapshot_interval_days", &H::snapshot_interval_days, "day", 1, 3650000,
                    "days between snapshots; the last day always gets one")});
    return c;
}

MemoryEstimate memory_estimate(const HydroScene& scene) {
    MemoryEstimate m;
    m.fixed_bytes = kFixedBytes;
    const double cells = static_cast<double>(scene.dem.size());
    m.terms.push_back({"terrain cells", cells, kBytesPerTerrainCell});
    if (scene.options.groundwater) {
        const double f = scene.options.aquifer_cell_factor;
        m.terms.push_back({"groundwater cells", cells / (f * f), kBytesPerGroundwaterCell});
        // The terrain cells' surface, seepage and seepage flag under a coarser aquifer.
        if (f > 1) m.terms.push_back({"terrain cells over the aquifer", cells, 17});
    }
    return m;
}

HydroScene load_hydro_scene(const json& s, const fs::path& base) {
    require_known_keys(s, {"terrain", "soil", "vegetation", "climate", "hydrology", "simulation"},
                       "");
    HydroScene scene;
    json& r = scene.resolved;
    scene = hydro_simulation_catalog().read(s.value("simulation", json::object()), scene);
    r["simulation"] = hydro_simulation_catalog().to_json(scene);
    if (!s.contains("terrain")) throw InputError("scene: missing key 'terrain'");
    scene.dem = load_terrain(s["terrain"], base, r, scene.terrain_source, scene.notes);
    require_valid_cells(scene.dem, "terrain");
    scene.soil = load_soil(s.value("soil", json{{"uniform", json::object()}}), base, scene.dem,
                           scene.seed, scene.soil_spec, r, scene.notes);
    scene.vegetation_density = load_vegetation_cover(s.value("vegetation", json::object()), base,
                                                     scene.dem, scene.cover, r, scene.notes);
    scene.climate = load_climate(s.value("climate", json::object()), base, scene, r);
    scene.options = load_options(s.value("hydrology", json::object()), r);
    return scene;
}

const std::vector<RasterLayer<SoilMap>>& soil_map_layers() {
    using S = SoilMap;
    static const std::vector<RasterLayer<S>> l{
        raster_layer<S>(
            "sand_pct", "%", "float32", "sand",
            [](const S& s) -> const auto& { return s.sand_pct; }),
        raster_layer<S>(
            "silt_pct", "%", "float32", "silt",
            [](const S& s) -> const auto& { return s.silt_pct; }),
        raster_layer<S>(
            "clay_pct", "%", "float32", "clay",
            [](const S& s) -> const auto& { return s.clay_pct; }),
        raster_layer<S>(
            "ph", "1", "float32", "soil pH", [](const S& s) -> const auto& { return s.ph; }),
        raster_layer<S>(
            "texture_class", "1", "uint8",
            "USDA texture class: 0 sand, 1 loamy sand, 2 sandy loam, 3 loam, 4 silt loam, 5 silt, "
            "6 sandy clay loam, 7 clay loam, 8 silty clay loam, 9 sandy clay, 10 silty clay, 11 "
            "clay",
            [](const S& s) -> const auto& { return s.texture; }),
        raster_layer<S>(
            "porosity", "m3/m3", "float32", "porosity",
            [](const S& s) -> const auto& { return s.porosity; }),
        raster_layer<S>(
            "field_capacity", "m3/m3", "float32", "field capacity (33 kPa)",
            [](const S& s) -> const auto& { return s.field_capacity; }),
        raster_layer<S>(
            "wilting_point", "m3/m3", "float32", "wilting point (1500 kPa)",
            [](const S& s) -> const auto& { return s.wilting_point; }),
        raster_layer<S>(
            "ksat_m_per_s", "m/s", "float32", "saturated hydraulic conductivity",
            [](const S& s) -> const auto& { return s.ksat_m_per_s; })};
    return l;
}

const std::vector<RasterLayer<HydrologyModel>>& water_state_layers() {
    using H = HydrologyModel;
    static const std::vector<RasterLayer<H>> l{
        raster_layer<H>("soil_moisture", "m3/m3", "float32",
                        "volumetric soil water in the root zone",
                        [](const H& h) -> const RasterD& { return h.soil_moisture(); }),
        raster_layer<H>("critical_layer_moisture", "m3/m3", "float32",
                        "volumetric soil water in the critical layer, the top "
                        "hydrology.critical_layer_depth_m of the root zone (what vehicles bear "
                        "on)",
                        [](const H& h) -> const RasterD& { return h.critical_layer_moisture(); }),
        raster_layer<H>("surface_water_depth_m", "m", "float32", "standing water depth",
                        [](const H& h) { return h.surface_water_depth(); }),
        raster_layer<H>("catchment_id", "1", "int32", "catchment holding the cell, 0 = dry",
                        [](const H& h) { return h.catchment_ids(); }),
        raster_layer<H>("water_table_depth_m", "m", "float32",
                        "depth of the water table below the surface (NaN without groundwater)",
                        [](const H& h) { return h.water_table_depth(); })};
    return l;
}

void write_soil_maps(io::Hdf5Writer& h5, const SoilMap& soil) {
    write_layers(h5, "/soil", soil_map_layers(), soil);
}

void write_table(io::Hdf5Writer& h5, const std::string& group, const Table& t) {
    for (std::size_t k = 0; k < t.names.size(); ++k) {
        const std::string path = group + "/" + t.names[k];
        const ColumnType type = k < t.types.size() ? t.types[k] : ColumnType::float64;
        if (type == ColumnType::int64 || type == ColumnType::int32) {
            std::vector<std::int64_t> v;
            v.reserve(t.columns[k].size());
            for (const double x : t.columns[k]) v.push_back(std::llround(x));
            h5.series(path, v, t.units[k], t.descriptions[k]);
        } else {
            h5.series(path, t.columns[k], t.units[k], t.descriptions[k]);
        }
    }
}

HydroRunSummary run_hydro_scene(const HydroScene& sc, const fs::path& output, const json& prov,
                                const fs::path& png_dir,
                                const std::function<void(const HydroProgress&)>& progress) {
    const auto t0 = std::chrono::steady_clock::now();
    io::Hdf5Writer h5(output); // fails now, not after the run, if the folder is missing
    check_memory(memory_estimate(sc), "the scene (" + std::to_string(sc.dem.nx()) + " x " +
                                          std::to_string(sc.dem.ny()) + " cells)");
    HydrologyModel model(sc.dem, sc.soil, sc.vegetation_density, sc.options, sc.climate);
    WeatherGenerator gen(sc.climate, sc.seed);
    const int total =
        sc.observed ? static_cast<int>(sc.observed->days.size()) : kDaysPerYear * sc.years;
    const double domain_m2 = sc.dem.grid().width_m() * sc.dem.grid().height_m();
    Table series = Table::of(daily_budget_columns());
    HydroRunSummary sum;
    int snapshot = 0;
    int model_last_year = 0, model_last_doy = 0; // the last day's calendar, for the pictures
    auto write_snapshot = [&](const DayWeather& w, int day) {
        char name[32];
        std::snprintf(name, sizeof name, "/snapshots/%04d", snapshot++);
        const std::string base = name;
        write_layers(h5, base, water_state_layers(), model);
        h5.integer_attribute(base, "day", day);
        h5.integer_attribute(base, "year", w.year);
        h5.integer_attribute(base, "day_of_year", w.doy);
    };
    for (int d = 1; d <= total; ++d) {
        const DayWeather w =
            sc.observed ? sc.observed->days[static_cast<std::size_t>(d - 1)] : gen.next();
        const DailyFluxes f = model.step(w);
        model_last_year = w.year;
        model_last_doy = w.doy;
        const BudgetRow row = daily_budget_row(d, w, f, domain_m2);
        series.push(row, daily_budget_columns());
        sum.rain_mm += row.rain_mm;
        sum.evaporation_mm += row.evaporation_mm;
        sum.transpiration_mm += row.transpiration_mm;
        sum.interception_mm += row.interception_mm;
        sum.runoff_out_mm += row.runoff_out_mm;
        sum.drainage_out_mm += row.drainage_out_mm;
        sum.groundwater_out_mm += row.groundwater_out_mm;
        if (d % sc.snapshot_interval_days == 0 || d == total) write_snapshot(w, d);
        if (progress && (d % 30 == 0 || d == total))
            progress(
                {d, total, w.year, w.doy,
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()});
    }
    sum.days = total;
    sum.residual_relative = std::abs(model.cumulative_residual_m3()) /
                            std::max(model.cumulative_throughput_m3(), 1e-300);
    // Maps and series.
    h5.raster(terrain::io::kRunTerrainDataset, sc.dem, "m", "terrain elevation");
    h5.attribute(terrain::io::kRunTerrainDataset, "source_json", sc.terrain_source.dump());
    write_soil_maps(h5, sc.soil);
    h5.raster("/vegetation/density", sc.vegetation_density, "1", "vegetation density (fraction)");
    write_table(h5, "/series/daily", series);
    h5.attribute("/series/daily", "cumulative_residual_relative", sum.residual_relative);
    json p = prov;
    p["scene"] = sc.resolved;
    h5.attribute("/provenance", "json", p.dump());
    h5.commit();
    if (!png_dir.empty()) {
        io::create_folder(png_dir, "the picture folder");
        terrain::MapFigure f;
        f.title = "Hillshade of the terrain";
        f.colour_bar = false;
        f.notes = {"light from the north-west (azimuth 315 deg, altitude 45 deg)"};
        terrain::write_map_figure(terrain::hillshade_image(sc.dem), sc.dem.grid(), f,
                                  png_dir / "hillshade.png");
        write_water_pictures(sc.dem, sc.soil, model.soil_moisture(), model.surface_water_depth(),
                             "end of simulation day " + std::to_string(total) + " (year " +
                                 std::to_string(model_last_year) + ", day of year " +
                                 std::to_string(model_last_doy) + ")",
                             png_dir);
    }
    sum.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return sum;
}

namespace {
/// The soil-water processes of the scene's options (paper 002's, or the defaults of issue 27).
void soil_water_methods(const HydrologyOptions& opt, Methods& m) {
    if (opt.evapotranspiration == EvapotranspirationMethod::fao56) {
        m.push_back({"open-water evaporation", "Penman (1948) Proc. R. Soc. A 193:120; "
                                               "Shuttleworth (1993) Handbook of Hydrology ch. 4"});
        m.push_back({"soil evaporation and transpiration",
                     "FAO-56 dual crop coefficients, two-stage soil evaporation (REW, TEW, Kr) "
                     "and water stress Ks: Allen, Pereira, Raes & Smith (1998) FAO Irrigation and "
                     "Drainage Paper 56, ch. 7-8"});
    } else {
        m.push_back({"open-water and surface evaporation",
                     "Penman (1948) Proc. R. Soc. A 193:120; Shuttleworth (1993) Handbook of "
                     "Hydrology ch. 4 (paper 002: the larger of the surface's demand and the "
                     "plants' request)"});
    }
    if (opt.drainage == DrainageMethod::gravity)
        m.push_back({"drainage below the root zone",
                     "unit-gradient drainage at K(theta) = Ks (theta/theta_s)^(3 + 2/lambda): "
                     "Saxton & Rawls (2006) SSSAJ 70:1569, eq. 16"});
    if (opt.interception == InterceptionMethod::gash)
        m.push_back({"canopy interception",
                     "Gash (1979) Q. J. R. Meteorol. Soc. 105:43, sparse form of Gash, Lloyd & "
                     "Lachaud (1995) J. Hydrol. 170:79"});
}

} // namespace

Methods scene_methods(const HydroScene& sc) {
    Methods m;
    const nlohmann::json& t = sc.resolved.value("terrain", nlohmann::json::object());
    const std::string gen =
        t.contains("generate") ? t["generate"].value("method", std::string()) : std::string();
    if (gen == "multifractal")
        m.push_back({"terrain",
                     "multifractal 3D Weierstrass-Mandelbrot terrain: Majhor & Bos, ASME "
                     "J. Autonomous Vehicles and Systems 5(2) 021003 (paper 000)"});
    else if (gen == "wm")
        m.push_back({"terrain", "3D Weierstrass-Mandelbrot function: Ausloos & Berman (1985) Proc. "
                                "R. Soc. Lond. A 400:331"});
    else if (gen == "fbm")
        m.push_back({"terrain", "spectral synthesis of fractional Brownian surfaces: Saupe (1988), "
                                "The Science of Fractal Images ch. 2"});
    else if (gen == "perlin" || gen == "gaussian" || gen == "variable")
        m.push_back({"terrain", "MAVS rough surfaces (" + gen +
                                    "): Terrain roughness in MAVS "
                                    "(paper 003); Perlin (2002) ACM Trans. Graph. 21:681"});
    if (sc.soil_spec.uniform.organic_matter_pct || sc.soil_spec.random.mean.organic_matter_pct)
        m.push_back({"soil water properties", "Saxton & Rawls (2006) SSSAJ 70:1569"});
    else
        m.push_back(
            {"soil water properties",
             "Rawls, Brakensiek & Saxton (1982) Trans. ASAE 25:1316, by USDA texture class"});
    if (sc.observed)
        m.push_back({"weather", "an observed daily series (replayed by calendar year)"});
    else
        m.push_back({"weather",
                     "WGEN daily weather generator: Richardson (1981) Water Resour. Res. "
                     "17:182; Richardson & Wright (1984)"});
    m.push_back({"reference evapotranspiration",
                 "FAO-56 Penman-Monteith: Allen, Pereira, Raes & Smith (1998) FAO Irrigation and "
                 "Drainage Paper 56"});
    soil_water_methods(sc.options, m);
    if (sc.options.runoff == RunoffMethod::curve_number)
        m.push_back({"runoff", "SCS curve number: USDA-SCS (1986) TR-55"});
    else
        m.push_back({"runoff", "rational-method coefficients by cover, slope and soil: Schwab, "
                               "Frevert, Edminster & Barnes, Soil and Water Conservation "
                               "Engineering (data/hydro/runoff_coefficients.json)"});
    if (sc.options.routing == Routing::mfd)
        m.push_back({"routing", "multiple flow directions: Freeman (1991) Comput. Geosci. 17:413; "
                                "Quinn et al. (1991) Hydrol. Process. 5:59"});
    else
        m.push_back({"routing", "D8: O'Callaghan & Mark (1984) CVGIP 28:323"});
    m.push_back({"standing water (fill, spill, merge)",
                 "the depression hierarchy of Barnes, Callaghan & Wickert (2020) ESurf 8:431"});
    if (sc.options.groundwater)
        m.push_back(
            {"groundwater",
             sc.options.groundwater_solver == GroundwaterSolver::cvode
                 ? "Dupuit-Boussinesq flow (Bear 1972) solved by CVODE: Hindmarsh et al. (2005) "
                   "ACM TOMS 31:363"
                 : "Dupuit-Boussinesq flow (Bear 1972), TR-BDF2 steps (Bank et al. 1985, IEEE "
                   "Trans. CAD 4:436) solved by conjugate gradients (Saad 2003, Iterative Methods "
                   "for Sparse Linear Systems, 2nd ed., SIAM) "
                   "preconditioned by an aggregation multigrid V-cycle (Braess 1995, Computing "
                   "55:379; Notay 2010, ETNA 37:123)"});
    return m;
}

} // namespace ecoterra::hydro
