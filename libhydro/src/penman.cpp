#include "ecoterra/hydro/penman.hpp"

#include "ecoterra/error.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

namespace ecoterra::hydro::et {

namespace {

constexpr double kPi = std::numbers::pi;
// Improved Magnus (Alduchov & Eskridge 1996), kPa and degC.
constexpr double kAerkA = 0.61094, kAerkB = 17.625, kAerkC = 243.04;
constexpr double kAerkiA = 0.61121, kAerkiB = 22.587, kAerkiC = 273.86;
// FAO-56 eq. 11.
constexpr double kFaoA = 0.6108, kFaoB = 17.27, kFaoC = 237.3;
// FAO-56 Penman-Monteith constants (grass reference).
constexpr double kCnDaily = 900.0, kCnHourly = 37.0, kCd = 0.34;
constexpr double kGDay = 0.1, kGNight = 0.5; // G / Rn, hourly
constexpr double kAngstromA = 0.25, kAngstromB = 0.50;
constexpr double kMinutesPerDay = 24.0 * 60.0;
constexpr double kMinutesPerHour = 60.0;
/// FAO-56 eq. 8: gamma = cp P / (epsilon lambda); cp in MJ kg-1 degC-1, epsilon = Mw / Md.
constexpr double kSpecificHeatAir = 1.013e-3;
constexpr double kMolecularWeightRatio = 0.622;

double rnl_humidity_factor(double ea) {
    return 0.34 - 0.14 * std::sqrt(ea);
}
double rnl_cloud_factor(double rs_over_rso) {
    return 1.35 * std::clamp(rs_over_rso, 0.0, 1.0) - 0.35;
}

} // namespace

double svp_water_kpa(double t) {
    return kAerkA * std::exp(kAerkB * t / (t + kAerkC));
}
double svp_ice_kpa(double t) {
    return kAerkiA * std::exp(kAerkiB * t / (t + kAerkiC));
}
double svp_slope_water_kpa(double t) {
    return svp_water_kpa(t) * kAerkB * kAerkC / ((t + kAerkC) * (t + kAerkC));
}
double svp_fao_kpa(double t) {
    return kFaoA * std::exp(kFaoB * t / (t + kFaoC));
}
double svp_slope_fao_kpa(double t) {
    return 4098.0 * svp_fao_kpa(t) / ((t + kFaoC) * (t + kFaoC));
}

double atmospheric_pressure_kpa(double z) {
    return 101.3 * std::pow((293.0 - 0.0065 * z) / 293.0, 5.26);
}
double psychrometric_constant_kpa(double p) {
    return kSpecificHeatAir * p / (kMolecularWeightRatio * kLatentHeat_MJ_per_kg);
}
double inverse_relative_distance(int doy) {
    return 1.0 + 0.033 * std::cos(2 * kPi * doy / 365.0);
}
double solar_declination_rad(int doy) {
    return 0.409 * std::sin(2 * kPi * doy / 365.0 - 1.39);
}
double sunset_hour_angle_rad(double lat, int doy) {
    const double x = -std::tan(lat) * std::tan(solar_declination_rad(doy));
    return std::acos(std::clamp(x, -1.0, 1.0)); // polar day / night
}

double extraterrestrial_radiation_daily(double lat, int doy) {
    const double ws = sunset_hour_angle_rad(lat, doy), d = solar_declination_rad(doy);
    return kMinutesPerDay / kPi * kSolarConstant * inverse_relative_distance(doy) *
           (ws * std::sin(lat) * std::sin(d) + std::cos(lat) * std::cos(d) * std::sin(ws));
}

double daylight_hours(double lat, int doy) {
    return 24.0 / kPi * sunset_hour_angle_rad(lat, doy);
}

double extraterrestrial_radiation_hourly(double lat, double lon_west_deg, double lz_west_deg,
                                         int doy, double hour_end, double duration_h) {
    const double b = 2 * kPi * (doy - 81) / 364.0;
    const double sc = 0.1645 * std::sin(2 * b) - 0.1255 * std::cos(b) - 0.025 * std::sin(b);
    const double t_mid = hour_end - 0.5 * duration_h;
    const double w = kPi / 12.0 * ((t_mid + 0.06667 * (lz_west_deg - lon_west_deg) + sc) - 12.0);
    const double ws = sunset_hour_angle_rad(lat, doy);
    const double w1 = std::clamp(w - kPi * duration_h / 24.0, -ws, ws);
    const double w2 = std::clamp(w + kPi * duration_h / 24.0, -ws, ws);
    if (w2 <= w1) return 0.0;
    const double d = solar_declination_rad(doy);
    const double ra = 12.0 * kMinutesPerHour / kPi * kSolarConstant *
                      inverse_relative_distance(doy) *
                      ((w2 - w1) * std::sin(lat) * std::sin(d) +
                       std::cos(lat) * std::cos(d) * (std::sin(w2) - std::sin(w1)));
    return std::max(0.0, ra);
}

double clear_sky_radiation(double ra, double z) {
    return (0.75 + 2e-5 * z) * ra;
}
double solar_from_sunshine(double n, double N, double ra) {
    return (kAngstromA + kAngstromB * n / N) * ra;
}
double solar_from_temperature(double tmax, double tmin, double ra, double krs) {
    return krs * std::sqrt(std::max(0.0, tmax - tmin)) * ra;
}

double net_longwave_daily(double tmax, double tmin, double ea, double rs, double rso) {
    const double tk4 = (std::pow(tmax + kKelvin, 4) + std::pow(tmin + kKelvin, 4)) / 2.0;
    return kStefanBoltzmannDaily * tk4 * rnl_humidity_factor(ea) *
           rnl_cloud_factor(rso > 0 ? rs / rso : 0.0);
}

double net_longwave_hourly(double t, double ea, double rs_over_rso) {
    return kStefanBoltzmannHourly * std::pow(t + kKelvin, 4) * rnl_humidity_factor(ea) *
           rnl_cloud_factor(rs_over_rso);
}

std::string wind_function_name(WindFunction w) {
    switch (w) {
    case WindFunction::penman1948:
        return "penman1948 (2.626 + 1.381 u2)";
    case WindFunction::penman1956:
        return "penman1956 (1.313 + 1.381 u2)";
    case WindFunction::shuttleworth1993:
        return "shuttleworth1993 (6.43 (1 + 0.536 u2) / lambda)";
    }
    return "?";
}

double wind_function(WindFunction w, double u2) {
    switch (w) {
    case WindFunction::penman1948:
        return 2.626 + 1.381 * u2;
    case WindFunction::penman1956:
        return 1.313 + 1.381 * u2;
    case WindFunction::shuttleworth1993:
        return 6.43 * (1.0 + 0.536 * u2) / kLatentHeat_MJ_per_kg;
    }
    return 0.0;
}

std::string method_name(Method m) {
    switch (m) {
    case Method::fao56:
        return "fao56";
    case Method::penman_open_water:
        return "penman-open-water";
    case Method::penman_bare_soil:
        return "penman-bare-soil";
    case Method::penman_grass:
        return "penman-grass";
    }
    return "?";
}

Method parse_method(const std::string& s, const std::string& what) {
    std::string names;
    for (Method m : {Method::fao56, Method::penman_open_water, Method::penman_bare_soil,
                     Method::penman_grass}) {
        if (s == method_name(m)) return m;
        names += (names.empty() ? "" : ", ") + method_name(m);
    }
    throw InputError(what + " must be one of " + names + ", got '" + s + "'");
}

const std::vector<std::pair<std::string, WindFunction>>& wind_function_keys() {
    static const std::vector<std::pair<std::string, WindFunction>> keys{
        {"penman1948", WindFunction::penman1948},
        {"penman1956", WindFunction::penman1956},
        {"shuttleworth1993", WindFunction::shuttleworth1993}};
    return keys;
}

WindFunction parse_wind_function(const std::string& s, const std::string& what) {
    static const std::vector<std::pair<std::string, WindFunction>> short_forms{
        {"1948", WindFunction::penman1948},
        {"1956", WindFunction::penman1956},
        {"shuttleworth", WindFunction::shuttleworth1993}};
    std::string names;
    for (const auto* list : {&wind_function_keys(), &short_forms})
        for (const auto& [key, w] : *list) {
            if (s == key) return w;
            names += (names.empty() ? "" : ", ") + key;
        }
    throw InputError(what + " must be one of " + names + ", got '" + s + "'");
}

void DailyWeather::validate() const {
    auto bad = [](const std::string& what, double v, const char* range) {
        throw InputError(what + " = " + format_number(v) + " is outside " + range);
    };
    if (!(lat_deg >= -90 && lat_deg <= 90)) bad("latitude (deg)", lat_deg, "[-90, 90]");
    if (!(elevation_m > -500 && elevation_m < 9000))
        bad("elevation (m)", elevation_m, "(-500, 9000)");
    if (doy < 1 || doy > 366) bad("day of year", doy, "[1, 366]");
    if (!(tmin_c > -90 && tmin_c < 60)) bad("tmin (degC)", tmin_c, "(-90, 60)");
    if (!(tmax_c > -90 && tmax_c < 60)) bad("tmax (degC)", tmax_c, "(-90, 60)");
    if (tmax_c < tmin_c)
        throw InputError("tmax (" + format_number(tmax_c) + " degC) is below tmin (" +
                         format_number(tmin_c) + " degC)");
    for (auto [v, name] : {std::pair{rh_min_pct, "rh min (%)"}, std::pair{rh_max_pct, "rh max (%)"},
                           std::pair{rh_mean_pct, "rh mean (%)"}})
        if (v && !(*v >= 0 && *v <= 100)) bad(name, *v, "[0, 100]");
    if (rh_min_pct.has_value() != rh_max_pct.has_value())
        throw InputError("give both rh min and rh max, or neither");
    if (rh_min_pct && rh_max_pct && *rh_min_pct > *rh_max_pct)
        throw InputError("rh min (" + format_number(*rh_min_pct) + " %) exceeds rh max (" +
                         format_number(*rh_max_pct) + " %)");
    if (!(u2_m_per_s >= 0 && u2_m_per_s < 100))
        bad("wind speed at 2 m (m/s)", u2_m_per_s, "[0, 100)");
    if (rs_mj && !(*rs_mj >= 0 && *rs_mj < 50))
        bad("solar radiation (MJ m-2 day-1)", *rs_mj, "[0, 50)");
    if (rs_mj && sunshine_h) throw InputError("give solar radiation or sunshine hours, not both");
    if (sunshine_h && !(*sunshine_h >= 0 && *sunshine_h <= 24))
        bad("sunshine hours", *sunshine_h, "[0, 24]");
    if (ea_kpa && !(*ea_kpa >= 0 && *ea_kpa < 10))
        bad("actual vapour pressure (kPa)", *ea_kpa, "[0, 10)");
}

DailyTerms daily_terms(const DailyWeather& w, double albedo, bool fao_svp) {
    w.validate();
    auto svp = [&](double t) { return fao_svp ? svp_fao_kpa(t) : svp_water_kpa(t); };
    DailyTerms d{};
    const double tmean = 0.5 * (w.tmax_c + w.tmin_c);
    const double lat = w.lat_deg * kPi / 180.0;
    d.pressure_kpa = atmospheric_pressure_kpa(w.elevation_m);
    d.gamma = psychrometric_constant_kpa(d.pressure_kpa);
    d.es = 0.5 * (svp(w.tmax_c) + svp(w.tmin_c));
    d.delta = fao_svp ? svp_slope_fao_kpa(tmean) : svp_slope_water_kpa(tmean);
    if (w.ea_kpa) {
        d.ea = *w.ea_kpa;
        d.humidity_from = "ea";
    } else if (w.tdew_c) {
        d.ea = svp(*w.tdew_c);
        d.humidity_from = "dew point";
    } else if (w.rh_min_pct && w.rh_max_pct) {
        d.ea = (svp(w.tmin_c) * *w.rh_max_pct + svp(w.tmax_c) * *w.rh_min_pct) / 200.0;
        d.humidity_from = "rh min/max";
    } else if (w.rh_mean_pct) {
        d.ea = *w.rh_mean_pct / 100.0 * d.es;
        d.humidity_from = "rh mean";
    } else {
        d.ea = svp(w.tmin_c); // FAO-56 s3: Tdew ~ Tmin when humidity is missing
        d.humidity_from = "tmin as dew point (FAO-56 missing-humidity rule)";
    }
    d.ra = extraterrestrial_radiation_daily(lat, w.doy);
    d.rso = clear_sky_radiation(d.ra, w.elevation_m);
    if (w.rs_mj) {
        d.rs = *w.rs_mj;
        d.radiation_from = "rs";
    } else if (w.sunshine_h) {
        d.rs = solar_from_sunshine(*w.sunshine_h, daylight_hours(lat, w.doy), d.ra);
        d.radiation_from = "sunshine hours (Angstrom 0.25/0.50)";
    } else {
        d.rs = solar_from_temperature(w.tmax_c, w.tmin_c, d.ra);
        d.radiation_from = "Hargreaves temperature estimate (kRs 0.16)";
    }
    d.rnl = net_longwave_daily(w.tmax_c, w.tmin_c, d.ea, d.rs, d.rso);
    d.albedo = albedo;
    d.rn = (1.0 - albedo) * d.rs - d.rnl;
    d.g = w.soil_heat_flux_mj;
    return d;
}

double fao56_reference_daily(const DailyWeather& w, DailyTerms* terms) {
    const DailyTerms d = daily_terms(w, kAlbedoGrass, true);
    if (terms) *terms = d;
    const double tmean = 0.5 * (w.tmax_c + w.tmin_c);
    return (0.408 * d.delta * (d.rn - d.g) +
            d.gamma * kCnDaily / (tmean + 273.0) * w.u2_m_per_s * (d.es - d.ea)) /
           (d.delta + d.gamma * (1.0 + kCd * w.u2_m_per_s));
}

double penman_open_water(const DailyWeather& w, WindFunction f, DailyTerms* terms, double albedo) {
    const DailyTerms d = daily_terms(w, albedo, false);
    if (terms) *terms = d;
    return (d.delta * (d.rn - d.g) / kLatentHeat_MJ_per_kg +
            d.gamma * wind_function(f, w.u2_m_per_s) * (d.es - d.ea)) /
           (d.delta + d.gamma);
}

double penman_grass_factor(double lat_deg, int doy) {
    // Month from the day of year (non-leap); southern hemisphere shifted by six months.
    static constexpr int kMonthEnd[12] = {31, 59, 90, 120, 151, 181, 212, 243, 273, 304, 334, 365};
    int month = 0;
    while (month < 11 && doy > kMonthEnd[month]) ++month;
    if (lat_deg < 0) month = (month + 6) % 12;
    static constexpr double kFactor[12] = {0.6, 0.6, 0.7, 0.7, 0.8, 0.8,
                                           0.8, 0.8, 0.7, 0.7, 0.6, 0.6};
    return kFactor[month];
}

double evapotranspiration(Method m, const DailyWeather& w, WindFunction f, DailyTerms* terms) {
    switch (m) {
    case Method::fao56:
        return fao56_reference_daily(w, terms);
    case Method::penman_open_water:
        return penman_open_water(w, f, terms);
    case Method::penman_bare_soil:
        return kPenmanBareSoilFactor * penman_open_water(w, f, terms);
    case Method::penman_grass:
        return penman_grass_factor(w.lat_deg, w.doy) * penman_open_water(w, f, terms);
    }
    return 0.0;
}

double fao56_reference_hourly(const HourlyWeather& w, DailyTerms* terms) {
    DailyTerms d{};
    const double lat = w.lat_deg * kPi / 180.0;
    d.pressure_kpa = atmospheric_pressure_kpa(w.elevation_m);
    d.gamma = psychrometric_constant_kpa(d.pressure_kpa);
    d.es = svp_fao_kpa(w.t_c);
    d.ea = d.es * w.rh_pct / 100.0;
    d.delta = svp_slope_fao_kpa(w.t_c);
    d.ra = extraterrestrial_radiation_hourly(lat, w.lon_west_deg, w.lz_west_deg, w.doy, w.hour_end);
    d.rso = clear_sky_radiation(d.ra, w.elevation_m);
    d.rs = w.rs_mj;
    const bool day = d.ra > 0.0 && d.rso > 0.0;
    d.rnl = net_longwave_hourly(w.t_c, d.ea, day ? d.rs / d.rso : w.night_rs_over_rso);
    d.albedo = kAlbedoGrass;
    d.rn = (1.0 - kAlbedoGrass) * d.rs - d.rnl;
    d.g = (day ? kGDay : kGNight) * d.rn;
    d.humidity_from = "rh";
    d.radiation_from = "rs";
    if (terms) *terms = d;
    return (0.408 * d.delta * (d.rn - d.g) +
            d.gamma * kCnHourly / (w.t_c + 273.0) * w.u2_m_per_s * (d.es - d.ea)) /
           (d.delta + d.gamma * (1.0 + kCd * w.u2_m_per_s));
}

} // namespace ecoterra::hydro::et
