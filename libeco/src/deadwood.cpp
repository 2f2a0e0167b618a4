// Dead wood as individuals: snags, their fall, logs, decay classes (deadwood.hpp).
#include "ecoterra/eco/deadwood.hpp"

#include "ecoterra/eco/plant.hpp"
#include "ecoterra/error.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace ecoterra::eco {

namespace {
constexpr double kBreastHeightM = 1.3;
/// The top of a snag starts where the stem's diameter is 4 in (FIA's merchantable top; Domke et
/// al. 2011 apply the top's structural loss to the stem above it).
constexpr double kTopDiameterM = 0.1016;
constexpr double kMetresPerInch = 0.0254;
// FVS-FFE's base snag fall rate, NI variant (fmsfall.f): fraction of the original snags falling
// per year, 0.064311 - 0.001679 D_in, at least 0.01 (Marcot's rates, Cline et al. 1980).
constexpr double kFallRateIntercept = 0.064311;
constexpr double kFallRatePerInch = 0.001679;
constexpr double kFallRateMin = 0.01;
/// The slope at which every stem falls downhill (our choice; below it the share falls with the
/// slope), rise over run; and the spread of a downhill fall, +-45 degrees.
constexpr double kSlopeAllDownhill = 0.3;
constexpr double kDownhillSpreadRad = 0.5 * std::numbers::pi;
constexpr std::array<double, 4> kClassThresholds = {0.9, 0.7, 0.4, 0.2};
constexpr std::array<double, 5> kTopRetained = {1.0, 0.5, 0.2, 0.1, 0.0};
constexpr std::array<double, 5> kLogCollapse = {1.0, 1.0, 0.9, 0.6, 0.3};
constexpr std::array<double, 5> kDensityReduction = {0.93, 0.79, 0.57, 0.52, 0.52};
// Root plates (deadwood.hpp): diameter per DBH and its cap; thickness per diameter and bounds.
constexpr double kPlatePerDbh = 12, kPlateMaxM = 5, kPlateThickness = 0.25;
constexpr double kPlateThinM = 0.3, kPlateThickM = 1.0;
/// A wind-felled stem falls along the storm, +-22.5 degrees.
constexpr double kWindSpreadRad = 0.25 * std::numbers::pi;
/// A broken stem snaps where half its mass is below (iLand's wind module: half the stem to the
/// snag pool, half to the ground).
constexpr double kSnapMassFraction = 0.5;
/// Version 2 added the piece kind and its offset along the stem (stumps and slash).
constexpr std::uint32_t kStateVersion = 2;

/// The rows of state version 1.
struct DeadStemV1 {
    double x_m, y_m, z_m, dbh_m, tree_height_m, length_m, azimuth_rad, mass0_kg, mass_kg;
    std::int64_t id;
    std::int32_t year_died, year_falls, year_down;
    std::uint16_t species;
    std::uint8_t cause, standing;
};
static_assert(sizeof(DeadStemV1) == 96, "DeadStemV1 is not version 1's row");

/// The top of stem `d` above height `z`, lying from there along `az` (a cut's slash or a storm's
/// broken top), with `mass_kg`, down in `year`.
DeadStem lying_top(const DeadStem& d, double z, double az, double mass_kg, int year) {
    DeadStem top = d;
    top.piece = static_cast<std::uint8_t>(PieceKind::slash);
    top.standing = 0;
    top.offset_m = z;
    top.length_m = d.tree_height_m - z;
    top.azimuth_rad = az;
    top.x_m += z * std::cos(az);
    top.y_m += z * std::sin(az);
    top.mass0_kg = top.mass_kg = mass_kg;
    top.year_falls = top.year_down = year;
    return top;
}

/// A piece of tree k of the population that died of `cause` in `year`: where and what it was.
DeadStem from_tree(const Population& pop, std::size_t k, DeathCause cause, int year) {
    DeadStem d;
    d.x_m = pop.x_m[k];
    d.y_m = pop.y_m[k];
    d.z_m = pop.z_m[k];
    d.dbh_m = pop.dbh_m[k];
    d.tree_height_m = pop.height_m[k];
    d.id = pop.id[k];
    d.species = pop.species[k];
    d.cause = static_cast<std::uint8_t>(cause);
    d.year_died = year;
    return d;
}

bool enters_dead_wood(const Species& s) {
    return s.life_form == LifeForm::tree;
}

/// Elevation at (x, y) with the point clamped onto the grid.
double elevation(const RasterD& dem, double x, double y) {
    const GridSpec& g = dem.grid();
    const double h = 0.5 * g.cell_size_m;
    x = std::clamp(x, g.origin_x_m + h, g.origin_x_m + g.width_m() - h);
    y = std::clamp(y, g.origin_y_m + h, g.origin_y_m + g.height_m() - h);
    return dem.sample_bilinear(x, y);
}
} // namespace

