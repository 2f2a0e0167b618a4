#include "ecoterra/run/season.hpp"

#include "ecoterra/archive.hpp"
#include "ecoterra/error.hpp"
#include "ecoterra/hash.hpp"
#include "ecoterra/hydro/soil_strength.hpp"
#include "ecoterra/mobility/ground.hpp"
#include "ecoterra/run/records.hpp"
#include "ecoterra/run/run_reader.hpp"
#include "run_layout.hpp"

namespace ecoterra::run {

namespace fs = std::filesystem;
using namespace layout;

namespace {

/// The stand at the ecosystem's present state, as mobility sees it.
SeasonStand stand_of(const eco::Ecosystem& eco) {
    SeasonStand s;
    const auto& species = eco.scene().ecosystem.species;
    std::vector<PlantRecord> plants;
    for (const eco::Plant& p : eco::rows(eco.plants()))
        plants.push_back(plant_record(p, species[p.species]));
    s.stems = stand_stems(plants);
    std::vector<DeadWoodRecord> pieces;
    for (const auto& d : eco.dead_wood().pieces())
        pieces.push_back(deadwood_record(d, species[d.species]));
    s.dead = stand_deadwood(pieces);
    s.dem = eco.scene().hydro.dem;
    const auto& soil = eco.scene().hydro.soil;
    s.fine_grained = mobility::fine_grained_mask(soil.silt_pct, soil.clay_pct);
    return s;
}

} // namespace

void replay_season(const fs::path& run, int year,
                   const std::function<void(const SeasonStand&)>& start,
                   const std::function<void(const SeasonDay&)>& day) {
    const RunInfo info = read_run_info(run);
    const nlohmann::json& scene = info.provenance.at("scene");
    const eco::EcoScene sc = eco::load_eco_scene(scene, "/");
    // The run's checkpoint for its last year (and the check that the rebuilt terrain is the
    // run's), without its state, which the replay does not need.
    const RunCheckpoint cp = read_run_checkpoint(run, sc, false);
    if (year == 0) year = cp.year;
    if (year < 1 || year > cp.year)
        throw InputError(run.string() + ": year " + std::to_string(year) +
                         " is outside the run (it holds years 1-" + std::to_string(cp.year) + ")");
    eco::Ecosystem eco(sc);
    // The latest snapshot checkpoint (simulation.snapshot_checkpoints) at or before the year
    // before, read once.
    int from = 0, latest = -1;
    for (int k = 0; k < info.snapshots; ++k)
        open_snapshot(run, k, [&](const H5::Group& g) {
            const int y = static_cast<int>(read_double_attr(g, "year"));
            if (y <= year - 1 && y > from && g.nameExists("checkpoint")) from = y, latest = k;
        });
    if (latest >= 0)
        open_snapshot(run, latest, [&](const H5::Group& g) {
            const std::string where =
                run.string() + ": snapshot " + std::to_string(latest) + " checkpoint";
            const auto bytes = read_vector<std::uint8_t>(g.openGroup("checkpoint"), "state",
                                                         H5::PredType::NATIVE_UINT8);
            const std::string sum = read_string_attr(g.openGroup("checkpoint"), "checksum_fnv1a64");
            if (sum != std::to_string(fnv1a64(bytes.data(), bytes.size())))
                throw InputError(where + " is damaged (its checksum does not match its bytes)");
            ArchiveReader r(bytes.data(), bytes.size(), where);
            with_context(where, [&] { eco.load_state(r); });
        });
    while (eco.years_done() < year - 1) eco.run_year();
    SeasonStand s = stand_of(eco);
    s.year = year;
    s.replayed_from = from;
    start(s);
    RasterD rci, water;
    bool closed = false;
    while (!closed) {
        closed = eco.step_day();
        const auto& hy = eco.hydrology();
        rci = hydro::rating_cone_index_map_kpa(sc.hydro.soil, hy.critical_layer_moisture());
        SeasonDay d;
        d.day_of_year = eco.last_weather().doy;
        d.rci_kpa = &rci;
        water = hy.surface_water_depth();
        d.water_depth_m = &water;
        d.weather = &eco.last_weather();
        day(d);
    }
}

} // namespace ecoterra::run
