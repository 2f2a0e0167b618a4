#pragma once
// Daily weather: a stochastic generator and a reader for observed series.
//
// Generator (after WGEN, Richardson 1981 Water Resour. Res. 17:182, and Richardson & Wright 1984):
// - occurrence: a first-order two-state Markov chain with transition probabilities P(W|D) and
//   P(W|W), each with a seasonal harmonic p(d) = p0 (1 + a cos(2 pi (d - d_peak) / 365));
// - amount on wet days: a gamma distribution (skewed), shape k, mean m(d) with the same harmonic;
//   draws by Marsaglia & Tsang (2000);
// - temperature: Tmax and Tmin = mean + amplitude cos(2 pi (d - d_warm) / 365), Tmax lowered on
//   wet days, plus AR(1) anomalies (lag-1 correlation rho, standard deviation sigma);
// - humidity: dew point = Tmin - depression (harmonic; smaller on wet days);
// - wind at 2 m: a harmonic mean times a gamma(4, 1/4) factor (mean 1, CV 0.5);
// - solar radiation: Rs = f Rso with Rso from latitude and day of year (FAO-56 eqs 21, 37) and
//   f drawn around 0.85 on dry days and 0.45 on wet days, clamped to [0.25 Ra, Rso].
// The year has 365 days. Everything is seeded: the same climate and seed give the same series.
//
// Observed series (CSV): see docs/formats.md. Missing values are filled as FAO-56 (Allen et al.
// 1998) ch. 3 recommends and every fill is counted: humidity from Tdew = Tmin, radiation from
// Hargreaves' Rs = 0.16 sqrt(Tmax - Tmin) Ra, wind 2 m/s; missing temperatures are interpolated
// linearly between the nearest observed days; missing rain is taken as 0.
#include "ecoterra/catalog.hpp"
#include "ecoterra/random.hpp"

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace ecoterra::hydro {

/// One day's weather. Units: degC, mm/day, %, m/s, MJ m-2 day-1.
struct DayWeather {
    int year = 1; ///< 1-based simulation year (or calendar year for observations)
    int doy = 1;  ///< day of year, 1..366
    double tmin_c = 10, tmax_c = 20, rain_mm = 0;
    double tdew_c = 8; ///< dew point (always filled)
    double u2_m_per_s = 2;
    double rs_mj = 15; ///< solar radiation (always filled)
};

/// Days in a simulated year: the weather generator's year has no leap days (observed weather
/// follows the calendar, days_in_calendar_year). The one definition ecoterra uses.
inline constexpr int kDaysPerYear = 365;

struct Climate {
    std::string name = "custom";
    double latitude_deg = 33.5, elevation_m = 100;
    // Occurrence and amounts.
    double p_wet_after_dry = 0.25, p_wet_after_wet = 0.5;
    double precip_seasonal_amplitude = 0.0; ///< a of the harmonic, in [-0.9, 0.9]
    int precip_peak_doy = 180;
    double wet_day_mean_mm = 12.9, gamma_shape = 0.75;
    // Temperature.
    double tmax_mean_c = 24, tmax_amplitude_c = 9, tmin_mean_c = 12, tmin_amplitude_c = 10;
    int warmest_doy = 200;
    double wet_day_tmax_drop_c = 2.0, temperature_sd_c = 2.5, temperature_lag1 = 0.6;
    // Humidity, wind, radiation.
    double dew_depression_mean_c = 4.0, dew_depression_amplitude_c = 1.0;
    double wind_mean_m_per_s = 2.0, wind_amplitude_m_per_s = 0.3;
    double dry_radiation_fraction = 0.85, wet_radiation_fraction = 0.45;
    void validate() const;
    /// Long-run mean annual rain implied by the parameters (ignoring the harmonic), mm/year.
    double expected_annual_rain_mm() const;
};

/// The generator's parameters as scene keys (section "climate"): key, unit, default, range.
const ParamCatalog<Climate>& climate_catalog();

/// Presets are data files, data/climates/NAME.json (every catalogue key, plus "description"):
/// "humid_subtropical" (the paper's forest, about 62 in = 1575 mm a year), "semi_arid_desert"
/// (about 300 mm, summer monsoon), "temperate" (about 800 mm).
Climate climate_preset(const std::string& name);
std::vector<std::string> climate_presets();
/// Reads a climate file (strict: unknown keys are errors); its name is the file's stem.
Climate load_climate_file(const std::filesystem::path& path);

class WeatherGenerator {
public:
    WeatherGenerator(const Climate& c, std::uint64_t seed);
    /// The next day (advances the state).
    DayWeather next();
    /// Generator state, for checkpoints.
    /// Written to checkpoints byte for byte, so it has no padding (no uninitialised bytes).
    struct State {
        std::array<std::uint64_t, 4> rng{};
        std::uint64_t wet = 0; ///< 1 if the last day was wet
        double tmax_anomaly = 0, tmin_anomaly = 0;
        std::int32_t year = 1, doy = 0;
    };
    static_assert(sizeof(State) == 4 * 8 + 8 + 2 * 8 + 2 * 4, "State must have no padding");
    State state() const;
    void set_state(const State& s);
    const Climate& climate() const { return m_c; }

private:
    double gamma(double shape);
    Climate m_c;
    Rng m_rng;
    bool m_wet = false;
    double m_tmax_anom = 0, m_tmin_anom = 0;
    int m_year = 1, m_doy = 0;
};

/// 366 in Gregorian leap years, else 365.
int days_in_calendar_year(int year);

struct WeatherSeries {
    std::vector<DayWeather> days;
    std::map<std::string, int> filled; ///< what was filled how often ("rs: Hargreaves", ...)
    double latitude_deg = 0, elevation_m = 0;
    std::string source; ///< the file read
};

/// One line per kind of filled value: "FILE: N of M days filled: what" (empty if none).
std::vector<std::string> fill_report(const WeatherSeries& ws);

/// Reads a daily CSV (header: date,tmin_c,tmax_c,rain_mm and optionally rh_min_pct, rh_max_pct,
/// rh_mean_pct, tdew_c, u2_m_per_s, rs_mj_per_m2_day; empty or NA = missing), filling gaps.
WeatherSeries read_weather_csv(const std::filesystem::path& path, double latitude_deg,
                               double elevation_m);

} // namespace ecoterra::hydro