const char* death_cause_name(DeathCause c) {
    switch (c) {
    case DeathCause::none:
        return "none";
    case DeathCause::starvation:
        return "starvation";
    case DeathCause::age:
        return "age";
    case DeathCause::background:
        return "background";
    case DeathCause::suppression:
        return "suppression";
    case DeathCause::overlap:
        return "overlap";
    case DeathCause::harvest:
        return "harvest";
    case DeathCause::wind_uprooted:
        return "wind_uprooted";
    case DeathCause::wind_broken:
        return "wind_broken";
    }
    return "unknown";
}

double root_plate_diameter_m(double dbh) {
    return std::min(kPlatePerDbh * dbh, kPlateMaxM);
}

double root_plate_thickness_m(double dbh) {
    return std::clamp(kPlateThickness * root_plate_diameter_m(dbh), kPlateThinM, kPlateThickM);
}

namespace deadwood {

double wrap_azimuth(double a) {
    const double two_pi = 2 * std::numbers::pi;
    return a - two_pi * std::floor(a / two_pi);
}

int decay_class(double f) {
    int c = 1;
    for (const double t : kClassThresholds) {
        if (f > t) return c;
        ++c;
    }
    return c;
}

double top_retained(int c) {
    return kTopRetained[static_cast<std::size_t>(std::clamp(c, 1, 5) - 1)];
}

double log_collapse(int c) {
    return kLogCollapse[static_cast<std::size_t>(std::clamp(c, 1, 5) - 1)];
}

double stem_diameter_m(double dbh, double h, double s) {
    if (s <= kBreastHeightM || h <= kBreastHeightM) return s <= h ? dbh : 0.0;
    return dbh * std::max(0.0, (h - s) / (h - kBreastHeightM));
}

double top_start_m(double dbh, double h) {
    double z4 = kBreastHeightM;
    if (dbh > kTopDiameterM && h > kBreastHeightM)
        z4 = h - kTopDiameterM / dbh * (h - kBreastHeightM);
    return std::min(z4, h);
}

double snag_height_m(double dbh, double h, int c) {
    const double z4 = top_start_m(dbh, h);
    return z4 + top_retained(c) * (h - z4);
}

double stem_volume_fraction_below(double h, double z) {
    if (!(h > 0)) return 1.0;
    z = std::clamp(z, 0.0, h);
    if (h <= kBreastHeightM) return z / h;
    const double cone = (h - kBreastHeightM) / 3;
    const double below =
        z <= kBreastHeightM
            ? z
            : kBreastHeightM +
                  cone * (1 - std::pow(1 - (z - kBreastHeightM) / (h - kBreastHeightM), 3));
    return below / (kBreastHeightM + cone);
}

double snag_fall_span_yr(const Species& s, double dbh_m) {
    const double rate =
        std::max(kFallRateMin, kFallRateIntercept - kFallRatePerInch * dbh_m / kMetresPerInch);
    return 1.0 / (rate * s.snag_fall_multiplier);
}

double density_reduction(int c) {
    return kDensityReduction[static_cast<std::size_t>(std::clamp(c, 1, 5) - 1)];
}

double volume_m3(const Species& s, const DeadStem& d) {
    if (!(d.mass0_kg > 0)) return 0.0;
    const double f = d.mass_kg / d.mass0_kg;
    return d.mass0_kg / s.wood_density_kg_per_m3 *
           std::min(1.0, f / density_reduction(decay_class(f)));
}

double fall_azimuth_rad(const RasterD& dem, double x, double y, Rng& rng) {
    const double u1 = rng.uniform(), u2 = rng.uniform();
    const double h = dem.grid().cell_size_m;
    const double gx = (elevation(dem, x + h, y) - elevation(dem, x - h, y)) / (2 * h);
    const double gy = (elevation(dem, x, y + h) - elevation(dem, x, y - h)) / (2 * h);
    const double slope = std::hypot(gx, gy);
    const double two_pi = 2.0 * std::numbers::pi;
    if (slope > 0 && u1 < std::min(1.0, slope / kSlopeAllDownhill)) {
        return wrap_azimuth(std::atan2(-gy, -gx) + (u2 - 0.5) * kDownhillSpreadRad);
    }
    return two_pi * u2;
}

} // namespace deadwood

