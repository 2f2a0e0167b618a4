#include "ecoterra/mobility/traverse.hpp"

#include "ecoterra/csv.hpp"
#include "ecoterra/error.hpp"
#include "stats.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace ecoterra::mobility {

namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;
/// Points sampled along the belly, between the axles.
constexpr int kBellySamples = 5;

struct Pose {
    double z_m = 0, pitch_rad = 0, roll_rad = 0;
    bool belly_touches = false;
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

private:
    double height(double x, double y) const {
        const double z = m_dem.sample_bilinear(x, y);
        if (std::isnan(z))
            throw InputError("mission " + std::to_string(m_m.id) + " leaves the terrain at (" +
                             format_number(x) + ", " + format_number(y) + ")");
        return z;
    }
    const Vehicle& m_v;
    const RasterD& m_dem;
    const MissionLine& m_m;
    double m_ux, m_uy; ///< forward; left is (-uy, ux)
};

Pose PoseSampler::at(double s) const {
    const double ux = m_ux, uy = m_uy, nx = -uy, ny = ux;
    const double half_l = 0.5 * m_v.wheelbase_m, half_t = 0.5 * m_v.track_m;
    const double cx = m_m.start_x_m + s * ux, cy = m_m.start_y_m + s * uy;
    const double fl = height(cx + half_l * ux + half_t * nx, cy + half_l * uy + half_t * ny);
    const double fr = height(cx + half_l * ux - half_t * nx, cy + half_l * uy - half_t * ny);
    const double rl = height(cx - half_l * ux + half_t * nx, cy - half_l * uy + half_t * ny);
    const double rr = height(cx - half_l * ux - half_t * nx, cy - half_l * uy - half_t * ny);
    Pose p;
    p.z_m = 0.25 * (fl + fr + rl + rr);
    p.pitch_rad = std::atan2(0.5 * (fl + fr - rl - rr), m_v.wheelbase_m);
    p.roll_rad = std::atan2(0.5 * (fl + rl - fr - rr), m_v.track_m);
    // The belly: the centre line between the axles against the contact plane there.
    for (int k = 0; k < kBellySamples && !p.belly_touches; ++k) {
        const double t = -half_l + (k + 0.5) * m_v.wheelbase_m / kBellySamples;
        const double plane = p.z_m + t * 0.5 * (fl + fr - rl - rr) / m_v.wheelbase_m;
        p.belly_touches = height(cx + t * ux, cy + t * uy) > plane + m_v.ground_clearance_m;
    }
    return p;
}

/// Why a pose ends the mission (nullptr: it does not).
const char* failure_of(const Pose& p, const Vehicle& v, double tip_rad) {
    if (std::abs(p.pitch_rad) > tip_rad || std::abs(p.roll_rad) > tip_rad) return "tip-over";
    if (p.pitch_rad > v.max_climb_deg / kDegPerRad) return "climb limit";
    if (std::abs(p.roll_rad) > v.max_side_slope_deg / kDegPerRad) return "side-slope limit";
    if (p.belly_touches) return "high-centred";
    return nullptr;
}

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
    const double step = speed * opt.dt_s;
    const int n = static_cast<int>(std::floor(length / step + 1e-9));
    const double tip = std::min(v.tip_over_deg, opt.tip_over_limit_deg) / kDegPerRad;
    std::vector<Pose> poses;
    for (int k = 0; k <= n; ++k) {
        const double s = std::min(k * step, length);
        const Pose p = pose.at(s);
        r.max_abs_pitch_deg = std::max(r.max_abs_pitch_deg, std::abs(p.pitch_rad) * kDegPerRad);
        r.max_abs_roll_deg = std::max(r.max_abs_roll_deg, std::abs(p.roll_rad) * kDegPerRad);
        if (const char* why = failure_of(p, v, tip)) {
            r.failure = why;
            r.failed_at_m = s;
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
    if (missions.empty()) throw InputError("no missions to drive");
    TraverseReport rep;
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
    for (const auto& r : rep.results) {
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
        records.push_back(std::move(j));
    }
    return {{"vehicle", to_json(v)},
            {"model", "kinematic proxy: quasi-static four-wheel pose on the heightmap every "
                      "0.05 s at constant speed, no dynamics"},
            {"records", std::move(records)}};
}

} // namespace ecoterra::mobility
