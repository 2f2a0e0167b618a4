#include "ecoterra/hydro/soil.hpp"

#include "ecoterra/terrain/noise.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace ecoterra::hydro {

namespace {

using ecoterra::GridSpec;

/// cm/h to m/s.
constexpr double kCmPerHourToMPerS = 0.01 / 3600.0;
/// mm/h to m/s.
constexpr double kMmPerHourToMPerS = 0.001 / 3600.0;
/// Tolerance on sand + silt + clay = 100 %.
constexpr double kSumTolerancePct = 2.0;

struct ClassRow {
    const char* name;
    double porosity, fc, wp, ks_cm_per_h;
};

/// Rawls, Brakensiek & Saxton 1982, in the order of the Texture enum; silt as stated in soil.hpp.
constexpr ClassRow kRawls[kTextureCount] = {
    {"sand", 0.437, 0.091, 0.033, 21.00},           {"loamy_sand", 0.437, 0.125, 0.055, 6.11},
    {"sandy_loam", 0.453, 0.207, 0.095, 2.59},      {"loam", 0.463, 0.270, 0.117, 1.32},
    {"silt_loam", 0.501, 0.330, 0.133, 0.68},       {"silt", 0.520, 0.280, 0.080, 0.68},
    {"sandy_clay_loam", 0.398, 0.255, 0.148, 0.43}, {"clay_loam", 0.464, 0.318, 0.197, 0.23},
    {"silty_clay_loam", 0.471, 0.366, 0.208, 0.15}, {"sandy_clay", 0.430, 0.339, 0.239, 0.12},
    {"silty_clay", 0.479, 0.387, 0.250, 0.09},      {"clay", 0.475, 0.396, 0.272, 0.06},
};

} // namespace

std::string texture_name(Texture t) {
    return kRawls[static_cast<int>(t)].name;
}

std::optional<Texture> parse_texture(const std::string& name) {
    std::string n = name;
    std::replace(n.begin(), n.end(), ' ', '_');
    std::transform(n.begin(), n.end(), n.begin(), [](unsigned char c) { return std::tolower(c); });
    for (int k = 0; k < kTextureCount; ++k)
        if (n == kRawls[k].name) return static_cast<Texture>(k);
    return std::nullopt;
}

void SoilComposition::validate(const std::string& where) const {
    const double parts[3] = {sand_pct, silt_pct, clay_pct};
    const char* names[3] = {"sand", "silt", "clay"};
    for (int k = 0; k < 3; ++k)
        if (!(parts[k] >= 0.0) || !std::isfinite(parts[k]))
            throw InputError(where + ": " + names[k] + " must be a percentage >= 0, got " +
                             format_number(parts[k]));
    const double sum = sand_pct + silt_pct + clay_pct;
    if (std::abs(sum - 100.0) > kSumTolerancePct)
        throw InputError(where + ": sand + silt + clay must be 100 % (within 2), got " +
                         format_number(sand_pct) + " + " + format_number(silt_pct) + " + " +
                         format_number(clay_pct) + " = " + format_number(sum));
    if (!(ph >= 0.0 && ph <= 14.0))
        throw InputError(where + ": pH must be in [0, 14], got " + format_number(ph));
    if (organic_matter_pct && !(*organic_matter_pct >= 0.0 && *organic_matter_pct <= 20.0))
        throw InputError(where + ": organic matter must be in [0, 20] %, got " +
                         format_number(*organic_matter_pct));
}

Texture classify_texture(double sand, double silt, double clay) {
    const double sum = sand + silt + clay;
    if (!(sum > 0)) throw InputError("texture: sand + silt + clay must be > 0");
    const double Sa = 100.0 * sand / sum, Si = 100.0 * silt / sum, C = 100.0 * clay / sum;
    if (Si + 1.5 * C < 15) return Texture::sand;
    if (Si + 2 * C < 30) return Texture::loamy_sand;
    if ((C >= 7 && C < 20 && Sa > 52 && Si + 2 * C >= 30) || (C < 7 && Si < 50 && Si + 2 * C >= 30))
        return Texture::sandy_loam;
    if (C >= 7 && C < 27 && Si >= 28 && Si < 50 && Sa <= 52) return Texture::loam;
    if ((Si >= 50 && C >= 12 && C < 27) || (Si >= 50 && Si < 80 && C < 12))
        return Texture::silt_loam;
    if (Si >= 80 && C < 12) return Texture::silt;
    if (C >= 20 && C < 35 && Si < 28 && Sa > 45) return Texture::sandy_clay_loam;
    if (C >= 27 && C < 40 && Sa > 20 && Sa <= 45) return Texture::clay_loam;
    if (C >= 27 && C < 40 && Sa <= 20) return Texture::silty_clay_loam;
    if (C >= 35 && Sa > 45) return Texture::sandy_clay;
    if (C >= 40 && Si >= 40) return Texture::silty_clay;
    if (C >= 40 && Sa <= 45 && Si < 40) return Texture::clay;
    throw Error("texture: no USDA class for sand " + format_number(Sa) + " silt " +
                format_number(Si) + " clay " + format_number(C) + " (a gap in the class rules)");
}

