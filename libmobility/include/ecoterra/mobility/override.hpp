#pragma once
// Vegetation override, NRMM-style (docs/mobility.md s2). NRMM's own coefficients are not public;
// the default law is the one MAVS implements (reference mobility.md s1.2), with d the stem diameter
// at the push height in cm and h the push height in cm:
//   F(d, h) = [2 - 1 / (1 + exp(-5 (d - 2.5)))] (10.86 - 0.0534 h) d^3            N
//   d_crit  = (W / (108.6 - 0.534 h))^(1/3)  cm, W the gross vehicle weight in N  (F(d_crit) ~
//   W/10)
// Stems below d_crit are pushed over (their forces add up over a vehicle-width cell); stems at or
// above it are obstacles to avoid. Steady-state speed: the largest v with
//   F_t(v) - k v^2 - R >= 0,  R = rolling + grade + cluster resistance,
// capped by the top speed (STNDMob's steady-state speed condition).
#include "ecoterra/mobility/vehicle.hpp"

namespace ecoterra::mobility {

/// Override force of one stem of diameter `d_m` at the push height, N (MAVS's cubic law).
double override_force_n(double d_m, double push_height_m);
/// The diameter from which a stem is avoided rather than overridden, m (MAVS's critical diameter).
double critical_diameter_m(double weight_n, double push_height_m);
/// Stem diameter at height `h_m` from the diameter at breast height (1.3 m) and the total height,
/// by a linear taper to zero at the top: d(h) = dbh (H - h) / (H - 1.3); 0 for stems that do not
/// reach breast height or `h_m`.
double diameter_at_height_m(double dbh_m, double height_m, double h_m);
/// The same for a shrub from its diameter at the ground: d(h) = d0 (H - h) / H; 0 above its top.
double diameter_at_height_from_base_m(double base_m, double height_m, double h_m);
/// Resistance of a grade (rise over run along the path; negative downhill), N.
double grade_resistance_n(const Vehicle& v, double grade);
/// Rolling and soil resistance on a grade, N.
double rolling_resistance_n(const Vehicle& v, double grade);
/// The steady-state speed against a resistance `resistance_n` (N, besides drag), m/s; 0 when the
/// vehicle cannot move (the force at standstill does not exceed the resistance).
double steady_speed_m_per_s(const Vehicle& v, double resistance_n);
/// The same with the tractive force capped at `traction` x the weight (a soil's, ground.hpp).
double steady_speed_m_per_s(const Vehicle& v, double resistance_n, double traction);

} // namespace ecoterra::mobility