DeadWood::DeadWood(const DeadWoodOptions& options, std::uint64_t seed)
    : m_opt(options), m_rng(seed, "eco.deadwood") {}

double DeadWood::stock_kg() const {
    double m = 0;
    for (const auto& d : m_pieces) m += d.mass_kg;
    return m;
}

void DeadWood::take_dead(const Population& pop, const std::vector<Species>& species,
                         const std::vector<char>* causes, bool allometric_mass, int year) {
    if (!m_opt.enabled) return;
    for (std::size_t k = 0; k < pop.size(); ++k) {
        const char c = causes ? (*causes)[k] : 0;
        if (pop.alive[k] && !c) continue;
        const Species& s = species[pop.species[k]];
        // A cut tree always leaves its stump (every cut tree reaches breast height).
        const bool cut = static_cast<DeathCause>(c) == DeathCause::harvest;
        if (!enters_dead_wood(s) || (!cut && pop.dbh_m[k] < m_opt.min_dbh_m)) continue;
        const double mass =
            allometric_mass ? allometry::stem_mass_kg(s, pop.dbh_m[k]) : pop.wood_kg[k];
        if (!(mass > 0)) continue;
        const auto cause = static_cast<DeathCause>(c);
        if (cut)
            add_cut(pop, k, mass, year);
        else if (cause == DeathCause::wind_uprooted || cause == DeathCause::wind_broken)
            add_wind(s, pop, k, cause, mass, year);
        else
            add(s, pop, k, c ? static_cast<DeathCause>(c) : DeathCause::starvation, mass, year);
    }
}

void DeadWood::add(const Species& s, const Population& pop, std::size_t k, DeathCause cause,
                   double mass_kg, int year) {
    DeadStem d = from_tree(pop, k, cause, year);
    d.length_m = d.tree_height_m;
    d.mass0_kg = d.mass_kg = mass_kg;
    // Each snag's fall year uniform over the span's years after its death: the cohort's standing
    // share falls by 1/span a year, linearly, as FFE's.
    d.year_falls = fall_year(s, d.dbh_m, year);
    m_sums.input_kg += mass_kg;
    m_sums.new_snags += 1;
    m_pieces.push_back(d);
}

std::int32_t DeadWood::fall_year(const Species& s, double dbh_m, int year) {
    return year + 1 +
           static_cast<std::int32_t>(
               std::floor(m_rng.uniform() * deadwood::snag_fall_span_yr(s, dbh_m)));
}