SoilProperties class_properties(Texture t) {
    const ClassRow& r = kRawls[static_cast<int>(t)];
    SoilProperties p;
    p.texture = t;
    p.porosity = r.porosity;
    p.field_capacity = r.fc;
    p.wilting_point = r.wp;
    p.ksat_m_per_s = r.ks_cm_per_h * kCmPerHourToMPerS;
    p.source = t == Texture::silt ? "rawls1982+schaake2000 (silt)" : "rawls1982";
    return p;
}

double readily_evaporable_water_mm(Texture t) {
    // Index by Texture (sand .. clay), FAO-56 Table 19 mid-range (see soil.hpp).
    static constexpr std::array<double, kTextureCount> rew = {4.5, 6.0, 8.0, 9.0, 9.5,  9.5,
                                                              8.0, 9.5, 9.5, 9.0, 10.0, 10.0};
    return rew[static_cast<std::size_t>(t)];
}

double conductivity_exponent(double field_capacity, double wilting_point) {
    const double lambda =
        (std::log(field_capacity) - std::log(wilting_point)) / (std::log(1500.0) - std::log(33.0));
    return 3.0 + 2.0 / lambda;
}

SoilProperties saxton_rawls_2006(double sand_pct, double clay_pct, double om) {
    const double S = sand_pct / 100.0, C = clay_pct / 100.0;
    const double t1500 = -0.024 * S + 0.487 * C + 0.006 * om + 0.005 * S * om - 0.013 * C * om +
                         0.068 * S * C + 0.031;
    const double wp = t1500 + (0.14 * t1500 - 0.02);
    const double t33 = -0.251 * S + 0.195 * C + 0.011 * om + 0.006 * S * om - 0.027 * C * om +
                       0.452 * S * C + 0.299;
    const double fc = t33 + (1.283 * t33 * t33 - 0.374 * t33 - 0.015);
    const double ts33 = 0.278 * S + 0.034 * C + 0.022 * om - 0.018 * S * om - 0.027 * C * om -
                        0.584 * S * C + 0.078;
    const double s33 = ts33 + (0.636 * ts33 - 0.107);
    const double sat = fc + s33 - 0.097 * S + 0.043;
    const double lambda = (std::log(fc) - std::log(wp)) / (std::log(1500.0) - std::log(33.0));
    const double ks_mm_h = 1930.0 * std::pow(sat - fc, 3.0 - lambda);
    SoilProperties p;
    p.texture = classify_texture(sand_pct, std::max(0.0, 100.0 - sand_pct - clay_pct), clay_pct);
    p.porosity = sat;
    p.field_capacity = fc;
    p.wilting_point = wp;
    p.ksat_m_per_s = ks_mm_h * kMmPerHourToMPerS;
    p.source = "saxton_rawls2006";
    return p;
}

SoilProperties soil_properties(const SoilComposition& c) {
    SoilProperties p = c.organic_matter_pct
                           ? saxton_rawls_2006(c.sand_pct, c.clay_pct, *c.organic_matter_pct)
                           : class_properties(classify_texture(c.sand_pct, c.silt_pct, c.clay_pct));
    p.ph = c.ph;
    return p;
}

namespace {

SoilMap empty_map(const GridSpec& g) {
    return SoilMap{RasterF(g), RasterF(g), RasterF(g), RasterF(g), RasterU8(g),
                   RasterF(g), RasterF(g), RasterF(g), RasterF(g)};
}

void set_cell(SoilMap& m, int i, int j, const SoilComposition& c) {
    const SoilProperties p = soil_properties(c);
    m.sand_pct(i, j) = static_cast<float>(c.sand_pct);
    m.silt_pct(i, j) = static_cast<float>(c.silt_pct);
    m.clay_pct(i, j) = static_cast<float>(c.clay_pct);
    m.ph(i, j) = static_cast<float>(c.ph);
    m.texture(i, j) = static_cast<std::uint8_t>(p.texture);
    m.porosity(i, j) = static_cast<float>(p.porosity);
    m.field_capacity(i, j) = static_cast<float>(p.field_capacity);
    m.wilting_point(i, j) = static_cast<float>(p.wilting_point);
    m.ksat_m_per_s(i, j) = static_cast<float>(p.ksat_m_per_s);
}

} // namespace

SoilMap uniform_soil(const GridSpec& grid, const SoilComposition& c) {
    c.validate("soil");
    SoilMap m = empty_map(grid);
    for (int j = 0; j < grid.ny; ++j)
        for (int i = 0; i < grid.nx; ++i) set_cell(m, i, j, c);
    return m;
}

