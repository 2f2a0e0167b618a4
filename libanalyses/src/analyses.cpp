#include "ecoterra/analyses/analyses.hpp"

#include "ecoterra/analyses/describe.hpp"
#include "ecoterra/export/formats.hpp"
#include "ecoterra/units.hpp"

#include <cmath>
#include <functional>
#include <limits>

namespace ecoterra::analyses {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

template <class R>
Column<R> metric(std::string name, std::string unit, std::string description,
                 std::function<double(const R&)> get, ColumnType type = ColumnType::float64) {
    Column<R> c;
    c.name = std::move(name);
    c.unit = std::move(unit);
    c.description = std::move(description);
    c.type = type;
    c.get = std::move(get);
    return c;
}
} // namespace

const std::vector<Column<run::RunSummary>>& run_metrics() {
    using R = run::RunSummary;
    static const std::vector<Column<R>> c{
        metric<R>(
            "years", "yr", "years the run holds",
            [](const R& r) { return static_cast<double>(r.years_total); }, ColumnType::int64),
        metric<R>(
            "reached_target", "1", "1 when the run stopped at its target basal area",
            [](const R& r) { return r.reached_target ? 1.0 : 0.0; }, ColumnType::int64),
        metric<R>("water_residual_relative", "1",
                  "|cumulative water budget residual| / cumulative throughput",
                  [](const R& r) { return r.water_residual_relative; }),
        metric<R>("rain_mm_per_yr", "mm/yr", "rain over the domain, mean over the run's days",
                  [](const R& r) { return r.water_mm_per_yr.rain; }),
        metric<R>("evaporation_mm_per_yr", "mm/yr",
                  "evaporation (soil, grass surface, open water), mean over the run",
                  [](const R& r) { return r.water_mm_per_yr.evaporation; }),
        metric<R>("transpiration_mm_per_yr", "mm/yr",
                  "transpiration of the plants and the ground layer, mean over the run",
                  [](const R& r) { return r.water_mm_per_yr.transpiration; }),
        metric<R>("interception_mm_per_yr", "mm/yr",
                  "rain held on the canopy and evaporated from it, mean over the run",
                  [](const R& r) { return r.water_mm_per_yr.interception; }),
        metric<R>("runoff_out_mm_per_yr", "mm/yr",
                  "surface water that left the domain, mean over the run",
                  [](const R& r) { return r.water_mm_per_yr.runoff_out; }),
        metric<R>("drainage_out_mm_per_yr", "mm/yr",
                  "water drained below the root zone out of the domain, mean over the run",
                  [](const R& r) { return r.water_mm_per_yr.drainage_out; }),
        metric<R>("groundwater_out_mm_per_yr", "mm/yr",
                  "groundwater that left through fixed-head edges, mean over the run",
                  [](const R& r) { return r.water_mm_per_yr.groundwater_out; }),
        metric<R>("recharge_mm_per_yr", "mm/yr",
                  "percolation below the root zone into the aquifer, mean over the run",
                  [](const R& r) { return r.water_mm_per_yr.recharge; }),
    };
    return c;
}

const std::vector<Column<eco::StandMetrics>>& stand_metrics() {
    using S = eco::StandMetrics;
    static const std::vector<Column<S>> c{
        metric<S>("area_ha", "ha", "area of the terrain", [](const S& s) { return s.area_ha; }),
        metric<S>(
            "stems", "1", "trees (stems that reach breast height; shrubs are undergrowth)",
            [](const S& s) { return static_cast<double>(s.stems); }, ColumnType::int64),
        metric<S>("stems_per_ha", "1/ha", "trees per hectare",
                  [](const S& s) { return s.stems_per_ha; }),
        metric<S>("basal_area_m2_per_ha", "m2/ha", "basal area of the trees at breast height",
                  [](const S& s) { return s.basal_area_m2_per_ha; }),
        metric<S>("basal_area_ft2_per_acre", "ft2/acre",
                  "the same in the units of paper 002's Fig 9",
                  [](const S& s) { return s.basal_area_m2_per_ha * kFt2PerAcrePerM2PerHa; }),
        metric<S>("mean_dbh_m", "m", "mean diameter at breast height",
                  [](const S& s) { return s.mean_dbh_m; }),
        metric<S>("quadratic_mean_dbh_m", "m", "quadratic mean diameter Dq",
                  [](const S& s) { return s.quadratic_mean_dbh_m; }),
        metric<S>("reineke_sdi_per_ha", "1/ha",
                  "Reineke's stand density index, N (Dq / 25.4 cm)^1.605 (Reineke 1933)",
                  [](const S& s) { return s.sdi_per_ha; }),
        metric<S>("q_per_class", "1",
                  "de Liocourt's q: ratio of stems in successive 5 cm classes of the fitted "
                  "negative exponential (null with fewer than 3 non-empty classes)",
                  [](const S& s) { return s.fit_valid ? s.q_per_class : kNaN; }),
        metric<S>("exponential_fit_r2", "1", "R2 of the negative exponential fit (null without)",
                  [](const S& s) { return s.fit_valid ? s.r2 : kNaN; }),
    };
    return c;
}

