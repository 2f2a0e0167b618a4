#include "ecoterra/terrain/generate.hpp"

#include "ecoterra/catalog.hpp"
#include "ecoterra/json_util.hpp"
#include "ecoterra/progress.hpp"
#include "ecoterra/terrain/noise.hpp"
#include "ecoterra/terrain/spectral.hpp"
#include "ecoterra/terrain/weierstrass.hpp"

#include <limits>
#include <numbers>

namespace ecoterra::terrain {

namespace {

using nlohmann::json;

/// Largest grid side accepted before the memory check (keeps nx * ny within int64 products).
constexpr long long kMaxSide = 1LL << 20;

constexpr double kInf = std::numeric_limits<double>::infinity();

const ParamCatalog<WMParams>& wm_fields() {
    using P = WMParams;
    static const ParamCatalog<P> c(
        "params",
        {integer<P>("M", &P::M, "1", 1, 4096, "number of ridges (directions)"),
         integer<P>("n_max", &P::n_max, "1", 0, 100000,
                    "highest frequency index; 0 = the grid's Nyquist cutoff"),
         number<P>("gamma", &P::gamma, "1", 1, kInf, "frequency density, > 1"),
         number<P>("D", &P::D, "1", 2, 3, "fractal dimension, strictly between 2 and 3"),
         number<P>("L_m", &P::L_m, "m", 0, kInf, "sampling length, > 0"),
         number<P>("G_m", &P::G_m, "m", 0, kInf, "elevation scaling coefficient, > 0"),
         number<P>("phase_max_rad", &P::phase_max_rad, "rad", 0, 2 * std::numbers::pi,
                   "random phases are uniform in [0, this], > 0 (pi in Majhor & Bos Table 1)")});
    return c;
}

const ParamCatalog<PerlinSurfaceParams>& perlin_fields() {
    using P = PerlinSurfaceParams;
    static const ParamCatalog<P> c(
        "params",
        {number<P>("hi_wavelength_m", &P::hi_wavelength_m, "m", 0, kInf,
                   "wavelength of the high-frequency octave, > 0"),
         number<P>("hi_magnitude_m", &P::hi_magnitude_m, "m", 0, kInf,
                   "magnitude of the high-frequency octave"),
         number<P>("lo_wavelength_m", &P::lo_wavelength_m, "m", 0, kInf,
                   "wavelength of the low-frequency octave, > 0"),
         number<P>("lo_magnitude_m", &P::lo_magnitude_m, "m", 0, kInf,
                   "magnitude of the low-frequency octave"),
         flag<P>("mavs_compat", &P::mavs_compat, "reproduce MAVS's scaling of the octaves")});
    return c;
}

const ParamCatalog<GaussianSurfaceParams>& gaussian_fields() {
    using P = GaussianSurfaceParams;
    static const ParamCatalog<P> c(
        "params", {number<P>("rms_m", &P::rms_m, "m", 0, kInf, "RMS height of the rough part"),
                   number<P>("correlation_length_m", &P::correlation_length_m, "m", 0, kInf,
                             "Gaussian correlation length, > 0"),
                   number<P>("lo_wavelength_m", &P::lo_wavelength_m, "m", 0, kInf,
                             "wavelength of the low-frequency Perlin octave, > 0"),
                   number<P>("lo_magnitude_m", &P::lo_magnitude_m, "m", 0, kInf,
                             "magnitude of the low-frequency Perlin octave")});
    return c;
}

const ParamCatalog<VariableSurfaceParams>& variable_fields() {
    using P = VariableSurfaceParams;
    static const ParamCatalog<P> c(
        "params",
        {number<P>("hi_magnitude_m", &P::hi_magnitude_m, "m", 0, kInf,
                   "magnitude of the rough part"),
         number<P>("spectral_exponent", &P::spectral_exponent, "1", 0, 6,
                   "PSD exponent of the rough part (3 with mavs_compat)"),
         number<P>("max_wavelength_m", &P::max_wavelength_m, "m", 0, kInf,
                   "longest wavelength of the rough part, > 0"),
         number<P>("envelope_wavelength_m", &P::envelope_wavelength_m, "m", 0, kInf,
                   "wavelength of the roughness envelope"),
         flag<P>("mavs_compat", &P::mavs_compat, "reproduce MAVS's variable-roughness surface")});
    return c;
}

const ParamCatalog<MultifractalParams>& multifractal_fields() {
    using P = MultifractalParams;
    static const ParamCatalog<P> c(
        "params",
        {number<P>("filter_sigma_m", &P::filter_sigma_m, "m", 0, kInf,
                   "Gaussian low-pass standard deviation (0 = no filter)"),
         number<P>("relief_m", &P::relief_m, "m", 0, kInf, "total relief (max - min), > 0"),
         number<P>("base_elevation_m", &P::base_elevation_m, "m", -kInf, kInf,
                   "elevation of the lowest cell"),
         choice<P>("layer_scaling", &P::layer_scaling,
                   std::vector<std::pair<std::string, LayerScaling>>{
                       {"zero_mean", LayerScaling::zero_mean},
                       {"unit_interval", LayerScaling::unit_interval}},
                   "each layer before the product: zero mean and peak 1 (the paper's text), or "
                   "[0, 1] (no flat bands where a layer crosses zero)"),
         number<P>("layer_offset", &P::layer_offset, "1", -kInf, kInf,
                   "added to each rescaled layer before the product (0 = the paper's zero "
                   "mean; above 1 no layer crosses zero)")});
    return c;
}

const ParamCatalog<FbmParams>& fbm_fields() {
    using P = FbmParams;
    static const ParamCatalog<P> c(
        "params", {number<P>("hurst", &P::hurst, "1", 0, 1,
                             "Hurst exponent H, strictly between 0 and 1 (or give D = 3 - H)"),
                   number<P>("rms_m", &P::rms_m, "m", 0, kInf, "RMS height about the mean, > 0")});
    return c;
}

json wm_json(const WMParams& p) {
    return wm_fields().to_json(p);
}

WMParams wm_from(const json& j, WMParams d, const std::string& where) {
    WMParams p = wm_fields().read(j, d, {}, where);
    validate(p);
    return p;
}

json multifractal_json(const MultifractalParams& p) {
    json j = multifractal_fields().to_json(p);
    j["low"] = wm_json(p.low);
    j["mid"] = wm_json(p.mid);
    j["high"] = wm_json(p.high);
    return j;
}

MultifractalParams multifractal_from(const json& j, const std::string& where) {
    const MultifractalParams d;
    MultifractalParams p =
        multifractal_fields().read(j, d, {"low", "mid", "high", "d_high"}, where);
    if (j.contains("low")) p.low = wm_from(j["low"], d.low, where + ".low");
    if (j.contains("mid")) p.mid = wm_from(j["mid"], d.mid, where + ".mid");
    if (j.contains("high")) p.high = wm_from(j["high"], d.high, where + ".high");
    if (j.contains("d_high")) {
        if (j.contains("high") && j["high"].contains("D"))
            throw InputError(where + ": give d_high or high.D, not both");
        p.high.D = get_number(j, "d_high", d.high.D, where);
        validate(p.high);
    }
    validate(p);
    return p;
}

PerlinSurfaceParams perlin_from(const json& j, const std::string& where) {
    const auto p = perlin_fields().read(j, PerlinSurfaceParams{}, {}, where);
    validate(p);
    return p;
}

GaussianSurfaceParams gaussian_from(const json& j, const std::string& where) {
    const auto p = gaussian_fields().read(j, GaussianSurfaceParams{}, {}, where);
    validate(p);
    return p;
}

json variable_json(const VariableSurfaceParams& p) {
    json j = variable_fields().to_json(p);
    if (p.mavs_compat) j["spectral_exponent"] = 3.0;
    return j;
}
VariableSurfaceParams variable_from(const json& j, const std::string& where) {
    auto p = variable_fields().read(j, VariableSurfaceParams{}, {}, where);
    if (p.mavs_compat && j.contains("spectral_exponent") && p.spectral_exponent != 3.0)
        throw InputError(where + ": mavs_compat fixes spectral_exponent at 3; do not set both");
    validate(p);
    return p;
}

json fbm_json(const FbmParams& p) {
    json j = fbm_fields().to_json(p);
    j["D"] = 3.0 - p.hurst;
    return j;
}
FbmParams fbm_from(const json& j, const std::string& where) {
    const FbmParams d;
    FbmParams p = fbm_fields().read(j, d, {"D"}, where);
    const double rms = p.rms_m;
    if (j.contains("D") && j.contains("hurst") &&
        std::abs(j["D"].get<double>() + j["hurst"].get<double>() - 3.0) > 1e-12)
        throw InputError(where + ": D and hurst disagree (D = 3 - hurst); give one");
    if (j.contains("D"))
        p = FbmParams::from_dimension(get_number(j, "D", 2.3, where), rms);
    else
        p = FbmParams{p.hurst, rms};
    validate(p);
    return p;
}

/// Default grid per method: the paper's grid for W-M and multifractal, 512 x 512 at 0.25 m else.
GridSpec default_grid(const std::string& method) {
    if (method == "multifractal" || method == "wm") return majhor2023_grid();
    return GridSpec{512, 512, 0.25, 0.0, 0.0};
}

/// The grid and seed keys of a terrain specification (beside method, preset, size and params).
struct GridAndSeed {
    GridSpec grid;
    long long seed = 1;
};

const ParamCatalog<GridAndSeed>& grid_catalog() {
    using G = GridAndSeed;
    constexpr double kMinCell_m = 1e-9;
    static const ParamCatalog<G> c(
        "", {integer<G>(
                 "nx", +[](G& g) -> int& { return g.grid.nx; }, "1", 1, kMaxSide,
                 "columns (x, east); `size` sets nx and ny at once")
                 .with_note("per method"),
             integer<G>(
                 "ny", +[](G& g) -> int& { return g.grid.ny; }, "1", 1, kMaxSide, "rows (y, north)")
                 .with_note("per method"),
             number<G>(
                 "cell_size_m", +[](G& g) -> double& { return g.grid.cell_size_m; }, "m",
                 kMinCell_m, catalog_detail::kNoLimit, "side of a square cell")
                 .with_note("per method"),
             number<G>(
                 "origin_x_m", +[](G& g) -> double& { return g.grid.origin_x_m; }, "m",
                 -catalog_detail::kNoLimit, catalog_detail::kNoLimit,
                 "x of the grid's south-west corner"),
             number<G>(
                 "origin_y_m", +[](G& g) -> double& { return g.grid.origin_y_m; }, "m",
                 -catalog_detail::kNoLimit, catalog_detail::kNoLimit,
                 "y of the grid's south-west corner"),
             integer<G>("seed", &G::seed, "1", 0, 4.611686018427388e18, "seed of the generator")});
    return c;
}

} // namespace

const std::vector<std::string>& terrain_methods() {
    static const std::vector<std::string> m = {"multifractal", "wm",       "perlin",
                                               "gaussian",     "variable", "fbm"};
    return m;
}

json resolve_terrain_spec(const json& spec) {
    require_known_keys(spec, grid_catalog().keys_at("", {"method", "preset", "size", "params"}),
                       "");
    std::string preset = get_string(spec, "preset", "", "");
    if (!preset.empty() && preset != "majhor2023")
        throw InputError("preset: unknown preset '" + preset + "' (known: majhor2023)");
    std::string method = get_string(spec, "method", preset.empty() ? "" : "multifractal", "");
    if (method.empty())
        throw InputError("method: no generation method given (" +
                         std::string("multifractal, wm, perlin, gaussian, "
                                     "variable, fbm)"));
    const auto& ms = terrain_methods();
    if (std::find(ms.begin(), ms.end(), method) == ms.end()) {
        std::string best;
        std::size_t bd = 4;
        for (const auto& m : ms)
            if (edit_distance(method, m) < bd) bd = edit_distance(method, m), best = m;
        throw InputError("method: unknown method '" + method + "'" +
                         (best.empty() ? "" : " (did you mean '" + best + "'?)") +
                         "; known: multifractal, wm, perlin, gaussian, variable, fbm");
    }
    if (!preset.empty() && method != "multifractal")
        throw InputError("preset majhor2023 is a multifractal setting; method is '" + method + "'");
    GridAndSeed gs{default_grid(method)};
    if (spec.contains("size"))
        gs.grid.nx = gs.grid.ny =
            static_cast<int>(get_integer(spec, "size", gs.grid.nx, "", 1, kMaxSide));
    gs = grid_catalog().read(spec, gs, {"method", "preset", "size", "params"});
    const GridSpec& g = gs.grid;
    g.validate("grid");
    const long long seed = gs.seed;
    const json params = spec.value("params", json::object());
    const std::string where = "params";
    json p;
    if (method == "multifractal") {
        p = multifractal_json(multifractal_from(params, where));
    } else if (method == "wm") {
        p = wm_json(wm_from(params, WMParams{}, where));
    } else if (method == "perlin") {
        const PerlinSurfaceParams q = perlin_from(params, where);
        p = perlin_fields().to_json(q);
    } else if (method == "gaussian") {
        const GaussianSurfaceParams q = gaussian_from(params, where);
        p = gaussian_fields().to_json(q);
    } else if (method == "variable") {
        const VariableSurfaceParams q = variable_from(params, where);
        p = variable_json(q);
    } else {
        p = fbm_json(fbm_from(params, where));
    }
    json r = {{"method", method},
              {"nx", g.nx},
              {"ny", g.ny},
              {"cell_size_m", g.cell_size_m},
              {"origin_x_m", g.origin_x_m},
              {"origin_y_m", g.origin_y_m},
              {"seed", seed},
              {"params", p}};
    if (!preset.empty()) r["preset"] = preset;
    if (method == "fbm") r["params"].erase("D"); // hurst is the resolved key
    return r;
}

std::vector<std::string> terrain_param_keys(const std::string& method) {
    if (method == "multifractal")
        return multifractal_fields().keys_at("", {"low", "mid", "high", "d_high"});
    if (method == "wm") return wm_fields().keys_at("");
    if (method == "perlin") return perlin_fields().keys_at("");
    if (method == "gaussian") return gaussian_fields().keys_at("");
    if (method == "variable") return variable_fields().keys_at("");
    if (method == "fbm") return fbm_fields().keys_at("", {"D"});
    throw InputError("unknown method '" + method + "'");
}

std::vector<std::pair<std::string, std::vector<ParamInfo>>> describe_terrain_params() {
    std::vector<std::pair<std::string, std::vector<ParamInfo>>> out;
    {
        std::vector<ParamInfo> grid = {
            {"method", "", "multifractal with a preset",
             "multifractal, wm, perlin, gaussian, variable, fbm", "generator"},
            {"preset", "", "none", "majhor2023", "the paper's multifractal setting and grid"}};
        for (auto& i : describe(grid_catalog(), GridAndSeed{GridSpec{512, 512, 0.25, 0, 0}})) {
            if (i.key == "nx")
                grid.push_back({"size", "1", "none", i.range, "sets nx and ny at once"});
            grid.push_back(std::move(i));
        }
        out.emplace_back("grid and seed (every method; multifractal and wm default to the paper's "
                         "1009 x 1009 grid)",
                         std::move(grid));
    }
    auto wm = describe(wm_fields(), WMParams{});
    auto mf = describe(multifractal_fields(), MultifractalParams{});
    const MultifractalParams md;
    for (const auto& [layer, w] : {std::pair<const char*, const WMParams*>{"low", &md.low},
                                   {"mid", &md.mid},
                                   {"high", &md.high}})
        for (auto i : describe(wm_fields(), *w)) {
            i.key = "params." + std::string(layer) + "." + i.key.substr(7);
            i.description = std::string(layer) + " layer: " + i.description;
            mf.push_back(std::move(i));
        }
    mf.push_back({"params.d_high", "1", format_number(md.high.D), "[2, 3]",
                  "shorthand for params.high.D (the paper's D_high)"});
    auto fbm = describe(fbm_fields(), FbmParams{});
    fbm.push_back({"params.D", "1", "3 - hurst", "[2, 3]", "fractal dimension; give D or hurst"});
    out.emplace_back("multifractal", std::move(mf));
    out.emplace_back("wm", std::move(wm));
    out.emplace_back("perlin", describe(perlin_fields(), PerlinSurfaceParams{}));
    out.emplace_back("gaussian", describe(gaussian_fields(), GaussianSurfaceParams{}));
    out.emplace_back("variable", describe(variable_fields(), VariableSurfaceParams{}));
    out.emplace_back("fbm", std::move(fbm));
    return out;
}

GeneratedTerrain generate_terrain(const json& spec) {
    GeneratedTerrain out;
    out.resolved = resolve_terrain_spec(spec);
    const json& r = out.resolved;
    const std::string method = r["method"];
    const GridSpec g{r["nx"].get<int>(), r["ny"].get<int>(), r["cell_size_m"].get<double>(),
                     r["origin_x_m"].get<double>(), r["origin_y_m"].get<double>()};
    ensure_fits_in_memory(g.size(), method == "multifractal" ? 40.0 : 24.0,
                          "grid " + std::to_string(g.nx) + "x" + std::to_string(g.ny));
    const auto seed = r["seed"].get<std::uint64_t>();
    const json& p = r["params"];
    if (method == "multifractal") {
        auto res = multifractal_generate(g, multifractal_from(p, "params"), seed);
        out.z = std::move(res.z);
        out.warnings = std::move(res.warnings);
    } else if (method == "wm") {
        auto res = wm_generate(g, wm_from(p, WMParams{}, "params"), seed);
        out.z = std::move(res.z);
        out.warnings = std::move(res.warnings);
        out.info["n_max"] = res.n_max;
        out.info["terms_evaluated"] = res.terms_evaluated;
    } else if (method == "perlin") {
        out.z = perlin_surface(g, perlin_from(p, "params"), seed);
    } else if (method == "gaussian") {
        out.z = gaussian_surface(g, gaussian_from(p, "params"), seed);
    } else if (method == "variable") {
        out.z = variable_surface(g, variable_from(p, "params"), seed);
    } else {
        out.z = fbm_surface(g, fbm_from(p, "params"), seed);
    }
    report_progress(1.0); // the workers' last reports are not the caller's
    return out;
}

} // namespace ecoterra::terrain
