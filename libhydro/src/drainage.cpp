// Gravity drainage at K(theta) (docs/hydrology.md s4b), in its own translation unit: it is the
// hottest per-cell-day kernel of the default hydrology (a log and an exp for u^m and a log1p and
// an expm1 for the day's fraction, twice a cell-day with the critical layer), and here it runs on
// ecoterra's branch-free fastmath.hpp, in loops the compiler vectorises. CMakeLists.txt compiles
// this file with -fno-trapping-math (so the clamps become selects) and -ffp-contract=off (no FMA:
// every clone below computes the same bits as the scalar drained_theta, on every machine).
#include "ecoterra/fastmath.hpp"
#include "ecoterra/hydro/kernels.hpp"

#include <algorithm>

namespace ecoterra::hydro {
namespace {

/// u1 = (u0^-m + m a dt)^(-1/m) = u0 (1 + r)^(-1/m), a = Ks / (d theta_s), r = m a dt u0^m, m =
/// n - 1: theta1 = theta0 - u0 theta_s (1 - (1 + r)^(-1/m)), the last factor as
/// -expm1(-log1p(r) / m), accurate from r ~ 1e-300 up. Returns theta0 when it is not positive or
/// the soil does not conduct.
inline double drain_one(double theta0, double porosity, double exponent, double ksat_m_per_s,
                        double depth_m, double dt_s) {
    const double u0 = std::min(theta0 / porosity, 1.0);
    const double m = exponent - 1.0;
    const double u_pow_m = fastmath::exp_clamped(m * fastmath::log_positive(std::max(u0, 1e-300)));
    const double r = m * ksat_m_per_s * dt_s / (depth_m * porosity) * u_pow_m;
    const double fraction = -fastmath::expm1_clamped(-fastmath::log1p_positive(r) / m);
    const double theta1 = theta0 - u0 * porosity * fraction;
    return theta0 > 0 && ksat_m_per_s > 0 ? theta1 : theta0;
}

} // namespace

double drained_theta(double theta0, double porosity, double exponent, double ksat_m_per_s,
                     double depth_m, double dt_s) {
    return drain_one(theta0, porosity, exponent, ksat_m_per_s, depth_m, dt_s);
}

// One clone per vector width, chosen once at load time (an ifunc); the same bits from each, as
// the test "[drainage]" checks against the scalar function on this machine's widest clone.
ECOTERRA_CLONES
void drained_theta_cells(std::int64_t n, const double* theta0, const float* porosity,
                         const float* exponent, const float* ksat_m_per_s, double depth_m,
                         double dt_s, double* theta1) {
    for (std::int64_t k = 0; k < n; ++k)
        theta1[k] = drain_one(theta0[k], porosity[k], exponent[k], ksat_m_per_s[k], depth_m, dt_s);
}

} // namespace ecoterra::hydro