const std::vector<Column<mobility::MobilityMap>>& mobility_map_metrics() {
    using M = mobility::MobilityMap;
    static const std::vector<Column<M>> c{
        metric<M>("mean_speed_m_per_s", "m/s",
                  "mean over the cells of the mean speed over the headings (NO-GO as 0)",
                  [](const M& m) { return m.mean_speed_m_per_s; }),
        metric<M>("go_share", "1", "share of the cell-headings that are GO",
                  [](const M& m) { return m.go_share; }),
        metric<M>("go_share_any_heading", "1", "share of the cells GO in at least one heading",
                  [](const M& m) { return m.any_go_share; }),
    };
    return c;
}

const std::vector<Column<mobility::StandMobility>>& mobility_metrics() {
    using M = mobility::StandMobility;
    static const std::vector<Column<M>> c{
        metric<M>("smg_mean_m_per_s", "m/s", "mean speed made good over the lines (NOGO as 0)",
                  [](const M& m) { return m.smg_mean_m_per_s; }),
        metric<M>("smg_median_m_per_s", "m/s", "median speed made good",
                  [](const M& m) { return m.smg_median_m_per_s; }),
        metric<M>("smg_p10_m_per_s", "m/s", "10th percentile of the speed made good",
                  [](const M& m) { return m.smg_p10_m_per_s; }),
        metric<M>("smg_p90_m_per_s", "m/s", "90th percentile of the speed made good",
                  [](const M& m) { return m.smg_p90_m_per_s; }),
        metric<M>("smg_mean_go_m_per_s", "m/s", "mean speed made good over the lines that go",
                  [](const M& m) { return m.smg_mean_go_m_per_s; }),
        metric<M>("nogo_fraction", "1", "share of the lines the vehicle cannot drive",
                  [](const M& m) { return m.nogo_fraction; }),
        metric<M>("override_fraction_of_distance", "1",
                  "share of the distance driven spent pushing stems over",
                  [](const M& m) { return m.override_fraction; }),
        metric<M>("detour_fraction_of_distance", "1",
                  "share of the distance driven beyond the straight lines",
                  [](const M& m) { return m.detour_fraction; }),
        metric<M>("basal_area_m2_per_ha", "m2/ha", "basal area of the stand driven through",
                  [](const M& m) { return m.basal_area_m2_per_ha; }),
        metric<M>("basal_area_ft2_per_acre", "ft2/acre", "the same in ft2/acre",
                  [](const M& m) { return m.basal_area_m2_per_ha * kFt2PerAcrePerM2PerHa; }),
        metric<M>(
            "trees", "1", "stems that reach breast height",
            [](const M& m) { return static_cast<double>(m.trees); }, ColumnType::int64),
        metric<M>(
            "shrubs", "1", "shrubs (overridden or avoided by their stem at the push height)",
            [](const M& m) { return static_cast<double>(m.shrubs); }, ColumnType::int64),
        metric<M>(
            "objects", "1", "rigid obstacles (always avoided)",
            [](const M& m) { return static_cast<double>(m.objects); }, ColumnType::int64),
        metric<M>(
            "snags", "1", "standing dead trees (overridden or avoided as trees of their DBH)",
            [](const M& m) { return static_cast<double>(m.snags); }, ColumnType::int64),
        metric<M>(
            "logs", "1", "logs on the ground",
            [](const M& m) { return static_cast<double>(m.logs); }, ColumnType::int64),
        metric<M>("step_limit_m", "m",
                  "the highest log the vehicle climbs: min(ground clearance, wheel radius)",
                  [](const M& m) { return m.step_limit_m; }),
        metric<M>("log_crossings_per_100m", "1/100m",
                  "logs climbed per 100 m driven on the lines that go",
                  [](const M& m) { return m.log_crossings_per_100m; }),
        metric<M>("logs_avoided_per_line", "1",
                  "logs too high to climb that lie across a line, mean over the lines",
                  [](const M& m) { return m.logs_avoided_per_line; }),
        metric<M>("area_ha", "ha", "area of the stand", [](const M& m) { return m.area_ha; }),
        metric<M>("critical_diameter_m", "m",
                  "the largest stem diameter the vehicle can override at its push height",
                  [](const M& m) { return m.critical_diameter_m; }),
    };
    return c;
}

