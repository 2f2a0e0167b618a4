#include "ecoterra/mobility/ground.hpp"

#include "ecoterra/error.hpp"
#include "ecoterra/mobility/override.hpp"

#include <algorithm>
#include <cmath>

namespace ecoterra::mobility {

namespace {
// Brixius 1987 (bias-ply tyres; reference trafficability.md s4a).
constexpr double kGtScale = 0.88, kGtBn = 0.1, kGtSlip = 7.5, kGtConst = 0.04;
constexpr double kMrConst = 0.04, kMrSlip = 0.5;
constexpr double kBnDeflection = 5, kBnWidth = 3;
} // namespace

double brixius_mobility_number(const Vehicle& v, double ci_kpa) {
    const double wheel_kn = v.weight_n() / (v.axles * v.tyres_per_axle) / 1000;
    const double b = v.tyre_width_m, d = 2 * v.wheel_radius_m;
    return ci_kpa * b * d / wheel_kn * (1 + kBnDeflection * kNominalDeflection) /
           (1 + kBnWidth * b / d);
}

double brixius_gross_traction(double bn, double slip) {
    return kGtScale * (1 - std::exp(-kGtBn * bn)) * (1 - std::exp(-kGtSlip * slip)) + kGtConst;
}

double brixius_motion_resistance(double bn, double slip) {
    return 1 / bn + kMrConst + kMrSlip * slip / std::sqrt(bn);
}

std::pair<double, double> brixius_max_net_traction(double bn) {
    // d(GT - MR)/ds = 0: A k e^(-k s) = 0.5 / sqrt(Bn), A the gross traction's slip amplitude.
    const double amp = kGtScale * (1 - std::exp(-kGtBn * bn));
    const double x = amp * kGtSlip * std::sqrt(bn) / kMrSlip;
    const double s = x > 1 ? std::clamp(std::log(x) / kGtSlip, 1e-6, 1.0) : 1e-6;
    return {brixius_gross_traction(bn, s) - brixius_motion_resistance(bn, s), s};
}

const char* limit_name(Limit l) {
    switch (l) {
    case Limit::none:
        return "none";
    case Limit::slope:
        return "slope";
    case Limit::soil:
        return "soil";
    case Limit::vegetation:
        return "vegetation";
    case Limit::water:
        return "water";
    case Limit::obstacle:
        return "obstacle";
    case Limit::nodata:
        return "nodata";
    }
    return "unknown";
}

VehicleGround::VehicleGround(const Vehicle& v)
    : m_v(&v), m_vci1_kpa(cone_index_needs(v).vci1_kpa()), m_fording_m(v.fording_depth()) {}

GroundEffect VehicleGround::effect(const GroundCell& c) const {
    GroundEffect e;
    e.traction_coefficient = m_v->traction_coefficient;
    if (c.water_depth_m > m_fording_m) {
        e.nogo = Limit::water;
        e.why = "standing water " + format_number(c.water_depth_m) +
                " m deep, over the vehicle's fording depth of " + format_number(m_fording_m) + " m";
        return e;
    }
    if (std::isnan(c.rci_kpa)) return e; // firm ground: the vehicle's own figures
    // The reasons are written only for a NO-GO (formatting numbers costs more than the rest).
    auto rci = [&] { return "rating cone index " + format_number(std::round(c.rci_kpa)) + " kPa"; };
    if (c.rci_kpa < m_vci1_kpa) {
        e.nogo = Limit::soil;
        e.why = "soil too soft: " + rci() + " below the vehicle's VCI1 of " +
                format_number(std::round(m_vci1_kpa)) + " kPa";
        return e;
    }
    const double bn = brixius_mobility_number(*m_v, std::max(c.rci_kpa, 0.0));
    const double nt_max = bn > 0 ? brixius_max_net_traction(bn).first : -1.0;
    if (!(nt_max > 0)) {
        e.nogo = Limit::soil;
        e.why = "soil too soft: " + rci() + " gives no net traction (Brixius mobility number " +
                format_number(bn) + ")";
        return e;
    }
    e.soil_resistance = 1 / bn;
    e.slippery = c.fine_grained && c.rci_kpa <= kSlipperyRciKpa;
    const double mu = m_v->traction_coefficient * (e.slippery ? kSlipperyTractionFactor : 1.0);
    e.traction_coefficient = std::min(mu, nt_max + m_v->rolling_resistance + e.soil_resistance);
    return e;
}

GroundCell GroundMaps::at(double x_m, double y_m) const {
    GroundCell c;
    auto cell = [&](const auto& r) { return r.cell_at(x_m, y_m); };
    if (rci_kpa) {
        const auto [i, j] = cell(*rci_kpa);
        if (i >= 0) c.rci_kpa = (*rci_kpa)(i, j);
    }
    if (water_depth_m) {
        const auto [i, j] = cell(*water_depth_m);
        if (i >= 0 && std::isfinite((*water_depth_m)(i, j)))
            c.water_depth_m = (*water_depth_m)(i, j);
    }
    if (fine_grained) {
        const auto [i, j] = cell(*fine_grained);
        if (i >= 0) c.fine_grained = (*fine_grained)(i, j) != 0;
    }
    return c;
}

double resistance_n(const Vehicle& v, double grade, const GroundEffect& g) {
    return rolling_resistance_n(v, grade) + grade_resistance_n(v, grade) +
           g.soil_resistance * v.weight_n() / std::sqrt(1 + grade * grade);
}

} // namespace ecoterra::mobility
