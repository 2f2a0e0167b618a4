#pragma once
// Evapotranspiration: pure functions, each with its equation and reference. Units: temperatures in
// deg C, vapour pressures in kPa, their slope in kPa/degC, radiation in MJ m-2 day-1 (daily) or
// MJ m-2 h-1 (hourly), wind at 2 m in m/s, elevation in m, latitude in radians unless named _deg,
// evaporation in mm/day (mm/h hourly), which equals kg m-2 per day.
//
// Saturation vapour pressure, improved Magnus (Alduchov & Eskridge 1996, J. Appl. Meteor. 35:601):
//   over water e = 0.61094 exp(17.625 T / (T + 243.04))   (AERK, -40..50 degC)
//   over ice   e = 0.61121 exp(22.587 T / (T + 273.86))   (AERKi, -80..0 degC)
//   slope      de/dT = e b c / (c + T)^2
// FAO-56 (Allen et al. 1998) uses its own Tetens form e = 0.6108 exp(17.27 T / (T + 237.3))
// (eq. 11); the FAO-56 reference ET below uses it so that the FAO examples are reproduced, while
// the Penman equations of the ecoterra model (paper 002 s4.2) use the improved Magnus form.
//
// FAO-56 auxiliaries: P = 101.3 ((293 - 0.0065 z) / 293)^5.26 (eq. 7); gamma = cp P / (eps lambda)
// (eq. 8, unrounded: 0.000664742 P);
// Ra (eq. 21 daily, eq. 28 hourly), N = 24 ws / pi (eq. 34), Rs = (0.25 + 0.5 n/N) Ra (eq. 35),
// Rs = kRs sqrt(Tmax - Tmin) Ra (eq. 50), Rso = (0.75 + 2e-5 z) Ra (eq. 37),
// Rnl = sigma ((Tmax,K^4 + Tmin,K^4)/2) (0.34 - 0.14 sqrt(ea)) (1.35 Rs/Rso - 0.35) (eq. 39),
// Rn = (1 - albedo) Rs - Rnl (eqs 38, 40).
//
// Penman (1948) combination equation for a free water surface:
//   E0 = [Delta Rn / lambda + gamma f(u) (es - ea)] / (Delta + gamma)          (mm/day)
// with lambda = 2.45 MJ/kg and the wind function f(u) = a + b u2 in mm day-1 kPa-1. Which constant
// belongs to which year is a known trap (reference hydrology.md s1.1): ecoterra's default is
// f(u) = 2.626 + 1.381 u2 ("Penman 1948" in the R package Evapotranspiration, 0.35(1 + u/100) in
// Penman's mmHg and miles/day), with 1.313 + 1.381 u2 ("1956") and Shuttleworth's (1993)
// 6.43 (1 + 0.536 u2) / lambda = 2.624 + 1.407 u2 selectable. Open-water albedo 0.08.
// Bare soil and grass use Penman's surface factors on E0 (Penman 1948; the values are as recalled
// in reference hydrology.md s1.1 and are stated as such in docs/hydrology.md): freshly wetted bare
// soil 0.9 E0; grass (turf) 0.8 in May-Aug, 0.7 in Mar-Apr and Sep-Oct, 0.6 in Nov-Feb (northern
// hemisphere; shifted by six months in the southern).
//
// FAO-56 Penman-Monteith reference ET (eq. 6; hourly eq. 53):
//   ETo = [0.408 Delta (Rn - G) + gamma Cn/(T + 273) u2 (es - ea)] / [Delta + gamma (1 + Cd u2)]
//   with Cn/Cd = 900/0.34 daily and 37/0.34 hourly (grass reference).
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace ecoterra::hydro::et {

inline constexpr double kLatentHeat_MJ_per_kg = 2.45;       ///< lambda, FAO-56
inline constexpr double kStefanBoltzmannDaily = 4.903e-9;   ///< MJ K-4 m-2 day-1
inline constexpr double kStefanBoltzmannHourly = 2.043e-10; ///< MJ K-4 m-2 h-1
inline constexpr double kSolarConstant = 0.0820;            ///< Gsc, MJ m-2 min-1
inline constexpr double kKelvin = 273.16;                   ///< FAO-56 uses 273.16 in eq. 39
inline constexpr double kAlbedoGrass = 0.23;
inline constexpr double kAlbedoOpenWater = 0.08;

// -- vapour pressure ----------------------------------------------------------------------------
double svp_water_kpa(double t_c);       ///< AERK over water
double svp_ice_kpa(double t_c);         ///< AERKi over ice
double svp_slope_water_kpa(double t_c); ///< d(AERK)/dT, kPa/degC
double svp_fao_kpa(double t_c);         ///< FAO-56 eq. 11
double svp_slope_fao_kpa(double t_c);   ///< FAO-56 eq. 13

// -- atmosphere and radiation -------------------------------------------------------------------
double atmospheric_pressure_kpa(double elevation_m);              ///< FAO-56 eq. 7
double psychrometric_constant_kpa(double pressure_kpa);           ///< FAO-56 eq. 8
double inverse_relative_distance(int doy);                        ///< dr, eq. 23
double solar_declination_rad(int doy);                            ///< delta, eq. 24
double sunset_hour_angle_rad(double lat_rad, int doy);            ///< ws, eq. 25
double extraterrestrial_radiation_daily(double lat_rad, int doy); ///< Ra, eq. 21
double daylight_hours(double lat_rad, int doy);                   ///< N, eq. 34
/// Ra for one hour ending at `hour_end` local standard time (FAO-56 eqs 28-33); longitudes are
/// degrees west of Greenwich (FAO convention), lz the centre of the time zone.
double extraterrestrial_radiation_hourly(double lat_rad, double lon_west_deg, double lz_west_deg,
                                         int doy, double hour_end, double duration_h = 1.0);
double clear_sky_radiation(double ra, double elevation_m);                   ///< Rso, eq. 37
double solar_from_sunshine(double sunshine_h, double daylight_h, double ra); ///< eq. 35
double solar_from_temperature(double tmax_c, double tmin_c, double ra,
                              double krs = 0.16); ///< eq. 50
double net_longwave_daily(double tmax_c, double tmin_c, double ea_kpa, double rs, double rso);
double net_longwave_hourly(double t_c, double ea_kpa, double rs_over_rso);

// -- daily weather and the methods ---------------------------------------------------------------
/// Penman wind functions f(u) = a + b u2, mm day-1 kPa-1.
enum class WindFunction { penman1948, penman1956, shuttleworth1993 };
std::string wind_function_name(WindFunction w);
double wind_function(WindFunction w, double u2_m_per_s);
/// The keys of the wind functions (`penman1948`, `penman1956`, `shuttleworth1993`): the one list
/// the scene catalogue and the `hydro et` option read.
const std::vector<std::pair<std::string, WindFunction>>& wind_function_keys();
/// The wind function of a key, or of its short form (`1948`, `1956`, `shuttleworth`); throws
/// InputError naming `what`, the value and the accepted keys otherwise.
WindFunction parse_wind_function(const std::string& s, const std::string& what);

enum class Method { fao56, penman_open_water, penman_bare_soil, penman_grass };
std::string method_name(Method m);
/// The method of a name (`fao56`, `penman-open-water`, `penman-bare-soil`, `penman-grass`);
/// throws InputError naming `what`, the value and the accepted names otherwise.
Method parse_method(const std::string& s, const std::string& what);

/// One day's weather at a site. Give humidity as rh_min/rh_max, rh_mean, tdew or ea; solar
/// radiation as rs or sunshine hours (else Hargreaves' temperature estimate, kRs 0.16).
struct DailyWeather {
    double lat_deg = 0, elevation_m = 0;
    int doy = 1;
    double tmin_c = 0, tmax_c = 0;
    std::optional<double> rh_min_pct, rh_max_pct, rh_mean_pct, tdew_c, ea_kpa;
    double u2_m_per_s = 2.0;
    std::optional<double> rs_mj, sunshine_h;
    double soil_heat_flux_mj = 0.0; ///< G, 0 for daily steps
    void validate() const;
};

/// Intermediates of a daily computation (units as in the header).
struct DailyTerms {
    double pressure_kpa, gamma, es, ea, delta, ra, rso, rs, rnl, rn, albedo, g;
    const char* humidity_from = "";  ///< which input gave ea
    const char* radiation_from = ""; ///< which input gave Rs
};

/// The terms for `albedo`, with vapour pressures from FAO-56's Tetens (fao = true) or the improved
/// Magnus form.
DailyTerms daily_terms(const DailyWeather& w, double albedo, bool fao_svp);

/// FAO-56 Penman-Monteith grass reference ET, mm/day.
double fao56_reference_daily(const DailyWeather& w, DailyTerms* terms = nullptr);
/// Penman open-water evaporation E0, mm/day (improved Magnus; albedo 0.08 unless given).
double penman_open_water(const DailyWeather& w, WindFunction f = WindFunction::penman1948,
                         DailyTerms* terms = nullptr, double albedo = kAlbedoOpenWater);
/// Penman's surface factors.
double penman_grass_factor(double lat_deg, int doy);
inline constexpr double kPenmanBareSoilFactor = 0.9;
/// ET by any method, mm/day.
double evapotranspiration(Method m, const DailyWeather& w,
                          WindFunction f = WindFunction::penman1948, DailyTerms* terms = nullptr);

/// FAO-56 hourly Penman-Monteith (eq. 53) for one hour; G = 0.1 Rn by day, 0.5 Rn by night.
struct HourlyWeather {
    double lat_deg = 0, lon_west_deg = 0, lz_west_deg = 0, elevation_m = 0;
    int doy = 1;
    double hour_end = 12; ///< local standard time at the end of the hour, h
    double t_c = 20, rh_pct = 50, u2_m_per_s = 2, rs_mj = 0;
    double night_rs_over_rso = 0.8; ///< Rs/Rso to use when the sun is down (FAO-56 Ex. 19)
};
double fao56_reference_hourly(const HourlyWeather& w, DailyTerms* terms = nullptr);

} // namespace ecoterra::hydro::et
