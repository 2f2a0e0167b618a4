#include "ecoterra/mobility/override.hpp"
#include "ecoterra/units.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace ecoterra::mobility {

namespace {
// MAVS's override law (reference mobility.md s1.2): F = [2 - logistic(5 (d - 2.5))] (a - b h) d^3
// with d and h in cm; the critical diameter uses ten times a and b.
constexpr double kForceA = 10.86;       // N cm^-3
constexpr double kForceB = 0.0534;      // N cm^-4
constexpr double kLogisticSlope = 5.0;  // cm^-1
constexpr double kLogisticCentre = 2.5; // cm
constexpr double kCriticalScale = 10.0; // d_crit: F(d_crit) is about a tenth of the weight
/// Bisection stops when the bracket is narrower than this, m/s.
constexpr double kSpeedTolerance = 1e-9;
} // namespace

double override_force_n(double d_m, double push_height_m) {
    if (!(d_m > 0)) return 0.0;
    const double d = d_m * kCmPerM, h = push_height_m * kCmPerM;
    const double small_stem = 2.0 - 1.0 / (1.0 + std::exp(-kLogisticSlope * (d - kLogisticCentre)));
    return small_stem * std::max(0.0, kForceA - kForceB * h) * d * d * d;
}

double critical_diameter_m(double weight_n, double push_height_m) {
    const double h = push_height_m * kCmPerM;
    const double per_cm3 = kCriticalScale * (kForceA - kForceB * h);
    if (!(per_cm3 > 0)) return std::numeric_limits<double>::infinity();
    return std::cbrt(weight_n / per_cm3) / kCmPerM;
}

double diameter_at_height_m(double dbh_m, double height_m, double h_m) {
    if (!(dbh_m > 0) || !(height_m > kBreastHeightM) || !(h_m < height_m)) return 0.0;
    return dbh_m * (height_m - h_m) / (height_m - kBreastHeightM);
}

double diameter_at_height_from_base_m(double base_m, double height_m, double h_m) {
    if (!(base_m > 0) || !(height_m > 0) || !(h_m < height_m)) return 0.0;
    return base_m * (height_m - std::max(h_m, 0.0)) / height_m;
}

double grade_resistance_n(const Vehicle& v, double grade) {
    return v.weight_n() * std::sin(std::atan(grade));
}

double rolling_resistance_n(const Vehicle& v, double grade) {
    return v.rolling_resistance * v.weight_n() * std::cos(std::atan(grade));
}

double steady_speed_m_per_s(const Vehicle& v, double resistance_n) {
    return steady_speed_m_per_s(v, resistance_n, v.traction_coefficient);
}

double steady_speed_m_per_s(const Vehicle& v, double resistance_n, double traction) {
    // Net force g(v) = F_t(v) - k v^2 - R. Between two rows of the tractive table it is concave
    // (linear minus a parabola), so from standstill the vehicle speeds up to the first root.
    auto net = [&](double s) {
        return v.tractive_force_at(s, traction) - v.drag_n_per_m2_s2 * s * s - resistance_n;
    };
    if (!(net(0.0) > 0)) return 0.0;
    std::vector<double> knots;
    for (const auto& row : v.tractive_force_n)
        if (row.first > 0 && row.first < v.top_speed_m_per_s) knots.push_back(row.first);
    knots.push_back(v.top_speed_m_per_s);
    double lo = 0.0;
    for (const double hi_knot : knots) {
        // Just below a knot the table's value holds (the force drops to 0 after the last row).
        const double hi = hi_knot;
        if (net(hi) > 0 && hi < v.top_speed_m_per_s) {
            lo = hi;
            continue;
        }
        if (net(hi) > 0) return v.top_speed_m_per_s;
        double a = lo, b = hi;
        while (b - a > kSpeedTolerance) {
            const double m = 0.5 * (a + b);
            (net(m) > 0 ? a : b) = m;
        }
        return a;
    }
    return v.top_speed_m_per_s;
}

} // namespace ecoterra::mobility
