#include "ecoterra/mobility/traverse.hpp"

#include "ecoterra/csv.hpp"
#include "ecoterra/error.hpp"
#include "stats.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace ecoterra::mobility {

namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;
/// Points sampled along the belly, between the axles.
constexpr int kBellySamples = 5;
/// Points across a tyre's width where its envelope is taken.
constexpr int kTyreWidthSamples = 3;
/// Rim samples on either side of a wheel's bottom, evenly in angle to kRimMaxRad.
constexpr int kRimSamples = 17;
constexpr double kRimMaxRad = 85.0 * std::numbers::pi / 180;
/// The climb is checked at least this often, as a fraction of the terrain's cell (a wheel meets
/// a step's edge at its steepest only for an instant).
constexpr double kClimbStepOfCell = 0.2;

struct Pose {
    double z_m = 0, pitch_rad = 0, roll_rad = 0;
    bool belly_touches = false;
    /// The steepest face (rise over run, against the chassis) the chassis's lower front edge
    /// meets; 0 where it meets none.
    double bumper_face_slope = 0;
    /// The mean over the wheels (each carrying a quarter of the weight) of tan(phi), phi the
    /// angle from the vertical at which the ground pushes back on the wheel.
    double push_slope = 0;
};

} // namespace

std::vector<MissionLine> read_missions_csv(const std::filesystem::path& path) {
    CsvReader csv(path, "missions file");
    const std::vector<std::string> names = {"id", "start_x_m", "start_y_m", "goal_x_m", "goal_y_m"};
    std::vector<int> col;
    for (const auto& n : names) col.push_back(csv.require(n));
    std::vector<MissionLine> out;
    while (csv.next()) {
        double v[5];
        for (std::size_t k = 0; k < names.size(); ++k) v[k] = csv.number(col[k], names[k]);
        out.push_back({static_cast<int>(v[0]), v[1], v[2], v[3], v[4]});
    }
    return out;
}

