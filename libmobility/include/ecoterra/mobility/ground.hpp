#pragma once
// The ground under the wheels (docs/mobility.md s9): what a cell's soil strength and standing
// water do to a wheeled vehicle.
//
//  - NO-GO where the rating cone index RCI is below the vehicle's VCI1 (FM 5-430-00-1's one-pass
//    rule; vehicles inside the mobility-index regressions only), or where standing water is
//    deeper than the vehicle's fording depth.
//  - Soft soil: Brixius's (1987, ASAE 87-1622) mobility number Bn = (CI b d / W) (1 + 5 delta/h)
//    / (1 + 3 b/d) of one wheel (load W = weight / wheels, tyre width b, diameter d, the nominal
//    deflection delta/h = 0.15 of the VCI regressions) gives the soil's motion resistance 1/Bn
//    (added to the vehicle's own rolling resistance, which stands for Brixius's constant 0.04) and
//    the largest net traction over slip, NT_max = max_s [GT(s) - MR(s)] with GT = 0.88 (1 -
//    e^(-0.1 Bn)) (1 - e^(-7.5 s)) + 0.04 and MR = 1/Bn + 0.04 + 0.5 s / sqrt(Bn) (bias-ply
//    tyres). The tractive force is capped at (NT_max + rolling + 1/Bn) x weight, so that what is
//    left after the rolling and soil resistance is NT_max x weight; NT_max <= 0 is NO-GO. CI is
//    taken as the rating cone index (RCI = CI x RI <= CI: on the safe side for remoulding soils).
//  - Slippery: a fine-grained soil (silt + clay >= 50 %, the USCS's fine-grained class, ASTM
//    D2487) with RCI <= 50 psi is slippery (NRMM's wet-slippery rule, Mason & Baylot) and its
//    traction coefficient is halved (surface saturation costs more than 50 % of the traction,
//    ibid.).
#include "ecoterra/mobility/vehicle.hpp"
#include "ecoterra/raster.hpp"
#include "ecoterra/units.hpp"

#include <cstdint>
#include <limits>
#include <string>
#include <utility>

namespace ecoterra::mobility {

/// Tyre deflection over section height of the VCI regressions and of Bn here.
inline constexpr double kNominalDeflection = 0.15;
/// A fine-grained soil at or below this rating cone index is slippery (50 psi), kPa.
inline constexpr double kSlipperyRciKpa = 50 * kKpaPerPsi;
/// The share of the traction coefficient a slippery soil leaves.
inline constexpr double kSlipperyTractionFactor = 0.5;
/// The silt + clay share from which a soil is fine-grained, %.
inline constexpr double kFineGrainedPct = 50;

/// Brixius's mobility number of one of the vehicle's wheels on soil of cone index `ci_kpa`.
double brixius_mobility_number(const Vehicle& v, double ci_kpa);
/// Brixius's gross traction and motion-resistance ratios at mobility number bn and slip s.
double brixius_gross_traction(double bn, double slip);
double brixius_motion_resistance(double bn, double slip);
/// The largest net traction ratio GT - MR over slip in (0, 1], and the slip that gives it.
std::pair<double, double> brixius_max_net_traction(double bn);

/// What limits a vehicle in a cell (the mobility map's limiting factor; docs/mobility.md s10).
enum class Limit : std::uint8_t {
    none = 0, ///< nothing: the vehicle's own power, drag and top speed
    slope = 1,
    soil = 2,
    vegetation = 3, ///< stems pushed over or too thick to pass (trees, shrubs, snags)
    water = 4,      ///< standing water deeper than the fording depth
    obstacle = 5,   ///< logs, root plates and rigid objects
    nodata = 255,   ///< off the terrain
};
/// "none", "slope", ... as in the map's legend and summary.
const char* limit_name(Limit l);

/// One cell's ground: its rating cone index (NaN: firm, not modelled), standing water and
/// whether its soil is fine-grained.
struct GroundCell {
    double rci_kpa = std::numeric_limits<double>::quiet_NaN();
    double water_depth_m = 0;
    bool fine_grained = false;
};

/// What the ground does to the vehicle.
struct GroundEffect {
    Limit nogo = Limit::none;        ///< soil or water when the vehicle cannot cross
    std::string why;                 ///< the reason of a NO-GO, with the numbers
    double soil_resistance = 0;      ///< the soil's motion resistance 1/Bn, fraction of the weight
    double traction_coefficient = 0; ///< the tractive force's cap, fraction of the weight
    bool slippery = false;
    bool go() const { return nogo == Limit::none; }
};

/// A vehicle's constants against the ground, computed once.
class VehicleGround {
public:
    explicit VehicleGround(const Vehicle& v);
    /// VCI1, kPa; NaN for a vehicle outside the mobility-index regressions.
    double vci1_kpa() const { return m_vci1_kpa; }
    double fording_depth_m() const { return m_fording_m; }
    GroundEffect effect(const GroundCell& c) const;

private:
    const Vehicle* m_v;
    double m_vci1_kpa, m_fording_m;
};

/// The ground's rasters on the terrain's (hydrology) grid; each may be missing.
struct GroundMaps {
    const RasterD* rci_kpa = nullptr;       ///< rating cone index, kPa
    const RasterD* water_depth_m = nullptr; ///< standing water, m
    const RasterU8* fine_grained = nullptr; ///< 1 where silt + clay >= 50 %
    bool empty() const { return !rci_kpa && !water_depth_m; }
    /// The cell under (x, y); off the rasters: firm, dry ground.
    GroundCell at(double x_m, double y_m) const;
};

/// The resistance on a grade (rise over run along the path) on this ground: rolling, grade and the
/// soil's motion resistance, N.
double resistance_n(const Vehicle& v, double grade, const GroundEffect& g);

/// 1 where a cell's silt + clay is at least kFineGrainedPct (rasters of percent, any type).
template <class R>
RasterU8 fine_grained_mask(const R& silt_pct, const R& clay_pct) {
    RasterU8 m(silt_pct.grid(), 0);
    for (int j = 0; j < m.ny(); ++j)
        for (int i = 0; i < m.nx(); ++i)
            m(i, j) = silt_pct(i, j) + clay_pct(i, j) >= kFineGrainedPct ? 1 : 0;
    return m;
}

} // namespace ecoterra::mobility