const std::vector<Column<mobility::TraverseReport>>& traverse_metrics() {
    using T = mobility::TraverseReport;
    static const std::vector<Column<T>> c{
        metric<T>(
            "missions", "1", "missions driven",
            [](const T& t) { return static_cast<double>(t.results.size()); }, ColumnType::int64),
        metric<T>(
            "successes", "1", "missions that reached their goal",
            [](const T& t) { return static_cast<double>(t.successes); }, ColumnType::int64),
        metric<T>("success_rate", "1", "successes / missions",
                  [](const T& t) { return t.success_rate; }),
        metric<T>("median_rms_vertical_acceleration_m_per_s2", "m/s2",
                  "median over the successful missions of the RMS vertical acceleration",
                  [](const T& t) { return t.median_rms_vertical_acceleration_m_per_s2; }),
        metric<T>("median_rms_pitch_rate_deg_per_s", "deg/s",
                  "median over the successful missions of the RMS pitch rate",
                  [](const T& t) { return t.median_rms_pitch_rate_deg_per_s; }),
        metric<T>("median_rms_roll_rate_deg_per_s", "deg/s",
                  "median over the successful missions of the RMS roll rate",
                  [](const T& t) { return t.median_rms_roll_rate_deg_per_s; }),
        metric<T>("median_time_s", "s", "median traversal time of the successful missions",
                  [](const T& t) { return t.median_time_s; }),
    };
    return c;
}

const std::vector<Column<terrain::TerrainAnalysis>>& terrain_metrics() {
    using A = terrain::TerrainAnalysis;
    static const std::vector<Column<A>> c{
        metric<A>("low_pct", "%", "low-roughness area before the closing (as paper 000 reports it)",
                  [](const A& a) { return a.classes.low_pct; }),
        metric<A>("semi_pct", "%", "semi-rough area before the closing",
                  [](const A& a) { return a.classes.semi_pct; }),
        metric<A>("high_pct", "%", "high-roughness area before the closing",
                  [](const A& a) { return a.classes.high_pct; }),
        metric<A>("closed_low_pct", "%", "low-roughness area after the closing",
                  [](const A& a) { return a.closed_classes.low_pct; }),
        metric<A>("closed_semi_pct", "%", "semi-rough area after the closing",
                  [](const A& a) { return a.closed_classes.semi_pct; }),
        metric<A>("closed_high_pct", "%", "high-roughness area after the closing",
                  [](const A& a) { return a.closed_classes.high_pct; }),
        metric<A>("rms_m", "m", "RMS height about the mean plane",
                  [](const A& a) { return a.rms.rms_m; }),
        metric<A>("rms_detrended_m", "m",
                  "RMS height about the moving-window trend (NaN where the window is under two "
                  "cells)",
                  [](const A& a) {
                      return a.detrended_valid ? a.rms.rms_detrended_m
                                               : std::numeric_limits<double>::quiet_NaN();
                  }),
        metric<A>("mean_slope", "1", "mean slope, rise over run",
                  [](const A& a) { return a.mean_slope; }),
        metric<A>("fractal_dimension", "1", "fractal dimension from the structure function",
                  [](const A& a) { return a.fd.dimension; }),
        metric<A>("psd_dimension", "1", "fractal dimension from the power spectrum's slope",
                  [](const A& a) { return a.psd.dimension; }),
    };
    return c;
}

namespace {
template <class R>
void add_info(std::vector<ColumnInfo>& out, const std::string& analysis,
              const std::vector<Column<R>>& metrics) {
    for (const auto& c : describe(analysis + ".", metrics)) out.push_back(c);
}
} // namespace

std::vector<ColumnInfo> describe_metrics() {
    std::vector<ColumnInfo> out;
    add_info(out, "run", run_metrics());
    add_info(out, "stand", stand_metrics());
    add_info(out, "mobility", mobility_metrics());
    add_info(out, "traverse", traverse_metrics());
    add_info(out, "mobility_map", mobility_map_metrics());
    add_info(out, "terrain", terrain_metrics());
    return out;
}