namespace {

/// The quasi-static pose of the vehicle along a mission: four wheel contacts on the heightmap.
class PoseSampler {
public:
    PoseSampler(const Vehicle& v, const RasterD& dem, const MissionLine& m, double length)
        : m_v(v), m_dem(dem), m_m(m), m_ux((m.goal_x_m - m.start_x_m) / length),
          m_uy((m.goal_y_m - m.start_y_m) / length) {}
    /// The pose with the vehicle's centre `s` m along the mission.
    Pose at(double s) const;
    /// The mean over the four wheels of tan(phi) with the vehicle's centre `s` m along (the
    /// tyres' centre lines only: the climb is checked more often than the pose is taken).
    double push_slope(double s) const;

private:
    double height(double x, double y) const {
        const double z = m_dem.sample_bilinear(x, y);
        if (std::isnan(z))
            throw InputError("mission " + std::to_string(m_m.id) + " leaves the terrain at (" +
                             format_number(x) + ", " + format_number(y) + ")");
        return z;
    }
    /// The height of the bottom of a wheel centred over (x, y), heading (ux, uy), m, and in
    /// `push` tan(phi) of its contact; `widths` points across the tyre.
    double wheel(double x, double y, double ux, double uy, double& push,
                 int widths = kTyreWidthSamples) const;
    const Vehicle& m_v;
    const RasterD& m_dem;
    const MissionLine& m_m;
    double m_ux, m_uy; ///< forward; left is (-uy, ux)
};

double PoseSampler::wheel(double x, double y, double ux, double uy, double& push,
                          int widths) const {
    // The rolling circle's envelope: the lowest the wheel's bottom can be with its rim above the
    // ground everywhere along its chord and across its width (a wheel bridges pits narrower than
    // its chord and rides up a step before its axle is over it).
    const double r = m_v.wheel_radius_m, b = m_v.tyre_width_m, nx = -uy, ny = ux;
    double top = -std::numeric_limits<double>::infinity(), contact = 0;
    // The rim sampled evenly in angle (the contact's angle decides the force), to 85 deg either
    // side of the bottom.
    for (int a = -kRimSamples; a <= kRimSamples; ++a) {
        const double phi = kRimMaxRad * a / kRimSamples;
        const double t = r * std::sin(phi), rise = r - r * std::cos(phi);
        for (int w = 0; w < widths; ++w) {
            const double o = widths == 1 ? 0.0 : b * (w / (widths - 1.0) - 0.5);
            const double z = height(x + t * ux + o * nx, y + t * uy + o * ny) - rise;
            // The contact: the highest; among equals, the nearest below the axle.
            if (z > top + 1e-12 || (z > top - 1e-12 && std::abs(t) < std::abs(contact)))
                top = z, contact = t;
        }
    }
    // The contact t ahead of the axle pushes back at the angle phi from the vertical, sin(phi) =
    // t/r: rolling the wheel up takes tan(phi) times its load (a plane's grade; a step's edge).
    const double c = std::clamp(contact, -0.999 * r, 0.999 * r);
    push = c / std::sqrt(r * r - c * c);
    return top;
}

double PoseSampler::push_slope(double s) const {
    const double ux = m_ux, uy = m_uy, nx = -uy, ny = ux;
    const double half_l = 0.5 * m_v.wheelbase_m, half_t = 0.5 * m_v.track_m;
    const double cx = m_m.start_x_m + s * ux, cy = m_m.start_y_m + s * uy;
    double sum = 0, push = 0;
    for (const double a : {half_l, -half_l})
        for (const double o : {half_t, -half_t}) {
            wheel(cx + a * ux + o * nx, cy + a * uy + o * ny, ux, uy, push, 1);
            sum += push;
        }
    return 0.25 * sum;
}

Pose PoseSampler::at(double s) const {
    const double ux = m_ux, uy = m_uy, nx = -uy, ny = ux;
    const double half_l = 0.5 * m_v.wheelbase_m, half_t = 0.5 * m_v.track_m;
    const double cx = m_m.start_x_m + s * ux, cy = m_m.start_y_m + s * uy;
    double push[4];
    const double fl =
        wheel(cx + half_l * ux + half_t * nx, cy + half_l * uy + half_t * ny, ux, uy, push[0]);
    const double fr =
        wheel(cx + half_l * ux - half_t * nx, cy + half_l * uy - half_t * ny, ux, uy, push[1]);
    const double rl =
        wheel(cx - half_l * ux + half_t * nx, cy - half_l * uy + half_t * ny, ux, uy, push[2]);
    const double rr =
        wheel(cx - half_l * ux - half_t * nx, cy - half_l * uy - half_t * ny, ux, uy, push[3]);
    Pose p;
    p.z_m = 0.25 * (fl + fr + rl + rr);
    p.push_slope = 0.25 * (push[0] + push[1] + push[2] + push[3]);
    p.pitch_rad = std::atan2(0.5 * (fl + fr - rl - rr), m_v.wheelbase_m);
    p.roll_rad = std::atan2(0.5 * (fl + rl - fr - rr), m_v.track_m);
    const double slope = 0.5 * (fl + fr - rl - rr) / m_v.wheelbase_m;
    // The belly: the centre line between the axles against the contact plane there.
    for (int k = 0; k < kBellySamples && !p.belly_touches; ++k) {
        const double t = -half_l + (k + 0.5) * m_v.wheelbase_m / kBellySamples;
        const double plane = p.z_m + t * slope;
        p.belly_touches = height(cx + t * ux, cy + t * uy) > plane + m_v.ground_clearance_m;
    }
    // The chassis's lower front edge: the overhang ahead of the front wheels' rims at the
    // clearance's height; where the ground rises above it, the face it meets.
    const double overhang = 0.5 * (m_v.length_m - m_v.wheelbase_m);
    const double d = 0.5 * m_dem.grid().cell_size_m;
    for (int k = 1; k <= 2 && overhang > m_v.wheel_radius_m; ++k) {
        const double t = half_l + m_v.wheel_radius_m + (overhang - m_v.wheel_radius_m) * k / 2;
        for (const double o : {-half_t, 0.0, half_t}) {
            const double x = cx + t * ux + o * nx, y = cy + t * uy + o * ny;
            if (height(x, y) <= p.z_m + t * slope + m_v.ground_clearance_m) continue;
            const double face =
                (height(x + d * ux, y + d * uy) - height(x - d * ux, y - d * uy)) / (2 * d) - slope;
            p.bumper_face_slope = std::max(p.bumper_face_slope, face);
        }
    }
    return p;
}

/// Why a pose ends the mission (nullptr: it does not).
const char* failure_of(const Pose& p, const Vehicle& v, double tip_rad, double traction) {
    if (std::abs(p.pitch_rad) > tip_rad || std::abs(p.roll_rad) > tip_rad) return "tip-over";
    if (p.pitch_rad > v.max_climb_deg / kDegPerRad) return "climb limit";
    if (std::abs(p.roll_rad) > v.max_side_slope_deg / kDegPerRad) return "side-slope limit";
    if (p.belly_touches) return "high-centred";
    // The chassis's lower front edge on a face it cannot slide up (steeper than 1/mu).
    if (p.bumper_face_slope > 1 / traction) return "bumper";
    return nullptr;
}

/// The traction-limited climb (docs/mobility.md s6), quasi-static: the force that rolls the wheels
/// up their contacts (a quarter of the weight times tan(phi) at each: a plane's grade, or a step's
/// edge, steepest at first contact) plus the rolling and soil resistance, against the tractive
/// force the ground lets the wheels give. More needed than given: the vehicle stalls, and from
/// rest, as paper 000's "stuck" (less than 0.2 m in 30 s) finds it, momentum cannot help.
class Climb {
public:
    Climb(const Vehicle& v, double speed, const GroundMaps& ground)
        : m_v(v), m_ground(ground), m_vg(v), m_speed(speed) {}
    /// The traction coefficient of the ground at `at`, or the reason it stops the vehicle.
    const char* ground(Point at, GroundEffect& g) const {
        g = m_vg.effect(m_ground.at(at.x_m, at.y_m)); // without maps: firm, dry ground
        if (g.nogo == Limit::water) return "water";
        return g.go() ? nullptr : "stuck (soil)";
    }
    /// With the wheels' mean tan(phi) `push` and the pitch on ground `g`: "stuck" where it
    /// stalls, or nullptr.
    const char* step(double push, double pitch, const GroundEffect& g) const {
        const double w = m_v.weight_n(), cos_p = std::cos(pitch);
        const double need = w * cos_p * (push + m_v.rolling_resistance + g.soil_resistance);
        const double give = std::min(m_v.tractive_force_at(m_speed, g.traction_coefficient),
                                     g.traction_coefficient * w * cos_p);
        return need > give ? "stuck" : nullptr;
    }

private:
    const Vehicle& m_v;
    const GroundMaps& m_ground;
    VehicleGround m_vg;
    double m_speed;
};

/// RMS vertical acceleration (second differences of z) and pitch and roll rates of the poses,
/// `dt` s apart.
void pose_statistics(const std::vector<Pose>& poses, double dt, TraverseResult& r) {
    double az2 = 0, pr2 = 0, rr2 = 0;
    std::size_t na = 0, nr = 0;
    for (std::size_t k = 1; k < poses.size(); ++k) {
        const double pitch_rate = (poses[k].pitch_rad - poses[k - 1].pitch_rad) / dt * kDegPerRad;
        const double roll_rate = (poses[k].roll_rad - poses[k - 1].roll_rad) / dt * kDegPerRad;
        pr2 += pitch_rate * pitch_rate;
        rr2 += roll_rate * roll_rate;
        ++nr;
        if (k + 1 < poses.size()) {
            const double a = (poses[k + 1].z_m - 2 * poses[k].z_m + poses[k - 1].z_m) / (dt * dt);
            az2 += a * a;
            ++na;
        }
    }
    r.rms_vertical_acceleration_m_per_s2 = na ? std::sqrt(az2 / static_cast<double>(na)) : 0.0;
    r.rms_pitch_rate_deg_per_s = nr ? std::sqrt(pr2 / static_cast<double>(nr)) : 0.0;
    r.rms_roll_rate_deg_per_s = nr ? std::sqrt(rr2 / static_cast<double>(nr)) : 0.0;
}

} // namespace

