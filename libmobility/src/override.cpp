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
    return v.weight_n() * grade / std::sqrt(1 + grade * grade); // W sin(atan(grade))
}

double rolling_resistance_n(const Vehicle& v, double grade) {
    return v.rolling_resistance * v.weight_n() / std::sqrt(1 + grade * grade); // cos(atan)
}

double steady_speed_m_per_s(const Vehicle& v, double resistance_n) {
    return steady_speed_m_per_s(v, resistance_n, v.traction_coefficient);
}

double steady_speed_m_per_s(const Vehicle& v, double resistance_n, double traction) {
    // Net force g(v) = min(F_t(v), mu W) - k v^2 - R. The table is linear between its rows and
    // the traction cap a constant, so g is a concave parabola on each piece between the rows and
    // where the table crosses the cap: from standstill the vehicle speeds up to the first root,
    // the larger root of the piece whose end the net force does not exceed.
    const double cap = traction * v.weight_n(), k = v.drag_n_per_m2_s2, top = v.top_speed_m_per_s;
    const auto& t = v.tractive_force_n;
    auto net = [&](double s) {
        return v.tractive_force_at(s, traction) - k * s * s - resistance_n;
    };
    if (!(net(0.0) > 0)) return 0.0;
    // Pieces [lo, hi] with the force a + b s on each.
    for (std::size_t r = 0; r < t.size(); ++r) {
        const double lo = t[r].first;
        if (lo >= top) break;
        const bool last = r + 1 == t.size();
        const double hi = last ? top : std::min(t[r + 1].first, top);
        const double b0 = last ? 0.0 : (t[r + 1].second - t[r].second) / (t[r + 1].first - lo);
        const double f0 = last ? 0.0 : t[r].second; // beyond the last row the force is 0
        // Split where the table crosses the cap.
        double pieces[3] = {lo, hi, hi};
        if (b0 != 0) {
            const double x = lo + (cap - f0) / b0;
            if (x > lo && x < hi) pieces[1] = x;
        }
        for (int p = 0; p < 2; ++p) {
            const double p0 = pieces[p], p1 = pieces[p + 1];
            if (!(p1 > p0)) continue;
            const double mid = 0.5 * (p0 + p1);
            const bool capped = f0 + b0 * (mid - lo) >= cap;
            const double b = capped ? 0.0 : b0, a = capped ? cap : f0 - b0 * lo;
            // The net force on the piece: -k s^2 + b s + c.
            const double c = a - resistance_n;
            const double g1 = -k * p1 * p1 + b * p1 + c;
            if (g1 > 0) continue;
            double root;
            if (k > 0) {
                root = (b + std::sqrt(std::max(0.0, b * b + 4 * k * c))) / (2 * k);
            } else {
                const double g0 = b * p0 + c;
                root = p0 + (p1 - p0) * g0 / (g0 - g1);
            }
            return std::clamp(root, p0, p1);
        }
    }
    return top;
}

} // namespace ecoterra::mobility
