#include "ecoterra/mobility/vehicle.hpp"

#include "ecoterra/io/atomic_file.hpp"
#include "ecoterra/json_util.hpp"
#include "ecoterra/units.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

namespace ecoterra::mobility {

namespace {
using nlohmann::json;
constexpr const char* kTableKey = "tractive_force_n";
} // namespace

const ParamCatalog<Vehicle>& vehicle_catalog() {
    using V = Vehicle;
    static const ParamCatalog<V> c(
        "", {text<V>("name", &V::name, "the vehicle's name"),
             text<V>("source", &V::source, "where the numbers come from"),
             number<V>("mass_kg", &V::mass_kg, "kg", 1, 1e6, "mass as driven (gross vehicle mass)")
                 .mandatory(),
             number<V>("width_m", &V::width_m, "m", 0.05, 20, "overall width").mandatory(),
             number<V>("length_m", &V::length_m, "m", 0.05, 50, "overall length").mandatory(),
             number<V>("wheelbase_m", &V::wheelbase_m, "m", 0.05, 50,
                       "front to rear axle; at most length_m"),
             number<V>("track_m", &V::track_m, "m", 0.05, 20,
                       "left to right wheel centres; at most width_m"),
             number<V>("wheel_radius_m", &V::wheel_radius_m, "m", 0.01, 5, "loaded wheel radius"),
             number<V>("cg_height_m", &V::cg_height_m, "m", 0.01, 10,
                       "centre of mass above the ground"),
             number<V>("push_height_m", &V::push_height_m, "m", 0, 5,
                       "height at which the bumper meets a stem"),
             number<V>("ground_clearance_m", &V::ground_clearance_m, "m", 0, 5,
                       "belly above the wheel-contact plane"),
             number<V>("drag_n_per_m2_s2", &V::drag_n_per_m2_s2, "N s2/m2", 0, 1e4,
                       "aerodynamic drag k of F = k v^2"),
             number<V>("rolling_resistance", &V::rolling_resistance, "1", 0, 1,
                       "rolling and soil resistance as a fraction of the weight"),
             number<V>("traction_coefficient", &V::traction_coefficient, "1", 0.01, 2,
                       "the tractive force is limited to this fraction of the weight"),
             number<V>("top_speed_m_per_s", &V::top_speed_m_per_s, "m/s", 0.01, 200,
                       "governed top speed"),
             number<V>("min_turn_radius_m", &V::min_turn_radius_m, "m", 0, 100,
                       "tightest turn radius (0: turns in place)"),
             number<V>("max_lateral_acceleration_m_per_s2", &V::max_lateral_acceleration_m_per_s2,
                       "m/s2", 0.05, 20, "lateral acceleration allowed in turns: v = sqrt(a R)"),
             number<V>("max_acceleration_m_per_s2", &V::max_acceleration_m_per_s2, "m/s2", 0.05, 20,
                       "speeding up between cells and after turns"),
             number<V>("max_deceleration_m_per_s2", &V::max_deceleration_m_per_s2, "m/s2", 0.05, 20,
                       "braking before turns and slower cells"),
             number<V>("max_climb_deg", &V::max_climb_deg, "deg", 0, 90, "steepest climb"),
             number<V>("max_side_slope_deg", &V::max_side_slope_deg, "deg", 0, 90,
                       "steepest side slope"),
             number<V>("tip_over_deg", &V::tip_over_deg, "deg", 0, 90,
                       "roll or pitch at which the vehicle tips over"),
             number<V>("tyre_width_m", &V::tyre_width_m, "m", 0.01, 3,
                       "tyre section width (the mobility index)"),
             integer<V>("tyres_per_axle", &V::tyres_per_axle, "1", 1, 8, "tyres on each axle"),
             integer<V>("axles", &V::axles, "1", 1, 12, "axles carrying the weight"),
             flag<V>("tyre_chains", &V::tyre_chains,
                     "chains on the tyres (the mobility index's grouser factor 1.05)"),
             flag<V>("manual_transmission", &V::manual_transmission,
                     "a manual gearbox (transmission factor 1.05; automatic and hydraulic 1.00)"),
             optional_number<V>("engine_power_kw", &V::engine_power_kw, "kW", 0.01, 1e5,
                                "engine power (engine factor 1.05 below 10 hp per short ton); "
                                "none: taken as at least that"),
             optional_number<V>("fording_depth_m", &V::fording_depth_m, "m", 0, 10,
                                "deepest standing water crossed; none: the ground clearance "
                                "(the floor, as Polaris's manuals advise)")});
    return c;
}

namespace {
constexpr double kLbPerKg = 2.2046226, kInPerM = 39.370079, kHpPerKw = 1.3410221;
constexpr double kKgPerShortTon = 907.18474;
/// WES's weight factor of an axle load of x kips.
double weight_factor(double x) {
    if (x < 2) return 0.553 * x;
    if (x < 13.5) return 0.033 * x + 1.05;
    if (x < 20) return 0.142 * x - 0.42;
    return 0.278 * x - 3.115;
}
} // namespace

double ConeIndexNeeds::vci1_kpa() const {
    return vci1_psi * kKpaPerPsi;
}
double ConeIndexNeeds::vci50_kpa() const {
    return vci50_psi * kKpaPerPsi;
}

ConeIndexNeeds cone_index_needs(const Vehicle& v) {
    const double w = v.mass_kg * kLbPerKg / v.axles; // axle load, lb
    const double d = 2 * v.wheel_radius_m * kInPerM, b = v.tyre_width_m * kInPerM;
    const double cpf = w / (0.5 * v.tyres_per_axle * d * b); // contact pressure factor, psi
    const double wf = weight_factor(w / 1000);
    const double tef = (10 + b) / 100;
    const double gf = v.tyre_chains ? 1.05 : 1.0;
    const double wlf = w / 2000;
    const double cf = v.ground_clearance_m * kInPerM / 10;
    const double hp_per_ton =
        v.engine_power_kw ? *v.engine_power_kw * kHpPerKw / (v.mass_kg / kKgPerShortTon) : 10.0;
    const double ef = hp_per_ton < 10 ? 1.05 : 1.0;
    const double tf = v.manual_transmission ? 1.05 : 1.0;
    ConeIndexNeeds n;
    n.mobility_index = (cpf * wf / (tef * gf) + wlf - cf) * ef * tf;
    const double mi = n.mobility_index;
    n.calibrated = mi > 0;
    if (!n.calibrated) {
        n.vci1_psi = n.vci50_psi = std::numeric_limits<double>::quiet_NaN();
        return n;
    }
    std::tie(n.vci1_psi, n.vci50_psi) = vci_from_mobility_index(mi);
    return n;
}

std::pair<double, double> vci_from_mobility_index(double mi) {
    if (mi > 115) return {4.1 * std::pow(mi, 0.446), 9 * std::pow(mi, 0.446)};
    return {11.48 + 0.2 * mi - 39.2 / (mi + 3.74), 28.23 + 0.43 * mi - 92.67 / (mi + 3.67)};
}

double Vehicle::tractive_force_at(double v, double traction) const {
    const double limit = traction * weight_n();
    const auto& t = tractive_force_n;
    if (t.empty() || v < 0) return 0.0;
    if (v >= t.back().first) return v == t.back().first ? std::min(t.back().second, limit) : 0.0;
    const auto it = std::upper_bound(t.begin(), t.end(), v,
                                     [](double x, const auto& row) { return x < row.first; });
    const auto& [v1, f1] = *it;
    const auto& [v0, f0] = *(it - 1);
    return std::min(f0 + (f1 - f0) * (v - v0) / (v1 - v0), limit);
}

void Vehicle::validate(const std::string& where) const {
    auto bad = [&](const std::string& what) { throw InputError(where + ": " + what); };
    if (track_m > width_m)
        bad("track_m = " + format_number(track_m) + " exceeds width_m = " + format_number(width_m));
    if (wheelbase_m > length_m)
        bad("wheelbase_m = " + format_number(wheelbase_m) +
            " exceeds length_m = " + format_number(length_m));
    if (tractive_force_n.size() < 2)
        bad(std::string(kTableKey) + ": give at least two rows [speed m/s, force N]");
    if (tractive_force_n.front().first != 0.0)
        bad(std::string(kTableKey) + ": the first row must be at speed 0, got " +
            format_number(tractive_force_n.front().first));
    for (std::size_t k = 0; k < tractive_force_n.size(); ++k) {
        const auto [v, f] = tractive_force_n[k];
        const std::string row = std::string(kTableKey) + " row " + std::to_string(k);
        if (!std::isfinite(v) || !std::isfinite(f) || f < 0)
            bad(row + ": [" + format_number(v) + ", " + format_number(f) +
                "] must be finite with a force >= 0 N");
        if (k > 0 && !(v > tractive_force_n[k - 1].first))
            bad(row + ": speed " + format_number(v) + " m/s does not exceed the row before (" +
                format_number(tractive_force_n[k - 1].first) +
                " m/s); the force must be a function of speed");
    }
    if (!(tractive_force_n.front().second > 0))
        bad(std::string(kTableKey) + ": the force at standstill must be > 0 N");
}

Vehicle parse_vehicle(const json& j, const std::string& source) {
    return with_context(source, [&] {
        if (!j.is_object()) throw InputError("a vehicle file must be a JSON object");
        Vehicle v = vehicle_catalog().read(j, Vehicle{}, {kTableKey});
        for (const auto& k : vehicle_catalog().absent(j))
            if (k == "tyre_width_m" || k == "tyres_per_axle" || k == "axles" ||
                k == "tyre_chains" || k == "manual_transmission" || k == "engine_power_kw")
                v.cone_index_defaults.push_back(k);
        if (!j.contains(kTableKey))
            throw InputError(std::string("missing key '") + kTableKey +
                             "' (rows [speed m/s, tractive force N])");
        const json& t = j.at(kTableKey);
        if (!t.is_array())
            throw InputError(std::string(kTableKey) + " must be an array of [speed, force] rows");
        v.tractive_force_n.clear();
        for (std::size_t k = 0; k < t.size(); ++k) {
            const json& row = t[k];
            if (!row.is_array() || row.size() != 2 || !row[0].is_number() || !row[1].is_number())
                throw InputError(std::string(kTableKey) + " row " + std::to_string(k) + ": " +
                                 row.dump() + " is not [speed m/s, force N]");
            v.tractive_force_n.emplace_back(row[0].get<double>(), row[1].get<double>());
        }
        v.validate("vehicle");
        return v;
    });
}

Vehicle load_vehicle(const std::filesystem::path& path) {
    return parse_vehicle(parse_json(io::read_text(path), path.string()), path.string());
}

json to_json(const Vehicle& v) {
    json j = vehicle_catalog().to_json(v);
    j[kTableKey] = json::array();
    for (const auto& [s, f] : v.tractive_force_n) j[kTableKey].push_back({s, f});
    return j;
}

} // namespace ecoterra::mobility
