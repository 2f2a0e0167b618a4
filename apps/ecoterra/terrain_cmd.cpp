// `ecoterra terrain ...`: generate, analyze, missions, convert.
#include "common.hpp"
#include "subcommands.hpp"

#include "ecoterra/analyses/analyses.hpp"
#include "ecoterra/io/atomic_file.hpp"
#include "ecoterra/json_util.hpp"
#include "ecoterra/progress.hpp"
#include "ecoterra/terrain/analysis.hpp"
#include "ecoterra/terrain/generate.hpp"
#include "ecoterra/terrain/io/dem_window.hpp"
#include "ecoterra/terrain/io/raster_io.hpp"
#include "ecoterra/terrain/missions.hpp"

#include <cstdio>
#include <map>
#include <memory>
#include <optional>

namespace ecoterra::app {

namespace {

using nlohmann::json;
using namespace ecoterra::terrain;

/// A numeric method parameter given as a flag, and the key it sets.
struct ParamFlag {
    const char* flag;
    const char* key;
    const char* help;
    std::optional<double> value;
};

struct GenerateArgs {
    std::string preset, method, config, output, format;
    std::optional<long long> size, nx, ny, seed;
    std::optional<double> cell, origin_x, origin_y;
    bool mavs_compat = false, force = false;
    std::vector<ParamFlag> params = {
        {"--D", "D", "fractal dimension D in (2, 3) (wm, fbm)", {}},
        {"--M", "M", "number of W-M ridges (wm)", {}},
        {"--G", "G_m", "W-M elevation scaling coefficient G, m (wm)", {}},
        {"--gamma", "gamma", "W-M frequency density gamma > 1 (wm)", {}},
        {"--L", "L_m", "W-M sampling length L, m (wm)", {}},
        {"--n-max", "n_max", "W-M highest frequency index (wm; default: Nyquist cutoff)", {}},
        {"--phase-max",
         "phase_max_rad",
         "W-M phases uniform in [0, this], rad (wm; default pi)",
         {}},
        {"--d-high",
         "d_high",
         "D of the high-frequency layer (multifractal; paper: 2.3, 2.45, 2.6)",
         {}},
        {"--sigma", "filter_sigma_m", "Gaussian low-pass standard deviation, m (multifractal)", {}},
        {"--relief", "relief_m", "total relief max - min, m (multifractal)", {}},
        {"--base", "base_elevation_m", "lowest elevation, m (multifractal)", {}},
        {"--hi-wavelength", "hi_wavelength_m", "short-feature wavelength, m (perlin)", {}},
        {"--hi-magnitude", "hi_magnitude_m", "short-feature amplitude, m (perlin, variable)", {}},
        {"--lo-wavelength", "lo_wavelength_m", "rolling-hill wavelength, m (perlin, gaussian)", {}},
        {"--lo-magnitude", "lo_magnitude_m", "rolling-hill amplitude, m (perlin, gaussian)", {}},
        {"--rms", "rms_m", "RMS height, m (gaussian, fbm)", {}},
        {"--correlation-length", "correlation_length_m", "correlation length, m (gaussian)", {}},
        {"--spectral-exponent",
         "spectral_exponent",
         "alpha in profile PSD ~ Omega^-alpha (variable; default 2)",
         {}},
        {"--max-wavelength",
         "max_wavelength_m",
         "longest octave, m (variable; capped at extent/4)",
         {}},
        {"--envelope-wavelength",
         "envelope_wavelength_m",
         "roughness envelope wavelength, m (variable; 0 = none)",
         {}},
        {"--hurst", "hurst", "Hurst exponent H in (0, 1), D = 3 - H (fbm)", {}},
    };
};

json build_spec(const GenerateArgs& a) {
    json spec = json::object();
    if (!a.config.empty()) spec = parse_json(ecoterra::io::read_text(a.config), a.config);
    if (!spec.is_object()) throw InputError(a.config + ": must hold a JSON object");
    if (!a.preset.empty()) spec["preset"] = a.preset;
    if (!a.method.empty()) spec["method"] = a.method;
    if (a.size) spec["size"] = *a.size;
    if (a.nx) spec["nx"] = *a.nx;
    if (a.ny) spec["ny"] = *a.ny;
    if (a.cell) spec["cell_size_m"] = *a.cell;
    if (a.origin_x) spec["origin_x_m"] = *a.origin_x;
    if (a.origin_y) spec["origin_y_m"] = *a.origin_y;
    if (a.seed) spec["seed"] = *a.seed;
    std::string method = spec.value("method", spec.contains("preset") ? "multifractal" : "");
    if (method.empty())
        throw InputError("give --method (multifractal, wm, perlin, gaussian, variable, fbm) or "
                         "--preset majhor2023");
    json& params = spec["params"];
    if (params.is_null()) params = json::object();
    std::vector<std::string> keys;
    try {
        keys = terrain_param_keys(method);
    } catch (const InputError&) {
        resolve_terrain_spec(spec); // reports the unknown method with suggestions
        throw;
    }
    auto accepts = [&](const std::string& k) {
        return std::find(keys.begin(), keys.end(), k) != keys.end();
    };
    for (const auto& p : a.params) {
        if (!p.value) continue;
        if (!accepts(p.key))
            throw InputError(std::string(p.flag) + " does not apply to method '" + method + "'");
        if (std::string(p.key) == "M" || std::string(p.key) == "n_max")
            params[p.key] = static_cast<long long>(std::llround(*p.value));
        else
            params[p.key] = *p.value;
    }
    if (a.mavs_compat) {
        if (!accepts("mavs_compat"))
            throw InputError("--mavs-compat does not apply to method '" + method + "'");
        params["mavs_compat"] = true;
    }
    return spec;
}

void run_generate(const GenerateArgs& a) {
    refuse_output_over_input("-o", a.output, {a.config});
    Stopwatch sw;
    const json spec = build_spec(a);
    const auto format = a.format.empty() ? terrain::io::format_from_path(a.output)
                                         : terrain::io::format_from_name(a.format);
    // Check the output before the (possibly long) generation.
    refuse_over_run_file("-o", a.output);
    claim_output("-o", a.output, a.force);
    { ecoterra::io::AtomicOutput probe(a.output); }
    GeneratedTerrain t = [&] {
        // Progress (with an ETA) for large grids: a 2017 x 2017 multifractal takes seconds.
        const ProgressScope progress(
            [&](double f) { progress_line(f, sw.seconds(), "  generating terrain  "); });
        return generate_terrain(spec);
    }();
    end_progress_line();
    const double gen_s = sw.seconds();
    std::vector<std::string> warnings = t.warnings;
    terrain::io::WriteOptions wo;
    wo.provenance = provenance({{"terrain", t.resolved}, {"info", t.info}});
    wo.warnings = &warnings;
    terrain::io::write_raster(t.z, a.output, format, wo);
    print_warnings(warnings);
    const auto s = stats(t.z);
    std::printf("generated %s terrain: %d x %d cells of %.4g m (%.4g x %.4g m), seed %llu\n",
                t.resolved["method"].get<std::string>().c_str(), t.z.nx(), t.z.ny(),
                t.z.cell_size(), t.z.grid().width_m(), t.z.grid().height_m(),
                static_cast<unsigned long long>(t.resolved["seed"].get<std::uint64_t>()));
    std::printf("elevation %.4g .. %.4g m, std %.4g m; %.3f s to generate (%.3g cells/s)\n", s.min,
                s.max, s.stddev, gen_s, static_cast<double>(t.z.size()) / gen_s);
    std::printf("wrote %s (%s)\n", a.output.c_str(), terrain::io::format_name(format).c_str());
}

struct AnalyzeArgs {
    std::string input, json_out, png_dir, estimator = "variogram";
    bool force = false;
    AnalysisOptions opt;
};

void add_analysis_options(CLI::App* c, AnalysisOptions& o) {
    c->add_option("--low-threshold", o.thresholds.low,
                  "largest slope (rise/run) of the low class (default 0.293 = 50 paper units/cm)");
    c->add_option("--high-threshold", o.thresholds.high,
                  "largest slope (rise/run) of the semi class (default 0.820 = 140 units/cm)");
    c->add_option("--border", o.border_m, "border left out of class areas and missions, m")
        ->capture_default_str();
    c->add_option("--closing-radius", o.closing_radius_m,
                  "disk radius of the morphological closing of the class map, m")
        ->capture_default_str();
}

void run_analyze(AnalyzeArgs& a) {
    refuse_output_over_input("--json", a.json_out, {a.input});
    if (a.estimator == "variogram")
        a.opt.fd.estimator = DimensionEstimator::variogram;
    else if (a.estimator == "madogram")
        a.opt.fd.estimator = DimensionEstimator::madogram;
    else
        throw InputError("--fd-estimator must be variogram or madogram, got '" + a.estimator + "'");
    a.opt.validate();
    claim_output("--json", a.json_out, a.force);
    claim_output("--png", a.png_dir, a.force);
    if (!a.json_out.empty()) {
        ecoterra::io::AtomicOutput probe(a.json_out);
    }
    Stopwatch sw;
    std::vector<std::string> warnings;
    const RasterD z = terrain::io::read_raster(a.input, &warnings);
    print_warnings(warnings);
    const TerrainAnalysis r = analyze_terrain(z, a.opt);
    std::printf("%s: %d x %d cells of %.4g m\n%s", a.input.c_str(), z.nx(), z.ny(), z.cell_size(),
                r.summary(a.opt).c_str());
    print_notes(r.notes);
    if (!a.json_out.empty()) {
        json j = analyses::terrain_json(r, a.opt);
        j["input"] = a.input;
        j["grid"] = {{"nx", z.nx()},
                     {"ny", z.ny()},
                     {"cell_size_m", z.cell_size()},
                     {"origin_x_m", z.grid().origin_x_m},
                     {"origin_y_m", z.grid().origin_y_m}};
        j["provenance"] = provenance();
        ecoterra::io::write_text_atomic(a.json_out, j.dump(2) + "\n");
        std::printf("wrote %s\n", a.json_out.c_str());
    }
    if (!a.png_dir.empty()) {
        const auto files = write_analysis_pictures(z, r, a.opt, a.png_dir);
        std::printf("wrote %zu pictures into %s\n", files.size(), a.png_dir.c_str());
    }
    std::printf("analysis took %.2f s\n", sw.seconds());
}

struct MissionArgs {
    std::string input, output, json_out;
    bool force = false;
    AnalysisOptions opt;
    MissionOptions m;
};

void run_missions(MissionArgs& a) {
    refuse_output_over_input("-o", a.output, {a.input});
    refuse_output_over_input("--json", a.json_out, {a.input});
    a.opt.validate();
    a.m.border_m = a.opt.border_m;
    a.m.validate();
    claim_output("-o", a.output, a.force);
    claim_output("--json", a.json_out, a.force);
    std::vector<std::string> warnings;
    const RasterD z = terrain::io::read_raster(a.input, &warnings);
    print_warnings(warnings);
    const auto missions = plan_missions(z, a.opt, a.m);
    json arr = json::array();
    for (const auto& m : missions)
        arr.push_back({{"id", m.id},
                       {"start_m", {m.start_x_m, m.start_y_m}},
                       {"goal_m", {m.goal_x_m, m.goal_y_m}},
                       {"heading_deg", m.heading_deg},
                       {"length_m", m.length_m},
                       {"fraction",
                        {{"low", m.class_fraction[0]},
                         {"semi", m.class_fraction[1]},
                         {"high", m.class_fraction[2]}}},
                       {"classes_crossed", m.classes_crossed}});
    const json doc = {{"input", a.input},
                      {"heading_convention", "degrees counter-clockwise from east (+x)"},
                      {"count", a.m.count},
                      {"length_m", a.m.length_m},
                      {"border_m", a.m.border_m},
                      {"seed", a.m.seed},
                      {"missions", arr},
                      {"provenance", provenance()}};
    auto write = [&](const std::string& path) {
        const bool as_json = path.size() >= 5 && path.substr(path.size() - 5) == ".json";
        ecoterra::io::write_text_atomic(path,
                                        as_json ? doc.dump(2) + "\n" : missions_csv(missions));
        std::printf("wrote %zu missions to %s\n", missions.size(), path.c_str());
    };
    if (!a.output.empty()) write(a.output);
    if (!a.json_out.empty()) write(a.json_out);
    if (a.output.empty() && a.json_out.empty()) std::fputs(missions_csv(missions).c_str(), stdout);
}

struct ConvertArgs {
    std::string input, output, format;
    bool force = false;
    // A window on a new grid (the scene's terrain.window, cell_m, resampling and crs).
    std::vector<double> bounds, pixels, centre, size;
    double cell = 0;
    std::string resampling = "auto", crs;
};

/// The window options of `terrain convert` as a request for read_dem.
terrain::io::DemRequest dem_request(const ConvertArgs& a) {
    terrain::io::DemRequest r;
    r.path = a.input;
    r.key = "terrain convert";
    auto arr = [](const std::vector<double>& v, std::size_t n, const char* opt) {
        if (v.size() != n)
            throw InputError(std::string(opt) + ": give " + std::to_string(n) +
                             " numbers separated by commas");
    };
    if (!a.bounds.empty()) {
        arr(a.bounds, 4, "--bounds");
        r.window.bounds = std::array<double, 4>{a.bounds[0], a.bounds[1], a.bounds[2], a.bounds[3]};
    }
    if (!a.pixels.empty()) {
        arr(a.pixels, 4, "--pixels");
        r.window.pixels = std::array<double, 4>{a.pixels[0], a.pixels[1], a.pixels[2], a.pixels[3]};
    }
    if (!a.centre.empty()) {
        arr(a.centre, 2, "--centre");
        if (a.size.empty()) throw InputError("--centre needs --size (metres: W or W,H)");
        r.window.centre = std::array<double, 2>{a.centre[0], a.centre[1]};
        r.window.size_m = {a.size[0], a.size.size() > 1 ? a.size[1] : a.size[0]};
    } else if (!a.size.empty()) {
        throw InputError("--size: only with --centre");
    }
    r.cell_m = a.cell;
    r.resampling = a.resampling;
    r.crs = a.crs;
    return r;
}

void run_convert(const ConvertArgs& a) {
    // "run.h5:/terrain/elevation" names the file run.h5: converting it onto itself would leave
    // only the raster.
    refuse_output_over_input("output", a.output, {raster_file_part(a.input)});
    const auto format = a.format.empty() ? terrain::io::format_from_path(a.output)
                                         : terrain::io::format_from_name(a.format);
    refuse_over_run_file("output", a.output);
    claim_output("output", a.output, a.force);
    std::vector<std::string> warnings;
    const terrain::io::DemRequest req = dem_request(a);
    RasterD z;
    json source;
    if (terrain::io::dem_request_resamples(req) || a.resampling != "auto") {
        terrain::io::DemRead d = terrain::io::read_dem(req, &warnings);
        z = std::move(d.z);
        source = std::move(d.record);
    } else {
        z = terrain::io::read_raster(a.input, &warnings);
    }
    terrain::io::WriteOptions wo;
    wo.provenance = provenance({{"converted_from", a.input}});
    if (!source.is_null()) wo.provenance["window"] = source;
    wo.warnings = &warnings;
    terrain::io::write_raster(z, a.output, format, wo);
    print_warnings(warnings);
    if (!source.is_null()) print_terrain_source(source);
    std::printf("converted %s (%d x %d cells of %.4g m) to %s (%s)\n", a.input.c_str(), z.nx(),
                z.ny(), z.cell_size(), a.output.c_str(), terrain::io::format_name(format).c_str());
}

} // namespace

namespace {

void add_generate(CLI::App* terrain) {
    auto g = std::make_shared<GenerateArgs>();
    CLI::App* gen = terrain->add_subcommand("generate", "generate a heightmap");
    gen->footer("Unset parameters take their method's defaults, which depend on the method and "
                "the grid: `ecoterra describe terrain` lists every one with its unit, default "
                "and range.");
    gen->add_option("--preset", g->preset, "a named setting: majhor2023 (paper 000 multifractal)");
    gen->add_option("--method", g->method,
                    "multifractal | wm | perlin | gaussian | variable | fbm");
    gen->add_option("--config", g->config, "JSON file with the specification (flags override it)");
    gen->add_option("--size", g->size, "N: an N x N grid, cells");
    gen->add_option("--nx", g->nx, "columns (x, east), cells");
    gen->add_option("--ny", g->ny, "rows (y, north), cells");
    gen->add_option("--cell", g->cell, "cell size, m per pixel");
    gen->add_option("--origin-x", g->origin_x, "x of the south-west corner, m");
    gen->add_option("--origin-y", g->origin_y, "y of the south-west corner, m");
    gen->add_option("--seed", g->seed, "random seed (non-negative integer)");
    for (auto& p : g->params) gen->add_option(p.flag, p.value, p.help);
    gen->add_flag(
        "--mavs-compat", g->mavs_compat,
        "reproduce MAVS's own scaling (perlin: 1.25 pi and 4x; variable: PSD ~ Omega^-3)");
    gen->add_option("-o,--output", g->output,
                    "output file; the extension picks the format (.h5 .asc .tif .png "
                    ".gazebo.png .obj)")
        ->required();
    gen->add_option("--format", g->format, "force a format: hdf5 asc geotiff png gazebo-png obj");
    add_force_flag(gen, g->force);
    gen->callback([g] { run_generate(*g); });
}

void add_analyze(CLI::App* terrain) {
    auto a = std::make_shared<AnalyzeArgs>();
    CLI::App* an = terrain->add_subcommand("analyze", "roughness, classes, PSD, fractal dimension");
    an->add_option("file", a->input, "elevation raster (any supported format)")->required();
    an->add_option("--json", a->json_out, "write the report as JSON here");
    an->add_option("--png", a->png_dir, "write pictures into this folder");
    add_analysis_options(an, a->opt);
    an->add_option("--detrend-window", a->opt.rms.detrend_window_m,
                   "side of the local-mean window for detrended RMS, m")
        ->capture_default_str();
    an->add_option("--band-cutoff", a->opt.rms.band_long_cutoff_m,
                   "band-limited RMS removes wavelengths longer than this, m (US Army: 3.0)")
        ->capture_default_str();
    an->add_option("--band-short-cutoff", a->opt.rms.band_short_cutoff_m,
                   "and shorter than this, m (0 = keep all)")
        ->capture_default_str();
    an->add_option("--psd-bin-ratio", a->opt.psd.bin_ratio,
                   "outer/inner frequency ratio of PSD annuli (>= W-M gamma)")
        ->capture_default_str();
    an->add_option("--psd-anchor", a->opt.psd.anchor_cpm,
                   "centre one annulus on this frequency, cycles/m (W-M: 1/L; 0 = 1/extent)");
    an->add_option("--psd-fit-min", a->opt.psd.fit_min_cpm,
                   "lowest fitted frequency, cycles/m (0 = 10/extent)");
    an->add_option("--psd-fit-max", a->opt.psd.fit_max_cpm,
                   "highest fitted frequency, cycles/m (0 = last annulus below Nyquist)");
    an->add_option("--fd-estimator", a->estimator, "variogram | madogram")->capture_default_str();
    an->add_option("--fd-max-lag", a->opt.fd.max_lag_fraction,
                   "longest lag as a fraction of the shorter side")
        ->capture_default_str();
    an->add_option("--fd-tolerance", a->opt.fd.tolerance,
                   "largest log10 residual inside the linear range")
        ->capture_default_str();
    add_force_flag(an, a->force);
    an->callback([a] { run_analyze(*a); });
}

void add_missions(CLI::App* terrain) {
    auto m = std::make_shared<MissionArgs>();
    CLI::App* mi = terrain->add_subcommand("missions", "random straight-line A-to-B missions");
    mi->add_option("file", m->input, "elevation raster")->required();
    mi->add_option("--count", m->m.count, "number of missions")->capture_default_str();
    mi->add_option("--length", m->m.length_m, "start-to-goal distance, m")->capture_default_str();
    mi->add_option("--seed", m->m.seed, "random seed")->capture_default_str();
    mi->add_flag("--allow-fewer", m->m.allow_fewer,
                 "return the missions found when the terrain has room for fewer (none without a "
                 "low cell) instead of failing");
    add_analysis_options(mi, m->opt);
    mi->add_option("-o,--output", m->output, "CSV file (or .json)");
    mi->add_option("--json", m->json_out, "also write JSON here");
    add_force_flag(mi, m->force);
    mi->callback([m] { run_missions(*m); });
}

void add_convert(CLI::App* terrain) {
    auto c = std::make_shared<ConvertArgs>();
    CLI::App* cv = terrain->add_subcommand("convert", "convert a raster between formats");
    cv->add_option("input", c->input, "input raster")->required();
    cv->add_option("output", c->output, "output raster; the extension picks the format")
        ->required();
    cv->add_option("--format", c->format, "force a format: hdf5 asc geotiff png gazebo-png obj");
    cv->add_option("--bounds", c->bounds,
                   "a window: x_min,y_min,x_max,y_max in the input's coordinate system")
        ->delimiter(',');
    cv->add_option("--pixels", c->pixels, "a window: column,row,columns,rows (row 0 north)")
        ->delimiter(',');
    cv->add_option("--centre", c->centre, "a window around x,y (the input's system), with --size")
        ->delimiter(',');
    cv->add_option("--size", c->size, "the window's width[,height], m")->delimiter(',');
    cv->add_option("--cell", c->cell, "resample to cells of this side, m (GDAL's warper)");
    cv->add_option("--resampling", c->resampling,
                   "auto (cubic refining, average coarsening), nearest, bilinear, cubic, "
                   "cubicspline, lanczos, average");
    cv->add_option("--crs", c->crs, "reproject to this system (EPSG:n, WKT, PROJ; metres)");
    cv->footer("The window options do what a scene's terrain.window, cell_m, resampling and crs "
               "do (docs/formats.md, DEM windows); the output's provenance records the window.");
    add_force_flag(cv, c->force);
    cv->callback([c] { run_convert(*c); });
}

} // namespace

void add_terrain_command(CLI::App& app) {
    CLI::App* terrain = app.add_subcommand("terrain", "generate, analyse and convert terrain");
    terrain->require_subcommand(1);
    add_generate(terrain);
    add_analyze(terrain);
    add_missions(terrain);
    add_convert(terrain);
}

} // namespace ecoterra::app
