#pragma once
// Unit conversions and the one forestry convention every layer shares. Inside the code every
// quantity is SI; these turn it into the units of outputs and of the literature.
namespace ecoterra {

inline constexpr double kMmPerM = 1000.0;
inline constexpr double kCmPerM = 100.0;
inline constexpr double kM2PerHa = 1e4;
/// 1 m2/ha of basal area in ft2/acre (10.7639 ft2/m2 / 2.47105 acre/ha).
inline constexpr double kFt2PerAcrePerM2PerHa = 4.356;
/// Breast height, where the trunk diameter (DBH) is measured, m.
inline constexpr double kBreastHeightM = 1.3;
/// 1 psi (lb/in2, the Army's cone-index unit) in kPa.
inline constexpr double kKpaPerPsi = 6.894757;

} // namespace ecoterra
