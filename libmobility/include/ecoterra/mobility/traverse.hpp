#pragma once
// Terrain traversal without a game engine (docs/mobility.md s6): a quasi-static proxy, not a
// physics engine. Along a straight mission the vehicle's pose is taken every `dt` at its speed:
// each wheel rests where its rim clears the heightmap (bilinear) along its chord and across its
// width, pitch and roll from the four, chassis height their mean. A mission fails at the first
// pose whose |pitch| or |roll| passes the tip-over angle (and the paper's 75 degrees), whose pitch
// passes the climb limit, whose |roll| passes the side-slope limit, whose belly touches the ground
// ("high-centred"), whose chassis front edge meets a face it cannot slide up ("bumper"), or where
// rolling the wheels up their contacts takes more than the traction gives ("stuck"; checked every
// fifth of a cell). For a successful mission: the RMS vertical acceleration (second differences of
// the chassis height), the RMS pitch and roll rates (first differences), as Majhor & Bos (paper
// 000) defines them at its 20 Hz, and the traversal time.
#include "ecoterra/mobility/ground.hpp"
#include "ecoterra/mobility/smg.hpp"
#include "ecoterra/mobility/vehicle.hpp"
#include "ecoterra/raster.hpp"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace ecoterra::mobility {

struct MissionLine {
    int id = 0;
    double start_x_m = 0, start_y_m = 0, goal_x_m = 0, goal_y_m = 0;
};

/// Reads missions: CSV with a header naming id, start_x_m, start_y_m, goal_x_m and goal_y_m (the
/// CSV of `ecoterra terrain missions`); errors name the file, the line, the column and the value.
std::vector<MissionLine> read_missions_csv(const std::filesystem::path& path);

struct TraverseOptions {
    double dt_s = 0.05;             ///< pose interval (paper 000 logs at 20 Hz)
    double speed_m_per_s = 0;       ///< 0: the vehicle's top speed
    double tip_over_limit_deg = 75; ///< the paper's criterion, besides the vehicle's own
    GroundMaps ground; ///< soil strength and standing water (ground.hpp); empty: firm and dry
    /// No mission is a report with no figures (NaN) rather than an error (a terrain planned with
    /// MissionOptions::allow_fewer that had no room).
    bool allow_no_missions = false;
};

struct TraverseResult {
    int id = 0;
    bool success = false;
    std::string failure; ///< tip-over, climb limit, side-slope limit, high-centred, bumper, stuck,
                         ///< stuck (soil), water
    double failed_at_m = 0; ///< distance along the mission of the failing pose
    double distance_m = 0, time_s = 0;
    double rms_vertical_acceleration_m_per_s2 = 0;
    double rms_pitch_rate_deg_per_s = 0, rms_roll_rate_deg_per_s = 0;
    double max_abs_pitch_deg = 0, max_abs_roll_deg = 0;
};

/// Drives one mission; InputError when it leaves the terrain (with the vehicle's footprint).
TraverseResult traverse(const Vehicle& v, const RasterD& dem, const MissionLine& m,
                        const TraverseOptions& opt = {});

/// Many missions and their summary; the medians are over the successful missions (as Majhor & Bos
/// (paper 000) reports them), 0 when none succeeds.
struct TraverseReport {
    std::vector<MissionLine> missions; ///< as driven (a record's start and goal, for replays)
    std::vector<TraverseResult> results;
    int successes = 0;
    double success_rate = 0;
    double median_rms_vertical_acceleration_m_per_s2 = 0;
    double median_rms_pitch_rate_deg_per_s = 0, median_rms_roll_rate_deg_per_s = 0;
    double median_time_s = 0;
};
/// Drives every mission (InputError when there is none, unless opt.allow_no_missions).
TraverseReport traverse_missions(const Vehicle& v, const RasterD& dem,
                                 const std::vector<MissionLine>& missions,
                                 const TraverseOptions& opt = {});
/// The report's details: the vehicle, the model's description and one record per mission. The
/// summary figures are the traverse analysis's metrics (analyses::traverse_json writes both).
nlohmann::json to_json(const TraverseReport& r, const Vehicle& v);

} // namespace ecoterra::mobility