void RandomSoilParams::validate() const {
    mean.validate("soil.mean");
    if (!(amplitude_pct >= 0 && amplitude_pct <= 50))
        throw InputError("soil.amplitude_pct must be in [0, 50], got " +
                         format_number(amplitude_pct));
    if (!(ph_amplitude >= 0 && ph_amplitude <= 7))
        throw InputError("soil.ph_amplitude must be in [0, 7], got " + format_number(ph_amplitude));
    if (!(patch_size_m > 0))
        throw InputError("soil.patch_size_m must be > 0, got " + format_number(patch_size_m));
}

SoilMap random_soil(const GridSpec& grid, const RandomSoilParams& p, std::uint64_t seed) {
    p.validate();
    const terrain::Perlin2D fsand(seed, 101), fclay(seed, 102), fph(seed, 103);
    SoilMap m = empty_map(grid);
    for (int j = 0; j < grid.ny; ++j)
        for (int i = 0; i < grid.nx; ++i) {
            const double x = grid.x_of(i) / p.patch_size_m, y = grid.y_of(j) / p.patch_size_m;
            SoilComposition c = p.mean;
            double sand = std::clamp(p.mean.sand_pct + p.amplitude_pct * fsand(x, y), 0.0, 100.0);
            double clay = std::clamp(p.mean.clay_pct + p.amplitude_pct * fclay(x, y), 0.0, 100.0);
            if (sand + clay > 100.0) {
                const double f = 100.0 / (sand + clay);
                sand *= f;
                clay *= f;
            }
            c.sand_pct = sand;
            c.clay_pct = clay;
            c.silt_pct = 100.0 - sand - clay;
            c.ph = std::clamp(p.mean.ph + p.ph_amplitude * fph(x, y), 0.0, 14.0);
            set_cell(m, i, j, c);
        }
    return m;
}

SoilMap soil_from_rasters(const RasterD& sand, const RasterD& silt, const RasterD& clay,
                          const RasterD* ph, const std::string& source_name) {
    if (!(sand.grid() == silt.grid()) || !(sand.grid() == clay.grid()) ||
        (ph && !(ph->grid() == sand.grid())))
        throw InputError(source_name + ": the sand, silt, clay (and pH) rasters differ in grid");
    SoilMap m = empty_map(sand.grid());
    for (int j = 0; j < sand.ny(); ++j)
        for (int i = 0; i < sand.nx(); ++i) {
            SoilComposition c{
                sand(i, j), silt(i, j), clay(i, j), ph ? (*ph)(i, j) : SoilComposition{}.ph, {}};
            c.validate(source_name + " cell (" + std::to_string(i) + ", " + std::to_string(j) +
                       ")");
            set_cell(m, i, j, c);
        }
    return m;
}

namespace {
SoilComposition& itself(SoilComposition& c) {
    return c;
}
SoilComposition& mean_of(RandomSoilParams& r) {
    return r.mean;
}

/// The composition keys over any struct that holds a composition (reached by `comp`).
template <class S, SoilComposition& (*comp)(S&)>
std::vector<Param<S>> composition_params() {
    return {number<S>(
                "sand_pct", +[](S& s) -> double& { return comp(s).sand_pct; }, "%", 0, 100,
                "sand, % by mass (sand + silt + clay = 100 within 2)"),
            number<S>(
                "silt_pct", +[](S& s) -> double& { return comp(s).silt_pct; }, "%", 0, 100,
                "silt, % by mass"),
            number<S>(
                "clay_pct", +[](S& s) -> double& { return comp(s).clay_pct; }, "%", 0, 100,
                "clay, % by mass"),
            number<S>(
                "ph", +[](S& s) -> double& { return comp(s).ph; }, "pH", 0, 14, "soil pH"),
            optional_number<S>(
                "organic_matter_pct",
                +[](S& s) -> std::optional<double>& { return comp(s).organic_matter_pct; }, "%", 0,
                20,
                "organic matter: hydraulic properties from Saxton & Rawls 2006 instead of the "
                "class table")};
}
} // namespace

const ParamCatalog<SoilComposition>& soil_composition_catalog() {
    static const ParamCatalog<SoilComposition> c("soil.uniform",
                                                 composition_params<SoilComposition, itself>());
    return c;
}

const ParamCatalog<RandomSoilParams>& random_soil_catalog() {
    using R = RandomSoilParams;
    static const ParamCatalog<R> c("soil.random", [] {
        auto p = composition_params<R, mean_of>();
        for (auto& q : p) q.description = "mean " + q.description;
        p.push_back(number<R>("amplitude_pct", &R::amplitude_pct, "%", 0, 50,
                              "amplitude of the sand and clay fields (Perlin noise)"));
        p.push_back(
            number<R>("ph_amplitude", &R::ph_amplitude, "pH", 0, 7, "amplitude of the pH field"));
        p.push_back(number<R>("patch_size_m", &R::patch_size_m, "m", 0.001, 1e6,
                              "size of the soil patches (the noise's wavelength)"));
        return p;
    }());
    return c;
}

} // namespace ecoterra::hydro