void DeadWood::add_cut(const Population& pop, std::size_t k, double mass_kg, int year) {
    const DeadStem d = from_tree(pop, k, DeathCause::harvest, year);
    const double h = d.tree_height_m;
    const double z_stump = std::min(m_opt.stump_height_m, h);
    const double z_top = std::max(deadwood::top_start_m(d.dbh_m, h), z_stump);
    const double stump_kg = mass_kg * deadwood::stem_volume_fraction_below(h, z_stump);
    const double slash_kg = mass_kg * (1 - deadwood::stem_volume_fraction_below(h, z_top));
    // The felling direction: one draw, any direction.
    const double az = 2 * std::numbers::pi * m_rng.uniform();
    if (stump_kg > 0) {
        DeadStem stump = d;
        stump.piece = static_cast<std::uint8_t>(PieceKind::stump);
        stump.length_m = z_stump;
        stump.mass0_kg = stump.mass_kg = stump_kg;
        stump.year_falls = std::numeric_limits<std::int32_t>::max(); // stumps do not fall
        m_pieces.push_back(stump);
        m_sums.input_kg += stump_kg;
        m_sums.cut_kept_kg += stump_kg;
    }
    if (slash_kg > 0 && h > z_top) {
        m_pieces.push_back(lying_top(d, z_top, az, slash_kg, year));
        m_sums.input_kg += slash_kg;
        m_sums.cut_kept_kg += slash_kg;
    }
}

void DeadWood::add_wind(const Species& s, const Population& pop, std::size_t k, DeathCause cause,
                        double mass_kg, int year) {
    const DeadStem d = from_tree(pop, k, cause, year);
    const double h = d.tree_height_m;
    const double az =
        deadwood::wrap_azimuth(m_storm_to_az + (m_rng.uniform() - 0.5) * kWindSpreadRad);
    m_sums.input_kg += mass_kg;
    if (cause == DeathCause::wind_uprooted) {
        DeadStem log = d;
        log.standing = 0;
        log.length_m = h;
        log.azimuth_rad = az;
        log.mass0_kg = log.mass_kg = mass_kg;
        log.year_falls = log.year_down = year;
        m_pieces.push_back(log);
        DeadStem plate = d;
        plate.piece = static_cast<std::uint8_t>(PieceKind::root_plate);
        plate.standing = 0;
        plate.length_m = root_plate_thickness_m(d.dbh_m);
        // The plate tips up on the windward side.
        plate.azimuth_rad = deadwood::wrap_azimuth(az + std::numbers::pi);
        plate.year_falls = plate.year_down = year;
        m_pieces.push_back(plate);
        return;
    }
    // Broken: the height below which half the stem's mass lies (the taper is monotone).
    double lo = 0, hi = h;
    for (int it = 0; it < 60; ++it) {
        const double mid = 0.5 * (lo + hi);
        (deadwood::stem_volume_fraction_below(h, mid) < kSnapMassFraction ? lo : hi) = mid;
    }
    const double z = 0.5 * (lo + hi);
    DeadStem snag = d;
    snag.piece = static_cast<std::uint8_t>(PieceKind::snapped);
    snag.length_m = z;
    snag.mass0_kg = snag.mass_kg = kSnapMassFraction * mass_kg;
    snag.year_falls = fall_year(s, d.dbh_m, year);
    m_pieces.push_back(snag);
    m_sums.new_snags += 1;
    m_pieces.push_back(lying_top(d, z, az, (1 - kSnapMassFraction) * mass_kg, year));
}

void DeadWood::fall(DeadStem& d, const RasterD& dem, int year) {
    d.standing = 0;
    d.year_down = year;
    d.azimuth_rad = deadwood::fall_azimuth_rad(dem, d.x_m, d.y_m, m_rng);
    m_sums.snags_fallen += 1;
}

