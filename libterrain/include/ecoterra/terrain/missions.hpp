#pragma once
// Random straight-line A-to-B missions (Majhor & Bos s2.3): the start is a random cell of the low
// class, the heading uniform in [0, 360) degrees (counter-clockwise from east, +x), the goal lies
// `length_m` away along it; both must be at least `border_m` from the map edge and the goal must be
// low or semi, all on the closed class map. Draws are retried until `count` missions are found;
// a terrain with too little room for them is an error, or, with `allow_fewer`, gets the missions
// found within the attempts (none when it has no low cell inside the border).
#include "ecoterra/raster.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace ecoterra::terrain {

struct MissionOptions {
    int count = 20;
    double length_m = 35.0;
    double border_m = 5.0;
    std::uint64_t seed = 1;
    int max_attempts_per_mission = 10000;
    bool allow_fewer = false; ///< return the missions found instead of failing
    void validate() const;
};

struct Mission {
    int id = 0;
    double start_x_m = 0, start_y_m = 0, goal_x_m = 0, goal_y_m = 0;
    double heading_deg = 0; ///< counter-clockwise from east
    double length_m = 0;
    std::array<double, 3> class_fraction{}; ///< fraction of the path in low, semi, high
    std::string classes_crossed;            ///< e.g. "low|semi|high"
};

/// `closed` picks starts and goals; `classes` (unclosed) measures what the path crosses.
std::vector<Mission> plan_missions(const RasterU8& closed, const RasterU8& classes,
                                   const MissionOptions& opt);

std::string missions_csv(const std::vector<Mission>& missions);

} // namespace ecoterra::terrain