TraverseResult traverse(const Vehicle& v, const RasterD& dem, const MissionLine& m,
                        const TraverseOptions& opt) {
    TraverseResult r;
    r.id = m.id;
    const double dx = m.goal_x_m - m.start_x_m, dy = m.goal_y_m - m.start_y_m;
    const double length = std::hypot(dx, dy);
    if (!(length > 0)) throw InputError("mission " + std::to_string(m.id) + " has no length");
    const double speed = opt.speed_m_per_s > 0 ? opt.speed_m_per_s : v.top_speed_m_per_s;
    if (!(opt.dt_s > 0)) throw InputError("the pose interval must be > 0 s");
    const PoseSampler pose(v, dem, m, length);
    const double cell = dem.grid().cell_size_m;
    const double step = speed * opt.dt_s;
    const int n = static_cast<int>(std::floor(length / step + 1e-9));
    const double tip = std::min(v.tip_over_deg, opt.tip_over_limit_deg) / kDegPerRad;
    std::vector<Pose> poses;
    Climb climb(v, speed, opt.ground);
    for (int k = 0; k <= n; ++k) {
        const double s = std::min(k * step, length);
        const Pose p = pose.at(s);
        r.max_abs_pitch_deg = std::max(r.max_abs_pitch_deg, std::abs(p.pitch_rad) * kDegPerRad);
        r.max_abs_roll_deg = std::max(r.max_abs_roll_deg, std::abs(p.roll_rad) * kDegPerRad);
        GroundEffect g;
        const char* why =
            climb.ground({m.start_x_m + s * dx / length, m.start_y_m + s * dy / length}, g);
        if (!why) why = failure_of(p, v, tip, g.traction_coefficient);
        // The climb between this pose and the next, checked every fifth of a cell.
        const double next = std::min((k + 1) * step, length);
        const int sub =
            k < n ? std::max(1, static_cast<int>(std::ceil((next - s) / (kClimbStepOfCell * cell))))
                  : 1;
        for (int q = 0; q < sub && !why; ++q) {
            const double at = s + (next - s) * q / sub;
            why = climb.step(q == 0 ? p.push_slope : pose.push_slope(at), p.pitch_rad, g);
            if (why) r.failed_at_m = at;
        }
        if (why) {
            r.failure = why;
            if (std::string(why) != "stuck") r.failed_at_m = s;
            return r;
        }
        poses.push_back(p);
    }
    r.success = true;
    r.distance_m = length;
    r.time_s = length / speed;
    pose_statistics(poses, opt.dt_s, r);
    return r;
}