std::string metric_unit(const std::string& qualified) {
    static const std::vector<ColumnInfo> all = describe_metrics();
    for (const auto& c : all)
        if (c.name == qualified) return c.unit;
    return "";
}

nlohmann::json stand_json(const eco::StandMetrics& m) {
    nlohmann::json j = eco::to_json(m);
    put_metrics(j, stand_metrics(), m);
    return j;
}

nlohmann::json mobility_json(const mobility::StandMobility& m, const mobility::Vehicle& v) {
    nlohmann::json j = mobility::to_json(m, v);
    put_metrics(j, mobility_metrics(), m);
    return j;
}

nlohmann::json traverse_json(const mobility::TraverseReport& r, const mobility::Vehicle& v) {
    nlohmann::json j = mobility::to_json(r, v);
    put_metrics(j, traverse_metrics(), r);
    return j;
}

nlohmann::json terrain_json(const terrain::TerrainAnalysis& a, const terrain::AnalysisOptions& o) {
    nlohmann::json j = a.to_json(o);
    put_metrics(j, terrain_metrics(), a);
    return j;
}

std::string column_unit(const std::string& column) {
    std::string u = metric_unit(column);
    if (!u.empty()) return u;
    for (const char* stat : {".mean", ".sd", ".p10", ".p50", ".p90"}) {
        const std::string s(stat);
        if (column.size() > s.size() && column.compare(column.size() - s.size(), s.size(), s) == 0)
            if (!(u = metric_unit(column.substr(0, column.size() - s.size()))).empty()) return u;
    }
    static const std::vector<std::pair<std::string, std::string>> own{
        {"member", "1"},  {"combination", "1"}, {"replicate", "1"},      {"seed", "1"},
        {"members", "1"}, {"ok", "1"},          {"failed", "1"},         {"threads", "1"},
        {"seconds", "s"}, {"area_ha", "ha"},    {"class_width_cm", "cm"}};
    for (const auto& [name, unit] : own)
        if (column == name) return unit;
    return analyses::scene_key_unit(column);
}

mobility::StandLinesOptions MobilityAnalysis::lines_options() const {
    mobility::StandLinesOptions o;
    o.lines = lines;
    o.length_m = length_m;
    o.seed = seed;
    o.layout = layout;
    o.effects = effects;
    return o;
}

const ParamCatalog<MobilityAnalysis>& mobility_catalog() {
    using M = MobilityAnalysis;
    static const ParamCatalog<M> c(
        "analyses.mobility",
        {text<M>("vehicle", &M::vehicle, "a vehicle file, e.g. ../vehicles/mrzr4.json").mandatory(),
         integer<M>("lines", &M::lines, "1", 1, 1000000, "lines driven through the stand"),
         number<M>("length_m", &M::length_m, "m", 1e-3, 1e6, "length of each line"),
         integer<M>("seed", &M::seed, "1", 0, 4.611686018427388e18,
                    "seed of the lines (an ensemble derives one per member)"),
         choice<M>("layout", &M::layout,
                   std::vector<std::pair<std::string, mobility::LineLayout>>{
                       {"random", mobility::LineLayout::random},
                       {"transects", mobility::LineLayout::transects}},
                   "random lines, or parallel transects across the stand"),
         flag<M>("deadwood", &M::deadwood,
                 "drive through the run's snags and over or around its logs (false: the living "
                 "stand only)"),
         flag<M>("soil", &M::soil,
                 "the snapshot's ground: soil strength (NO-GO below the vehicle's VCI1, slower "
                 "on soft soil) and standing water (NO-GO over the fording depth) (false: firm, "
                 "dry ground; stem lists have neither)"),
         choice<M>("effects", &M::effects, mobility::stem_effects_names(),
                   "the stems the lines meet: both (all), override_only (those below the "
                   "critical diameter) or avoidance_only (those at or above it, and objects), "
                   "to take the slowing apart (docs/mobility.md s4)")});
    return c;
}

mobility::MapOptions MobilityMapAnalysis::map_options() const {
    mobility::MapOptions o;
    o.cell_m = cell_m;
    o.headings = headings;
    return o;
}

