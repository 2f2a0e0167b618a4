#pragma once
// Rain partitioning into infiltration and runoff (paper 002 s4.2).
//
// Runoff coefficients: C = table[vegetation class][slope class][texture group], a fraction of the
// day's rain that runs off; the rest infiltrates. The table (data/hydro/runoff_coefficients.json)
// is the rational-method table of reference hydrology.md s4.2, standing in for the Mahmoud et al.
// table of the paper, which is not public. A flat cell (slope below flat_slope) has C = 0.
//
// SCS curve number (USDA-SCS 1972, NEH-4; TR-55 1986), as an option:
//   S = 25400 / CN - 254 (mm), Ia = 0.2 S, Q = (P - Ia)^2 / (P - Ia + S) for P > Ia, else 0.
//   Antecedent moisture (Chow et al. 1988): CN_I = 4.2 CN / (10 - 0.058 CN),
//   CN_III = 23 CN / (10 + 0.13 CN).
#include "ecoterra/hydro/soil.hpp"

#include <array>
#include <filesystem>
#include <string>

namespace ecoterra::hydro {

class RunoffTable {
public:
    /// Loads the JSON table; throws InputError naming the file and key.
    static RunoffTable load(const std::filesystem::path& path);
    /// The shipped table (data/hydro/runoff_coefficients.json, or $ECOTERRA_DATA/hydro/...).
    static RunoffTable standard();
    /// C for a vegetation density (0..1), slope (rise/run) and texture.
    double coefficient(double vegetation_density, double slope, Texture t) const;
    std::string source() const { return m_source; }

private:
    std::array<double, 3> m_veg_max{};   // upper density of each vegetation class (low to high)
    std::array<double, 3> m_slope_max{}; // upper slope (fraction) of each slope class
    std::array<int, kTextureCount> m_group{};
    double m_c[3][3][3] = {}; // [vegetation][slope][group]
    std::string m_source;
};

/// SCS curve-number runoff (mm) for P mm of rain at curve number cn (antecedent condition II).
double scs_runoff_mm(double p_mm, double cn);
/// Hydrologic soil group A-D from texture (NEH/Rawls heuristic, reference s3.4): 0..3.
int hydrologic_soil_group(Texture t);
/// TR-55 curve numbers for woods (fair) and fallow bare soil, by group, interpolated by
/// vegetation density.
double curve_number(double vegetation_density, Texture t);

} // namespace ecoterra::hydro