TraverseReport traverse_missions(const Vehicle& v, const RasterD& dem,
                                 const std::vector<MissionLine>& missions,
                                 const TraverseOptions& opt) {
    TraverseReport rep;
    if (missions.empty()) {
        if (!opt.allow_no_missions) throw InputError("no missions to drive");
        constexpr double nan = std::numeric_limits<double>::quiet_NaN();
        rep.success_rate = rep.median_rms_vertical_acceleration_m_per_s2 = nan;
        rep.median_rms_pitch_rate_deg_per_s = rep.median_rms_roll_rate_deg_per_s = nan;
        rep.median_time_s = nan;
        return rep;
    }
    rep.missions = missions;
    std::vector<double> az, pr, rr, tt;
    for (const auto& m : missions) {
        rep.results.push_back(traverse(v, dem, m, opt));
        const auto& r = rep.results.back();
        if (!r.success) continue;
        ++rep.successes;
        az.push_back(r.rms_vertical_acceleration_m_per_s2);
        pr.push_back(r.rms_pitch_rate_deg_per_s);
        rr.push_back(r.rms_roll_rate_deg_per_s);
        tt.push_back(r.time_s);
    }
    rep.success_rate = static_cast<double>(rep.successes) / static_cast<double>(missions.size());
    rep.median_rms_vertical_acceleration_m_per_s2 = detail::quantile(az, 0.5);
    rep.median_rms_pitch_rate_deg_per_s = detail::quantile(pr, 0.5);
    rep.median_rms_roll_rate_deg_per_s = detail::quantile(rr, 0.5);
    rep.median_time_s = detail::quantile(tt, 0.5);
    return rep;
}

nlohmann::json to_json(const TraverseReport& rep, const Vehicle& v) {
    nlohmann::json records = nlohmann::json::array();
    for (std::size_t k = 0; k < rep.results.size(); ++k) {
        const TraverseResult& r = rep.results[k];
        nlohmann::json j = {{"id", r.id},
                            {"success", r.success},
                            {"max_abs_pitch_deg", r.max_abs_pitch_deg},
                            {"max_abs_roll_deg", r.max_abs_roll_deg}};
        if (r.success) {
            j["rms_vertical_acceleration_m_per_s2"] = r.rms_vertical_acceleration_m_per_s2;
            j["rms_pitch_rate_deg_per_s"] = r.rms_pitch_rate_deg_per_s;
            j["rms_roll_rate_deg_per_s"] = r.rms_roll_rate_deg_per_s;
            j["time_s"] = r.time_s;
        } else {
            j["failure"] = r.failure;
            j["failed_at_m"] = r.failed_at_m;
        }
        if (k < rep.missions.size()) {
            const MissionLine& m = rep.missions[k];
            j["start_m"] = {m.start_x_m, m.start_y_m};
            j["goal_m"] = {m.goal_x_m, m.goal_y_m};
        }
        records.push_back(std::move(j));
    }
    return {{"vehicle", to_json(v)},
            {"model", "quasi-static proxy: four wheels resting by their rims on the heightmap, "
                      "pose every 0.05 s at constant speed, traction-limited climb, belly and "
                      "front-edge contact; no dynamics (docs/mobility.md s6)"},
            {"records", std::move(records)}};
}

} // namespace ecoterra::mobility