const ParamCatalog<MobilityMapAnalysis>& mobility_map_catalog() {
    using M = MobilityMapAnalysis;
    static const ParamCatalog<M> c(
        "analyses.mobility_map",
        {text<M>("vehicle", &M::vehicle, "a vehicle file, e.g. ../vehicles/mrzr4.json").mandatory(),
         number<M>("cell_m", &M::cell_m, "m", 0, 1e5,
                   "map cell, a whole multiple of the terrain's (0: the terrain's)"),
         integer<M>("headings", &M::headings, "1", 1, 360, "headings, evenly spaced from north"),
         flag<M>("deadwood", &M::deadwood,
                 "the snapshot's snags and logs (false: the living only)"),
         flag<M>("soil", &M::soil,
                 "the snapshot's soil strength and standing water (false: firm, dry ground)")});
    return c;
}

terrain::MissionOptions TraverseAnalysis::mission_options() const {
    terrain::MissionOptions o;
    o.count = missions;
    o.length_m = length_m;
    o.seed = seed;
    o.allow_fewer = allow_fewer;
    return o;
}

mobility::TraverseOptions TraverseAnalysis::traverse_options() const {
    mobility::TraverseOptions o;
    o.speed_m_per_s = speed_m_per_s;
    o.allow_no_missions = allow_fewer;
    return o;
}

const ParamCatalog<TraverseAnalysis>& traverse_catalog() {
    using T = TraverseAnalysis;
    static const ParamCatalog<T> c(
        "analyses.traverse",
        {text<T>("vehicle", &T::vehicle, "a vehicle file, e.g. ../vehicles/mrzr4.json").mandatory(),
         integer<T>("missions", &T::missions, "1", 1, 100000, "missions planned and driven"),
         number<T>("length_m", &T::length_m, "m", 1e-3, 1e6, "straight-line length of a mission"),
         integer<T>("seed", &T::seed, "1", 0, 4.611686018427388e18,
                    "seed of the missions (an ensemble derives one per member)"),
         number<T>("speed_m_per_s", &T::speed_m_per_s, "m/s", 0, 100,
                   "driving speed; 0: the vehicle's top speed"),
         flag<T>("allow_fewer", &T::allow_fewer,
                 "drive the missions found when the terrain has room for fewer than `missions` "
                 "(none without a low cell); traverse.missions says how many (default: the member "
                 "fails)")});
    return c;
}

terrain::AnalysisOptions TerrainAnalysisOptions::options() const {
    terrain::AnalysisOptions o;
    o.border_m = border_m;
    o.closing_radius_m = closing_radius_m;
    o.validate();
    return o;
}

const ParamCatalog<TerrainAnalysisOptions>& terrain_catalog() {
    using T = TerrainAnalysisOptions;
    static const ParamCatalog<T> c(
        "analyses.terrain",
        {number<T>("border_m", &T::border_m, "m", 0, 1e6, "border left out of the class areas"),
         number<T>("closing_radius_m", &T::closing_radius_m, "m", 0, 1e6,
                   "disk radius of the morphological closing of the classes")});
    return c;
}

const ParamCatalog<ExportAnalysis>& export_catalog() {
    using E = ExportAnalysis;
    static const ParamCatalog<E> c = [] {
        std::vector<std::string> names;
        for (const auto f : {exporter::SceneFormat::mavs, exporter::SceneFormat::gazebo,
                             exporter::SceneFormat::unreal, exporter::SceneFormat::gltf})
            names.emplace_back(exporter::scene_format_name(f));
        return ParamCatalog<E>(
            "analyses.export",
            {choice_list<E>("formats", &E::formats, names,
                            "scene formats to export, each into scene_FORMAT/ (docs/exports.md)"),
             flag<E>("layers", &E::layers, "the GeoTIFF layers too, into layers/")});
    }();
    return c;
}

const std::vector<std::pair<std::string, std::vector<std::string>>>& analysis_keys() {
    static const std::vector<std::pair<std::string, std::vector<std::string>>> k = [] {
        // The seed is not the manifest's to give: each member derives its own.
        auto keys = [](const auto& catalog) {
            std::vector<std::string> out;
            for (const auto& p : catalog.params())
                if (p.key != "seed") out.push_back(p.key);
            return out;
        };
        return std::vector<std::pair<std::string, std::vector<std::string>>>{
            {"stand", {}},
            {"mobility", keys(mobility_catalog())},
            {"mobility_map", keys(mobility_map_catalog())},
            {"terrain", keys(terrain_catalog())},
            {"traverse", keys(traverse_catalog())},
            {"export", keys(export_catalog())},
            {"pictures", {}}};
    }();
    return k;
}

} // namespace ecoterra::analyses
