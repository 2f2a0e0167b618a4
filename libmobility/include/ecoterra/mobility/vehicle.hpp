#pragma once
// Vehicle files (docs/mobility.md s1; data/vehicles/*.json): JSON, strict like scenes. Every key
// has a unit, a default and a range in vehicle_catalog(); the tractive-force curve is a table of
// [speed m/s, force N] rows, read and checked by load_vehicle().
#include "ecoterra/catalog.hpp"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace ecoterra::mobility {

inline constexpr double kGravity_m_per_s2 = 9.80665;

struct Vehicle {
    std::string name = "vehicle";
    std::string source; ///< where the numbers come from (free text)
    double mass_kg = 1000;
    double width_m = 1.5;
    double length_m = 3.5;
    double wheelbase_m = 2.7;
    double track_m = 1.3;
    double wheel_radius_m = 0.33;
    double cg_height_m = 0.6;
    double push_height_m = 0.23; ///< height at which the bumper meets a stem
    double ground_clearance_m = 0.25;
    /// Tractive force at the wheels against speed: rows [speed m/s, force N], speeds strictly
    /// increasing from 0, forces >= 0; linear between rows, 0 beyond the last.
    std::vector<std::pair<double, double>> tractive_force_n;
    double drag_n_per_m2_s2 = 0;       ///< aerodynamic drag k of F = k v^2, N s2 m-2
    double rolling_resistance = 0.03;  ///< rolling and soil resistance as a fraction of the weight
    double traction_coefficient = 0.7; ///< tractive force is limited to this x the weight
    double top_speed_m_per_s = 20;
    double min_turn_radius_m = 5;                 ///< tightest turn (0: turns in place)
    double max_lateral_acceleration_m_per_s2 = 3; ///< sets the speed through a turn
    double max_acceleration_m_per_s2 = 2;
    double max_deceleration_m_per_s2 = 4;
    double max_climb_deg = 30;
    double max_side_slope_deg = 25;
    double tip_over_deg = 45;
    // The mobility index's inputs (WES, Priddy 1999; reference trafficability.md s3a).
    double tyre_width_m = 0.25;
    int tyres_per_axle = 2;
    int axles = 2;
    bool tyre_chains = false;
    bool manual_transmission = false;
    std::optional<double> engine_power_kw; ///< none: taken as at least 10 hp per short ton
    /// Deepest standing water the vehicle crosses, m; none: its ground clearance (the floor;
    /// Polaris's manuals: no deeper than the bottom of the footrests).
    std::optional<double> fording_depth_m;
    /// The mobility index's keys the file did not give (they took their defaults), for reports.
    std::vector<std::string> cone_index_defaults;

    double fording_depth() const { return fording_depth_m.value_or(ground_clearance_m); }
    /// Gross vehicle weight, N.
    double weight_n() const { return mass_kg * kGravity_m_per_s2; }
    /// The tractive force at speed v (the table, capped by the traction limit), N.
    double tractive_force_at(double v_m_per_s) const {
        return tractive_force_at(v_m_per_s, traction_coefficient);
    }
    /// The same with the traction limit at `traction` x the weight (a soil's), N.
    double tractive_force_at(double v_m_per_s, double traction) const;
    /// Checks rules across keys; throws InputError naming `where` and the keys.
    void validate(const std::string& where) const;
};

/// The wheeled mobility index and vehicle cone indices (docs/mobility.md s7): WES's formula (Priddy
/// 1999, ERDC TR GL-99-8, pp. 42-43; Kennedy & Rush 1968) in its units (lb, in, psi), and VCI1,
/// VCI50 from it (Priddy & Willoughby 2006, J. Terramech. 43:85; FM 5-430-00-1), at the nominal
/// 15 % tyre deflection. The regressions were fit to military vehicles: a mobility index at or
/// below 0 (a small robot's clearance outweighs its load) is outside them and gives no VCI.
struct ConeIndexNeeds {
    double mobility_index = 0;
    double vci1_psi = 0, vci50_psi = 0; ///< NaN outside the regressions
    bool calibrated = false;
    double vci1_kpa() const;
    double vci50_kpa() const;
};
ConeIndexNeeds cone_index_needs(const Vehicle& v);
/// VCI1 and VCI50, psi, of a wheeled vehicle of mobility index mi > 0 (the regressions above).
std::pair<double, double> vci_from_mobility_index(double mi);

/// The scalar keys of a vehicle file.
const ParamCatalog<Vehicle>& vehicle_catalog();

/// Reads a vehicle from JSON (`source` names the file in errors): unknown keys, missing required
/// keys, values out of range and a tractive-force table that is not a function of speed are
/// InputErrors naming the source, the key and the value.
Vehicle parse_vehicle(const nlohmann::json& j, const std::string& source);
Vehicle load_vehicle(const std::filesystem::path& path);
/// The vehicle as JSON with every key (the form stored in outputs).
nlohmann::json to_json(const Vehicle& v);

} // namespace ecoterra::mobility
