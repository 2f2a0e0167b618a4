// `ecoterra hydro ...`: soil, et (and the hydrology runs).
#include "common.hpp"
#include "subcommands.hpp"

#include "ecoterra/hydro/penman.hpp"
#include "ecoterra/hydro/soil.hpp"

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
    const auto m = et::parse_method(a.method);
    if (!m)
        throw InputError("--method must be fao56, penman-open-water, penman-bare-soil or "
                         "penman-grass, got '" + a.method + "'");
    et::WindFunction wf;
    if (a.wind == "1948") wf = et::WindFunction::penman1948;
    else if (a.wind == "1956") wf = et::WindFunction::penman1956;
    else if (a.wind == "shuttleworth") wf = et::WindFunction::shuttleworth1993;
    else throw InputError("--wind-function must be 1948, 1956 or shuttleworth, got '" + a.wind + "'");
    a.w.rh_min_pct = a.rhmin;
    a.w.rh_max_pct = a.rhmax;
    a.w.rh_mean_pct = a.rhmean;
    a.w.tdew_c = a.tdew;
    a.w.ea_kpa = a.ea;
    a.w.rs_mj = a.rs;
    a.w.sunshine_h = a.sunshine;
    et::DailyTerms t{};
    const double e = et::evapotranspiration(*m, a.w, wf, &t);
    if (a.as_json) {
        json j = {{"method", et::method_name(*m)},
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
        if (*m != et::Method::fao56) j["wind_function"] = et::wind_function_name(wf);
        std::printf("%s\n", j.dump(2).c_str());
        return;
    }
    std::printf("es %.4f kPa, ea %.4f kPa (from %s), delta %.5f kPa/degC, gamma %.5f kPa/degC\n",
                t.es, t.ea, t.humidity_from, t.delta, t.gamma);
    std::printf("Ra %.3f, Rso %.3f, Rs %.3f (from %s), Rnl %.3f, Rn %.3f MJ m-2 day-1 "
                "(albedo %.2f)\n",
                t.ra, t.rso, t.rs, t.radiation_from, t.rnl, t.rn, t.albedo);
    if (*m != et::Method::fao56)
        std::printf("wind function %s\n", et::wind_function_name(wf).c_str());
    std::printf("%.2f mm/day %s\n", e, et::method_name(*m).c_str());
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
    soil->add_option("--organic-matter", s->om,
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
    et->add_option("--wind-function", e->wind, "Penman f(u): 1948 | 1956 | shuttleworth")
        ->capture_default_str();
    et->add_flag("--json", e->as_json, "print all intermediates as JSON");
    et->callback([e] { run_et(*e); });
}

} // namespace ecoterra::app
