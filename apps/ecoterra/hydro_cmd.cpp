// `ecoterra hydro ...`: soil, et (and the hydrology runs).
#include "common.hpp"
#include "subcommands.hpp"

#include "ecoterra/hydro/penman.hpp"
#include "ecoterra/hydro/pond.hpp"
#include "ecoterra/hydro/scene.hpp"
#include "ecoterra/hydro/soil.hpp"
#include "ecoterra/json_util.hpp"
#include "ecoterra/terrain/io/raster_io.hpp"
#include "ecoterra/terrain/picture.hpp"

#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>

namespace ecoterra::app {

namespace {

using nlohmann::json;

struct SoilArgs {
    double sand = 0, silt = 0, clay = 0, ph = 6.5;
    std::optional<double> om;
    bool as_json = false;
};

void run_soil(const SoilArgs& a) {
    hydro::SoilComposition c{a.sand, a.silt, a.clay, a.ph, a.om};
    c.validate("soil");
    const hydro::SoilProperties p = hydro::soil_properties(c);
    if (a.as_json) {
        const json j = {{"class", hydro::texture_name(p.texture)},
                        {"sand_pct", a.sand},
                        {"silt_pct", a.silt},
                        {"clay_pct", a.clay},
                        {"ph", a.ph},
                        {"porosity", p.porosity},
                        {"field_capacity", p.field_capacity},
                        {"wilting_point", p.wilting_point},
                        {"ksat_m_per_s", p.ksat_m_per_s},
                        {"source", p.source}};
        std::printf("%s\n", j.dump(2).c_str());
        return;
    }
    std::printf("texture class    %s (sand %.4g %%, silt %.4g %%, clay %.4g %%, pH %.3g)\n"
                "porosity         %.3f m3/m3\n"
                "field capacity   %.3f m3/m3 (33 kPa)\n"
                "wilting point    %.3f m3/m3 (1500 kPa)\n"
                "ksat             %.4g m/s (%.4g cm/h)\n"
                "source           %s\n",
                hydro::texture_name(p.texture).c_str(), a.sand, a.silt, a.clay, a.ph, p.porosity,
                p.field_capacity, p.wilting_point, p.ksat_m_per_s, p.ksat_m_per_s * 3.6e5,
                p.source.c_str());
}

struct EtArgs {
    std::string method = "fao56", wind = "1948";
    hydro::et::DailyWeather w;
    std::optional<double> rhmin, rhmax, rhmean, tdew, ea, rs, sunshine;
    bool as_json = false;
};

void run_et(EtArgs& a) {
    namespace et = hydro::et;
    const et::Method m = et::parse_method(a.method, "--method");
    const et::WindFunction wf = et::parse_wind_function(a.wind, "--wind-function");
    a.w.rh_min_pct = a.rhmin;
    a.w.rh_max_pct = a.rhmax;
    a.w.rh_mean_pct = a.rhmean;
    a.w.tdew_c = a.tdew;
    a.w.ea_kpa = a.ea;
    a.w.rs_mj = a.rs;
    a.w.sunshine_h = a.sunshine;
    et::DailyTerms t{};
    const double e = et::evapotranspiration(m, a.w, wf, &t);
    if (a.as_json) {
        json j = {{"method", et::method_name(m)},
                  {"et_mm_per_day", e},
                  {"es_kpa", t.es},
                  {"ea_kpa", t.ea},
                  {"delta_kpa_per_degc", t.delta},
                  {"gamma_kpa_per_degc", t.gamma},
                  {"pressure_kpa", t.pressure_kpa},
                  {"ra_mj_per_m2_day", t.ra},
                  {"rso_mj_per_m2_day", t.rso},
                  {"rs_mj_per_m2_day", t.rs},
                  {"rnl_mj_per_m2_day", t.rnl},
                  {"rn_mj_per_m2_day", t.rn},
                  {"albedo", t.albedo},
                  {"humidity_from", t.humidity_from},
                  {"radiation_from", t.radiation_from}};
        if (m != et::Method::fao56) j["wind_function"] = et::wind_function_name(wf);
        std::printf("%s\n", j.dump(2).c_str());
        return;
    }
    std::printf("es %.4f kPa, ea %.4f kPa (from %s), delta %.5f kPa/degC, gamma %.5f kPa/degC\n",
                t.es, t.ea, t.humidity_from, t.delta, t.gamma);
    std::printf("Ra %.3f, Rso %.3f, Rs %.3f (from %s), Rnl %.3f, Rn %.3f MJ m-2 day-1 "
                "(albedo %.2f)\n",
                t.ra, t.rso, t.rs, t.radiation_from, t.rnl, t.rn, t.albedo);
    if (m != et::Method::fao56)
        std::printf("wind function %s\n", et::wind_function_name(wf).c_str());
    std::printf("%.2f mm/day %s\n", e, et::method_name(m).c_str());
}

struct PondArgs {
    std::string dem, output, routing = "d8";
    double depth_m = 0.0;
    bool force = false;
};

void run_pond(const PondArgs& a) {
    refuse_output_over_input("-o", a.output, {a.dem});
    const hydro::Routing routing = hydro::parse_routing(a.routing);
    refuse_over_run_file("-o", a.output);
    claim_output("-o", a.output, a.force);
    { io::AtomicOutput probe(a.output); }
    std::vector<std::string> warnings;
    const RasterD dem = terrain::io::read_raster(a.dem, &warnings);
    print_warnings(warnings);
    Stopwatch sw;
    const hydro::PondResult p = hydro::pond_with_budget(dem, a.depth_m, routing);
    const double seconds = sw.seconds();
    hydro::write_pond(a.output, dem, p, provenance({{"dem", a.dem}}).dump());
    const hydro::PondBudget& b = p.budget;
    std::printf("ponded %.4g m over %s (%d x %d cells of %.4g m), %s routing\n", a.depth_m,
                a.dem.c_str(), dem.nx(), dem.ny(), dem.cell_size(),
                hydro::routing_name(routing).c_str());
    std::printf("budget: input %.6g m3 = stored %.6g m3 + left through edges %.6g m3 "
                "(residual %.3g m3)\n",
                b.input_m3, b.stored_m3, b.left_through_edges_m3, b.residual_m3());
    std::printf("%zu catchments, %lld wet cells (%.2f %%), max depth %.4g m; %.3f s "
                "(%.3g cells/s)\n",
                p.catchments, static_cast<long long>(p.wet_cells),
                p.valid_cells
                    ? 100.0 * static_cast<double>(p.wet_cells) / static_cast<double>(p.valid_cells)
                    : 0.0,
                stats(p.water_depth_m).max, seconds, static_cast<double>(dem.size()) / seconds);
    std::printf("wrote %s\n", a.output.c_str());
}

struct RunArgs {
    std::string scene, output = "hydro.h5", png_dir;
    std::vector<std::string> sets;
    std::optional<long long> years, seed;
    bool force = false;
};

void run_hydro_run(const RunArgs& a) {
    refuse_output_over_input("-o", a.output, {a.scene});
    json scene = parse_json(io::read_text(a.scene), a.scene);
    std::vector<std::string> sets = a.sets;
    if (a.years) sets.push_back("simulation.years=" + std::to_string(*a.years));
    if (a.seed) sets.push_back("simulation.seed=" + std::to_string(*a.seed));
    apply_overrides(scene, sets);
    const std::filesystem::path base = std::filesystem::path(a.scene).parent_path();
    const hydro::HydroScene sc = with_context(a.scene, [&] {
        return hydro::load_hydro_scene(scene, base.empty() ? std::filesystem::path(".") : base);
    });
    print_notes(sc.notes);
    print_terrain_source(sc.terrain_source);
    claim_output("-o", a.output, a.force);
    claim_output("--png", a.png_dir, a.force);
    json prov = provenance({{"scene_file", a.scene},
                            {"overrides", sets},
                            {"methods", methods_json(hydro::scene_methods(sc))}});
    if (sc.observed) {
        print_notes(hydro::fill_report(*sc.observed));
        prov["observed_weather_filled"] = sc.observed->filled;
    }
    std::printf("hydrology: %d x %d cells of %.4g m, %d years, seed %llu, %s climate%s\n",
                sc.dem.nx(), sc.dem.ny(), sc.dem.cell_size(), sc.years,
                static_cast<unsigned long long>(sc.seed), sc.climate.name.c_str(),
                sc.options.groundwater ? ", groundwater on" : "");
    const double cells = static_cast<double>(sc.dem.size());
    const auto sum =
        hydro::run_hydro_scene(sc, a.output, prov, a.png_dir, [&](const hydro::HydroProgress& p) {
            // The weather's own calendar: observed leap years have a day 366.
            progress_line(static_cast<double>(p.day) / p.days, p.seconds,
                          "  year %d day %3d  (%d of %d days, %.3g cell-days/s)  ", p.year, p.doy,
                          p.day, p.days, cells * p.day / std::max(p.seconds, 1e-9));
            if (p.day == p.days) end_progress_line();
        });
    std::printf("%d days in %.2f s (%.3g cell-days/s)\n", sum.days, sum.seconds,
                cells * sum.days / sum.seconds);
    std::printf("water budget, mm over the domain: rain %.1f = evaporation %.1f + transpiration "
                "%.1f + interception %.1f + runoff out %.1f + drainage out %.1f + groundwater out "
                "%.1f + storage change; cumulative residual %.2e of the throughput\n",
                sum.rain_mm, sum.evaporation_mm, sum.transpiration_mm, sum.interception_mm,
                sum.runoff_out_mm, sum.drainage_out_mm, sum.groundwater_out_mm,
                sum.residual_relative);
    if (sum.transpiration_mm == 0)
        std::printf("  (transpiration is the water plants take; a hydrology run has no plants, "
                    "so the loss of the vegetation cover is in evaporation, at Penman's grass "
                    "rate where the density is above grass_density_threshold: docs/hydrology.md "
                    "s4)\n");
    std::printf("methods (cite them with the run; also in its /provenance):\n%s",
                methods_text(hydro::scene_methods(sc)).c_str());
    std::printf("wrote %s\n", a.output.c_str());
    if (!a.png_dir.empty()) std::printf("wrote pictures into %s\n", a.png_dir.c_str());
}

} // namespace

void add_hydro_command(CLI::App& app) {
    CLI::App* hydro = app.add_subcommand("hydro", "soils, evapotranspiration and hydrology");
    hydro->require_subcommand(1);

    auto s = std::make_shared<SoilArgs>();
    CLI::App* soil = hydro->add_subcommand("soil", "USDA texture class and hydraulic properties");
    soil->add_option("--sand", s->sand, "sand, % by mass")->required();
    soil->add_option("--silt", s->silt, "silt, % by mass")->required();
    soil->add_option("--clay", s->clay, "clay, % by mass")->required();
    soil->add_option("--ph", s->ph, "soil pH")->capture_default_str();
    soil->add_option(
        "--organic-matter", s->om,
        "organic matter, % by mass: use Saxton & Rawls 2006 instead of the class table");
    soil->add_flag("--json", s->as_json, "print JSON");
    soil->callback([s] { run_soil(*s); });

    auto e = std::make_shared<EtArgs>();
    CLI::App* et = hydro->add_subcommand("et", "evapotranspiration for one day's weather");
    et->add_option("--method", e->method,
                   "fao56 | penman-open-water | penman-bare-soil | penman-grass")
        ->capture_default_str();
    et->add_option("--lat", e->w.lat_deg, "latitude, degrees (south negative)")->required();
    et->add_option("--elev", e->w.elevation_m, "elevation above sea level, m")->required();
    et->add_option("--doy", e->w.doy, "day of the year, 1-366")->required();
    et->add_option("--tmin", e->w.tmin_c, "daily minimum air temperature, deg C")->required();
    et->add_option("--tmax", e->w.tmax_c, "daily maximum air temperature, deg C")->required();
    et->add_option("--rhmin", e->rhmin, "minimum relative humidity, %");
    et->add_option("--rhmax", e->rhmax, "maximum relative humidity, %");
    et->add_option("--rhmean", e->rhmean, "mean relative humidity, %");
    et->add_option("--tdew", e->tdew, "dew point, deg C");
    et->add_option("--ea", e->ea, "actual vapour pressure, kPa");
    et->add_option("--u2", e->w.u2_m_per_s, "wind speed at 2 m, m/s")->capture_default_str();
    et->add_option("--rs", e->rs, "solar radiation, MJ m-2 day-1");
    et->add_option("--sunshine-hours", e->sunshine, "bright sunshine, hours");
    et->add_option("--soil-heat-flux", e->w.soil_heat_flux_mj, "G, MJ m-2 day-1 (0 for days)")
        ->capture_default_str();
    et->add_option(
          "--wind-function", e->wind,
          "Penman f(u): 1948 | 1956 | shuttleworth (or penman1948 | penman1956 | shuttleworth1993)")
        ->capture_default_str();
    et->add_flag("--json", e->as_json, "print all intermediates as JSON");
    et->callback([e] { run_et(*e); });

    auto p = std::make_shared<PondArgs>();
    CLI::App* pond = hydro->add_subcommand("pond", "where does a uniform depth of water pond?");
    pond->add_option("dem", p->dem, "elevation raster (any supported format)")->required();
    pond->add_option("--depth-m", p->depth_m, "water depth spread over every cell, m")->required();
    pond->add_option(
            "--routing", p->routing,
            "d8 (steepest descent) | d8-lowest (to the lowest neighbour, as Fill-Spill-Merge) | "
            "mfd (multiple directions)")
        ->capture_default_str();
    pond->add_option("-o,--output", p->output, "HDF5 output file")->required();
    add_force_flag(pond, p->force);
    pond->callback([p] { run_pond(*p); });

    auto r = std::make_shared<RunArgs>();
    CLI::App* run = hydro->add_subcommand("run", "run the hydrology of a scene for some years");
    run->add_option("scene", r->scene, "scene JSON file (docs/formats.md)")->required();
    run->add_option("-o,--output", r->output, "HDF5 output file")->capture_default_str();
    run->add_option("--years", r->years, "simulated years (overrides simulation.years)");
    run->add_option("--seed", r->seed, "random seed (overrides simulation.seed)");
    run->add_option("--set", r->sets, "KEY=VALUE: override any scene key by its dotted path");
    run->add_option("--png", r->png_dir, "write pictures of the final state into this folder");
    add_force_flag(run, r->force);
    run->callback([r] { run_hydro_run(*r); });
}

} // namespace ecoterra::app