void DeadWood::step_year(const std::vector<Species>& species, const RasterD& dem, int year) {
    std::size_t out = 0;
    for (std::size_t k = 0; k < m_pieces.size(); ++k) {
        DeadStem d = m_pieces[k];
        if (d.year_died < year && d.piece == static_cast<std::uint8_t>(PieceKind::root_plate)) {
            // No wood: the plate stands until a log of its species would be gone.
            const double rate = species[d.species].deadwood_decay_rate_per_yr;
            if (rate > 0 && (year - d.year_died) * rate >= -std::log(m_opt.removal_mass_fraction)) {
                m_sums.pieces_gone += 1;
                continue;
            }
        } else if (d.year_died < year) {
            const Species& s = species[d.species];
            const double rate =
                d.standing ? s.snag_decay_rate_per_yr : s.deadwood_decay_rate_per_yr;
            const double left = d.mass_kg * std::exp(-rate);
            m_sums.decay_kg += d.mass_kg - left;
            d.mass_kg = left;
            const bool snapped = d.piece == static_cast<std::uint8_t>(PieceKind::snapped);
            if (d.standing && (d.piece == static_cast<std::uint8_t>(PieceKind::stem) || snapped)) {
                const double h = deadwood::snag_height_m(d.dbh_m, d.tree_height_m,
                                                         deadwood::decay_class(left / d.mass0_kg));
                d.length_m = snapped ? std::min(d.length_m, h) : h;
                if (year >= d.year_falls) fall(d, dem, year);
            }
            if (d.mass_kg < m_opt.removal_mass_fraction * d.mass0_kg) {
                m_sums.decay_kg += d.mass_kg; // the rest decays in its last year
                m_sums.pieces_gone += 1;
                continue;
            }
        }
        m_pieces[out++] = d;
    }
    m_pieces.resize(out);
}

void DeadWood::save(ArchiveWriter& a) const {
    a.put(kStateVersion);
    a.put(m_rng.state());
    a.put_vector(m_pieces);
    a.put(m_sums);
}

void DeadWood::load(ArchiveReader& a) {
    const auto v = a.get<std::uint32_t>();
    if (v != kStateVersion && v != 1)
        throw CheckpointError("checkpoint section 'deadwood' has state version " +
                              std::to_string(v) + ", this ecoterra reads version " +
                              std::to_string(kStateVersion));
    m_rng.set_state(a.get<std::array<std::uint64_t, 4>>());
    if (v == 1) {
        m_pieces.clear();
        for (const DeadStemV1& o : a.get_vector<DeadStemV1>()) {
            DeadStem d;
            d.x_m = o.x_m, d.y_m = o.y_m, d.z_m = o.z_m, d.dbh_m = o.dbh_m;
            d.tree_height_m = o.tree_height_m, d.length_m = o.length_m;
            d.azimuth_rad = o.azimuth_rad, d.mass0_kg = o.mass0_kg, d.mass_kg = o.mass_kg;
            d.id = o.id, d.year_died = o.year_died, d.year_falls = o.year_falls;
            d.year_down = o.year_down, d.species = o.species, d.cause = o.cause;
            d.standing = o.standing;
            m_pieces.push_back(d);
        }
        const auto [input, decay, snags, fallen, gone] =
            a.get<std::array<double, 5>>(); // version 1's sums, without the harvest
        m_sums = DeadWoodSums{input, decay, 0, snags, fallen, gone};
        return;
    }
    m_pieces = a.get_vector<DeadStem>();
    m_sums = a.get<DeadWoodSums>();
}

DeadWoodMetrics deadwood_metrics(const DeadWood& dw, const std::vector<Species>& species,
                                 double area_m2) {
    DeadWoodMetrics m;
    const double per_ha = 1e4 / area_m2;
    for (const auto& d : dw.pieces()) {
        if (d.piece == static_cast<std::uint8_t>(PieceKind::root_plate)) {
            m.root_plates_per_ha += per_ha;
            continue;
        }
        const double v = deadwood::volume_m3(species[d.species], d) * per_ha;
        const bool stump = d.piece == static_cast<std::uint8_t>(PieceKind::stump);
        (stump ? m.stumps_per_ha : d.standing ? m.snags_per_ha : m.logs_per_ha) += per_ha;
        (stump        ? m.stump_volume_m3_per_ha
         : d.standing ? m.snag_volume_m3_per_ha
                      : m.log_volume_m3_per_ha) += v;
        m.volume_by_class_m3_per_ha[static_cast<std::size_t>(
            deadwood::decay_class(d.mass_kg / d.mass0_kg) - 1)] += v;
        m.stock_kg += d.mass_kg;
    }
    return m;
}

} // namespace ecoterra::eco
