#pragma once
// A run's year replayed day by day (docs/mobility.md s10.2): the run's stored scene is rebuilt, its
// checkpoint loaded when it ends at or before the year before (else the scene starts afresh), the
// years up to it grown, and every day of the year stepped, handing the day's ground to a caller.
// The engine is deterministic, so the days are the run's own days whether the replay starts from
// the checkpoint or from the beginning; nothing is written to the run.
#include "ecoterra/eco/ecosystem.hpp"
#include "ecoterra/mobility/stand.hpp"
#include "ecoterra/raster.hpp"

#include <filesystem>
#include <functional>

namespace ecoterra::run {

/// The stand a vehicle meets during the year (the plants and dead wood at its start: they change
/// at the year's end), the terrain and the fine-grained soils.
struct SeasonStand {
    int year = 0;          ///< the year replayed (1-based)
    int replayed_from = 0; ///< the year end the replay started from (0: the scene's start)
    std::vector<mobility::StandStem> stems; ///< the living (the snags are in `dead`)
    mobility::StandDeadWood dead;
    RasterD dem;
    RasterU8 fine_grained;
};

/// One day of the year: its ground on the terrain's grid and its weather.
struct SeasonDay {
    int day_of_year = 0;
    const RasterD* rci_kpa = nullptr;
    const RasterD* water_depth_m = nullptr;
    const hydro::DayWeather* weather = nullptr;
};

/// Replays year `year` (1..the run's years; 0: the last) of `run`: `start` once with the stand,
/// then `day` for every day. InputError naming the run and the years it holds for a year outside
/// it.
void replay_season(const std::filesystem::path& run, int year,
                   const std::function<void(const SeasonStand&)>& start,
                   const std::function<void(const SeasonDay&)>& day);

} // namespace ecoterra::run
