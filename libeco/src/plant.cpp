#include "ecoterra/eco/plant.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace ecoterra::eco::allometry {

namespace {
/// dbh_from_stem_mass: Newton steps at most, and the relative step that ends them.
constexpr int kMaxNewtonSteps = 60;
constexpr double kRelativeStepTolerance = 1e-13;
/// The smallest diameter the relative tolerance is taken of, m.
constexpr double kToleranceFloorM = 1e-6;
/// The first upper bracket when the guess is smaller, m.
constexpr double kFirstBracketM = 1e-4;
/// dbh_from_height_m reads heights at or above Max Height at this share of the curve.
constexpr double kMaxInvertedHeightShare = 1 - 1e-9;
} // namespace

namespace {
/// The height the curve starts from: breast height for trees (D is measured there), the ground
/// for shrubs (D is the stem's at the ground).
double base_height_m(const Species& s) {
    return measured_at_breast_height(s) ? kBreastHeightM : 0;
}
} // namespace

double height_m(const Species& s, double d) {
    if (s.life_form == LifeForm::object) return s.max_height_m;
    const double h0 = base_height_m(s);
    return h0 + (s.max_height_m - h0) * (1.0 - std::exp(-s.height_dbh_slope_per_cm * d * kCmPerM));
}

double dbh_from_height_m(const Species& s, double h) {
    if (s.life_form == LifeForm::object) return object_diameter_m(s);
    const double h0 = base_height_m(s);
    if (!(h > h0)) return 0.0;
    // The curve reaches Max Height only at an infinite diameter: heights at or above it are read
    // at kMaxInvertedHeightShare of the way up.
    const double share = std::min((h - h0) / (s.max_height_m - h0), kMaxInvertedHeightShare);
    const double d = -std::log1p(-share) / (s.height_dbh_slope_per_cm * kCmPerM);
    return s.max_stem_diameter_m > 0 ? std::min(d, s.max_stem_diameter_m) : d;
}

double crown_radius_m(const Species& s, double d) {
    if (s.life_form == LifeForm::object) return 0.5 * s.height_to_diameter_ratio * s.max_height_m;
    const double r = s.crown_radius_coefficient_m * std::pow(d * kCmPerM, s.crown_radius_exponent);
    return std::clamp(r, kMinCrownRadiusM, s.max_crown_radius_m);
}

double leaf_area_m2(const Species& s, double r) {
    if (s.life_form == LifeForm::object) return 0;
    return s.leaf_area_per_crown_area * std::numbers::pi * r * r;
}

double stem_mass_kg(const Species& s, double d) {
    return s.wood_density_kg_per_m3 * kStemFormFactor * 0.25 * std::numbers::pi * d * d *
           height_m(s, d);
}

double dbh_from_stem_mass(const Species& s, double mass, double guess) {
    if (!(mass > 0)) return 0.0;
    // Bracket, then Newton steps kept inside the bracket (M is increasing in D).
    double lo = 0, hi = std::max(guess, kFirstBracketM);
    while (stem_mass_kg(s, hi) < mass) hi *= 2;
    double d = std::clamp(guess, lo, hi);
    const double h0 = base_height_m(s);
    const double c = s.wood_density_kg_per_m3 * kStemFormFactor * 0.25 * std::numbers::pi;
    for (int it = 0; it < kMaxNewtonSteps; ++it) {
        // stem_mass_kg and its slope at d from one exponential (height_m's, in the same order).
        const double e = std::exp(-s.height_dbh_slope_per_cm * d * kCmPerM);
        const double h = s.life_form == LifeForm::object ? s.max_height_m
                                                         : h0 + (s.max_height_m - h0) * (1.0 - e);
        const double m = c * d * d * h - mass;
        if (m > 0)
            hi = d;
        else
            lo = d;
        const double dh = s.height_dbh_slope_per_cm * kCmPerM * (s.max_height_m - h0) * e;
        const double dm = c * (2 * d * h + d * d * dh);
        double next = dm > 0 ? d - m / dm : 0.5 * (lo + hi);
        if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
        if (std::abs(next - d) <= kRelativeStepTolerance * std::max(d, kToleranceFloorM))
            return next;
        d = next;
    }
    return d;
}

Size size(const Species& s, double dbh_m) {
    Size z;
    z.dbh_m = s.life_form == LifeForm::object ? object_diameter_m(s) : dbh_m;
    z.height_m = height_m(s, z.dbh_m);
    z.crown_radius_m = crown_radius_m(s, z.dbh_m);
    z.leaf_area_m2 = leaf_area_m2(s, z.crown_radius_m);
    return z;
}

void apply(const Species& s, Plant& p) {
    const Size z = size(s, p.dbh_m);
    p.dbh_m = z.dbh_m;
    p.height_m = z.height_m;
    p.crown_radius_m = z.crown_radius_m;
    p.leaf_area_m2 = z.leaf_area_m2;
}

double object_diameter_m(const Species& s) {
    return s.height_to_diameter_ratio * s.max_height_m;
}

} // namespace ecoterra::eco::allometry
