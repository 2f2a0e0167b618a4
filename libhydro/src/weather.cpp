#include "ecoterra/hydro/weather.hpp"

#include "ecoterra/data_dir.hpp"
#include "ecoterra/error.hpp"
#include "ecoterra/hydro/penman.hpp"
#include "ecoterra/io/atomic_file.hpp"
#include "ecoterra/json_util.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <sstream>

namespace ecoterra::hydro {

namespace {

constexpr double kRadiationNoiseSd = 0.08; ///< of the clear-sky fraction
constexpr double kWindGammaShape = 4.0;    ///< daily wind factor: mean 1, CV 0.5
constexpr double kMinDiurnalRangeC = 0.5;
constexpr double kWetDewDepressionFactor = 0.3; ///< wet days: depression x 0.3
constexpr double kMinRadiationOfRa = 0.25;
constexpr double kDefaultWindMPerS = 2.0; ///< FAO-56 s3 global average at 2 m
constexpr double kHargreavesKrs = 0.16;

double harmonic(double mean, double amplitude, int peak, int doy) {
    return mean + amplitude * std::cos(2 * std::numbers::pi * (doy - peak) / kDaysPerYear);
}

} // namespace

const ParamCatalog<Climate>& climate_catalog() {
    using C = Climate;
    static const ParamCatalog<C> c(
        "climate",
        {number<C>("latitude_deg", &C::latitude_deg, "deg", -90, 90, "site latitude (north +)"),
         number<C>("elevation_m", &C::elevation_m, "m", -500, 9000, "site elevation"),
         number<C>("p_wet_after_dry", &C::p_wet_after_dry, "1", 0, 1,
                   "Markov chain: probability of a wet day after a dry day"),
         number<C>("p_wet_after_wet", &C::p_wet_after_wet, "1", 0, 1,
                   "Markov chain: probability of a wet day after a wet day"),
         number<C>("precip_seasonal_amplitude", &C::precip_seasonal_amplitude, "1", -0.9, 0.9,
                   "a of the harmonic p(d) = p0 (1 + a cos(2 pi (d - d_peak) / 365))"),
         integer<C>("precip_peak_doy", &C::precip_peak_doy, "day", 1, 366,
                    "day of year of the wettest season"),
         number<C>("wet_day_mean_mm", &C::wet_day_mean_mm, "mm", 0, 500, "mean rain of a wet day"),
         number<C>("gamma_shape", &C::gamma_shape, "1", 0.05, 20,
                   "shape of the gamma distribution of wet-day amounts"),
         number<C>("tmax_mean_c", &C::tmax_mean_c, "degC", -60, 60,
                   "annual mean of the daily maximum temperature"),
         number<C>("tmax_amplitude_c", &C::tmax_amplitude_c, "degC", 0, 40,
                   "seasonal amplitude of the daily maximum"),
         number<C>("tmin_mean_c", &C::tmin_mean_c, "degC", -60, 60,
                   "annual mean of the daily minimum temperature; at most tmax_mean_c"),
         number<C>("tmin_amplitude_c", &C::tmin_amplitude_c, "degC", 0, 40,
                   "seasonal amplitude of the daily minimum"),
         integer<C>("warmest_doy", &C::warmest_doy, "day", 1, 366,
                    "day of year of the warmest season"),
         number<C>("wet_day_tmax_drop_c", &C::wet_day_tmax_drop_c, "degC", 0, 20,
                   "the maximum temperature is lower by this on wet days"),
         number<C>("temperature_sd_c", &C::temperature_sd_c, "degC", 0, 20,
                   "standard deviation of the daily temperature anomalies"),
         number<C>("temperature_lag1", &C::temperature_lag1, "1", 0, 0.99,
                   "lag-1 autocorrelation of the temperature anomalies"),
         number<C>("dew_depression_mean_c", &C::dew_depression_mean_c, "degC", 0, 40,
                   "mean of Tmin - Tdew"),
         number<C>("dew_depression_amplitude_c", &C::dew_depression_amplitude_c, "degC", 0, 40,
                   "seasonal amplitude of the dew-point depression"),
         number<C>("wind_mean_m_per_s", &C::wind_mean_m_per_s, "m/s", 0, 30,
                   "mean wind speed at 2 m"),
         number<C>("wind_amplitude_m_per_s", &C::wind_amplitude_m_per_s, "m/s", 0, 30,
                   "seasonal amplitude of the wind speed"),
         number<C>("dry_radiation_fraction", &C::dry_radiation_fraction, "1", 0.1, 1,
                   "solar radiation of a dry day as a fraction of the clear-sky value"),
         number<C>("wet_radiation_fraction", &C::wet_radiation_fraction, "1", 0.1, 1,
                   "solar radiation of a wet day as a fraction of the clear-sky value")});
    return c;
}

void Climate::validate() const {
    climate_catalog().check(*this, "climate " + name);
    if (tmax_mean_c < tmin_mean_c)
        throw InputError("climate " + name + ": tmax_mean_c is below tmin_mean_c");
}

double Climate::expected_annual_rain_mm() const {
    const double wet_fraction = p_wet_after_dry / (1.0 + p_wet_after_dry - p_wet_after_wet);
    return kDaysPerYear * wet_fraction * wet_day_mean_mm;
}

std::vector<std::string> climate_presets() {
    std::vector<std::string> names;
    std::error_code ec;
    for (const auto& e : std::filesystem::directory_iterator(data_dir() / "climates", ec))
        if (e.path().extension() == ".json") names.push_back(e.path().stem().string());
    std::sort(names.begin(), names.end());
    return names;
}

Climate climate_preset(const std::string& name) {
    const auto path = data_dir() / "climates" / (name + ".json");
    std::error_code ec;
    if (name.empty() || name.find('/') != std::string::npos ||
        !std::filesystem::is_regular_file(path, ec)) {
        std::string list;
        for (const auto& n : climate_presets()) list += (list.empty() ? "" : ", ") + n;
        throw InputError("unknown climate preset '" + name + "' (" + list + "; files in " +
                         (data_dir() / "climates").string() + ")");
    }
    return load_climate_file(path);
}

Climate load_climate_file(const std::filesystem::path& path) {
    const auto j = parse_json(io::read_text(path), path.string());
    Climate c;
    c.name = path.stem().string();
    c = climate_catalog().read(j, c, {"description"}, path.string());
    c.validate();
    return c;
}

WeatherGenerator::WeatherGenerator(const Climate& c, std::uint64_t seed)
    : m_c(c), m_rng(seed, "hydro.weather") {
    m_c.validate();
}

double WeatherGenerator::gamma(double shape) {
    // Marsaglia & Tsang (2000); shape < 1 by the boost gamma(k + 1) U^(1/k).
    if (shape < 1.0) return gamma(shape + 1.0) * std::pow(m_rng.uniform(), 1.0 / shape);
    const double d = shape - 1.0 / 3.0, c = 1.0 / std::sqrt(9.0 * d);
    for (;;) {
        double x, v;
        do {
            x = m_rng.normal();
            v = 1.0 + c * x;
        } while (v <= 0);
        v = v * v * v;
        const double u = m_rng.uniform();
        if (u < 1.0 - 0.0331 * x * x * x * x) return d * v;
        if (std::log(u) < 0.5 * x * x + d * (1.0 - v + std::log(v))) return d * v;
    }
}

DayWeather WeatherGenerator::next() {
    if (++m_doy > kDaysPerYear) {
        m_doy = 1;
        ++m_year;
    }
    DayWeather w;
    w.year = m_year;
    w.doy = m_doy;
    const double season = harmonic(1.0, m_c.precip_seasonal_amplitude, m_c.precip_peak_doy, m_doy);
    const double p =
        std::clamp((m_wet ? m_c.p_wet_after_wet : m_c.p_wet_after_dry) * season, 0.0, 1.0);
    m_wet = m_rng.uniform() < p;
    w.rain_mm = m_wet ? gamma(m_c.gamma_shape) * m_c.wet_day_mean_mm / m_c.gamma_shape : 0.0;
    const double rho = m_c.temperature_lag1;
    const double innov = std::sqrt(1.0 - rho * rho) * m_c.temperature_sd_c;
    m_tmax_anom = rho * m_tmax_anom + innov * m_rng.normal();
    m_tmin_anom = rho * m_tmin_anom + innov * m_rng.normal();
    w.tmax_c = harmonic(m_c.tmax_mean_c, m_c.tmax_amplitude_c, m_c.warmest_doy, m_doy) +
               m_tmax_anom - (m_wet ? m_c.wet_day_tmax_drop_c : 0.0);
    w.tmin_c =
        harmonic(m_c.tmin_mean_c, m_c.tmin_amplitude_c, m_c.warmest_doy, m_doy) + m_tmin_anom;
    if (w.tmax_c < w.tmin_c + kMinDiurnalRangeC) {
        const double mid = 0.5 * (w.tmax_c + w.tmin_c);
        w.tmax_c = mid + 0.5 * kMinDiurnalRangeC;
        w.tmin_c = mid - 0.5 * kMinDiurnalRangeC;
    }
    const double dep =
        std::max(0.0, harmonic(m_c.dew_depression_mean_c, m_c.dew_depression_amplitude_c,
                               m_c.warmest_doy, m_doy));
    w.tdew_c = w.tmin_c - (m_wet ? kWetDewDepressionFactor * dep : dep);
    w.u2_m_per_s = std::max(0.0, harmonic(m_c.wind_mean_m_per_s, m_c.wind_amplitude_m_per_s,
                                          m_c.warmest_doy + 182, m_doy)) *
                   gamma(kWindGammaShape) / kWindGammaShape;
    const double lat = m_c.latitude_deg * std::numbers::pi / 180.0;
    const double ra = et::extraterrestrial_radiation_daily(lat, m_doy);
    const double rso = et::clear_sky_radiation(ra, m_c.elevation_m);
    const double f = (m_wet ? m_c.wet_radiation_fraction : m_c.dry_radiation_fraction) +
                     kRadiationNoiseSd * m_rng.normal();
    w.rs_mj = std::clamp(f * rso, std::min(kMinRadiationOfRa * ra, rso), rso);
    return w;
}

WeatherGenerator::State WeatherGenerator::state() const {
    return State{m_rng.state(), m_wet ? 1u : 0u, m_tmax_anom, m_tmin_anom, m_year, m_doy};
}

void WeatherGenerator::set_state(const State& s) {
    m_rng.set_state(s.rng);
    m_wet = s.wet != 0;
    m_tmax_anom = s.tmax_anomaly;
    m_tmin_anom = s.tmin_anomaly;
    m_year = s.year;
    m_doy = s.doy;
}

namespace {

bool leap(int y) {
    return (y % 4 == 0 && y % 100 != 0) || y % 400 == 0;
}

/// Parses YYYY-MM-DD into (year, day of year).
int days_in_month(int year, int month) {
    static constexpr int kDays[12] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
    return kDays[month - 1] + (month == 2 && leap(year) ? 1 : 0);
}

/// (year, day of year) of a YYYY-MM-DD date; a day the calendar does not have is refused.
std::pair<int, int> parse_date(const std::string& s, const std::string& where) {
    int y = 0, m = 0, d = 0;
    char c1 = 0, c2 = 0;
    std::istringstream in(s);
    const bool read = static_cast<bool>(in >> y >> c1 >> m >> c2 >> d) && (in >> std::ws).eof();
    if (!read || c1 != '-' || c2 != '-' || m < 1 || m > 12 || d < 1)
        throw InputError(where + ": date must be YYYY-MM-DD, got '" + s + "'");
    if (d > days_in_month(y, m))
        throw InputError(where + ": date '" + s + "' does not exist (" + std::to_string(y) +
                         (m == 2 ? (leap(y) ? " is a leap year" : " is not a leap year")
                                 : std::string(" has ") + std::to_string(days_in_month(y, m)) +
                                       " days in that month") +
                         ")");
    int doy = d;
    for (int k = 1; k < m; ++k) doy += days_in_month(y, k);
    return {y, doy};
}

/// YYYY-MM-DD of a (year, day of year).
std::string iso_date(int year, int doy) {
    int m = 1;
    while (m < 12 && doy > days_in_month(year, m)) doy -= days_in_month(year, m++);
    char buf[32];
    std::snprintf(buf, sizeof buf, "%04d-%02d-%02d", year, m, doy);
    return buf;
}

std::vector<std::string> split_csv(const std::string& line) {
    std::vector<std::string> out;
    std::string cur;
    for (char c : line) {
        if (c == ',') {
            out.push_back(cur);
            cur.clear();
        } else if (c != '\r') {
            cur += c;
        }
    }
    out.push_back(cur);
    for (auto& s : out) {
        s.erase(0, s.find_first_not_of(" \t"));
        s.erase(s.find_last_not_of(" \t") + 1);
    }
    return out;
}

} // namespace

namespace {

/// A row of an observed-weather CSV: its day and its values (nullopt where missing).
struct RawDay {
    int year = 0, doy = 0, line = 0;
    std::map<std::string, std::optional<double>> v;
};

/// The columns of the header by name; InputError for an unknown or a missing one.
std::map<std::string, std::size_t> weather_columns(const std::vector<std::string>& header,
                                                   const std::string& where) {
    const std::vector<std::string> known = {
        "date",       "tmin_c",      "tmax_c", "rain_mm",    "rh_min_pct",
        "rh_max_pct", "rh_mean_pct", "tdew_c", "u2_m_per_s", "rs_mj_per_m2_day"};
    std::map<std::string, std::size_t> col;
    for (std::size_t k = 0; k < header.size(); ++k) {
        if (std::find(known.begin(), known.end(), header[k]) == known.end())
            throw InputError(where + ": unknown column '" + header[k] + "'");
        col[header[k]] = k;
    }
    for (const char* req : {"date", "tmin_c", "tmax_c", "rain_mm"})
        if (!col.count(req))
            throw InputError(where + ": missing column '" + std::string(req) + "'");
    return col;
}

/// One data line: its date and values ("", NA and NaN are missing), named by line and column.
RawDay parse_weather_line(const std::vector<std::string>& f,
                          const std::map<std::string, std::size_t>& col, std::size_t fields,
                          int lineno, const std::string& where) {
    const std::string at = where + " line " + std::to_string(lineno);
    if (f.size() != fields)
        throw InputError(at + ": " + std::to_string(f.size()) + " fields, header has " +
                         std::to_string(fields));
    RawDay r{};
    r.line = lineno;
    std::tie(r.year, r.doy) = parse_date(f[col.at("date")], at);
    for (const auto& [name, k] : col) {
        if (name == "date") continue;
        const std::string& s = f[k];
        if (s.empty() || s == "NA" || s == "NaN" || s == "nan") {
            r.v[name] = std::nullopt;
            continue;
        }
        try {
            std::size_t used = 0;
            r.v[name] = std::stod(s, &used);
            if (used != s.size()) throw std::invalid_argument(s);
        } catch (const std::exception&) {
            throw InputError(at + ": " + name + " is not a number: '" + s + "'");
        }
        if (!std::isfinite(*r.v[name]))
            throw InputError(at + ": " + name + " is not a finite number: '" + s + "'");
    }
    return r;
}

/// One row per day, in order, none missing: a model year is a calendar year.
void check_consecutive(const std::vector<RawDay>& rows, const std::string& where) {
    for (std::size_t k = 1; k < rows.size(); ++k) {
        const RawDay &a = rows[k - 1], &b = rows[k];
        const bool next =
            (b.year == a.year && b.doy == a.doy + 1) ||
            (b.year == a.year + 1 && b.doy == 1 && a.doy == days_in_calendar_year(a.year));
        if (next) continue;
        const std::string at = where + " line " + std::to_string(b.line) + ": " +
                               iso_date(b.year, b.doy) + " follows " + iso_date(a.year, a.doy) +
                               " (line " + std::to_string(a.line) + "): ";
        if (b.year == a.year && b.doy == a.doy) throw InputError(at + "the day is given twice");
        if (b.year < a.year || (b.year == a.year && b.doy < a.doy))
            throw InputError(at + "days must be in calendar order");
        const int next_year = a.doy == days_in_calendar_year(a.year) ? a.year + 1 : a.year;
        const int next_doy = a.doy == days_in_calendar_year(a.year) ? 1 : a.doy + 1;
        throw InputError(at + "days must follow one another; " + iso_date(next_year, next_doy) +
                         " is missing (give it a row with empty fields to have it filled)");
    }
}

/// Temperatures: linear interpolation between the nearest observed days.
void interpolate_temperatures(std::vector<RawDay>& rows, WeatherSeries& ws) {
    for (const char* t : {"tmin_c", "tmax_c"}) {
        std::vector<int> have;
        for (int k = 0; k < static_cast<int>(rows.size()); ++k)
            if (rows[k].v[t]) have.push_back(k);
        if (have.empty()) throw InputError(ws.source + ": column " + t + " has no value at all");
        for (int k = 0; k < static_cast<int>(rows.size()); ++k) {
            if (rows[k].v[t]) continue;
            auto hi = std::lower_bound(have.begin(), have.end(), k);
            double v;
            if (hi == have.begin())
                v = *rows[*hi].v[t];
            else if (hi == have.end())
                v = *rows[have.back()].v[t];
            else {
                const int a = *(hi - 1), b = *hi;
                v = *rows[a].v[t] + (*rows[b].v[t] - *rows[a].v[t]) * (k - a) / double(b - a);
            }
            rows[k].v[t] = v;
            ++ws.filled[std::string(t) + ": interpolated"];
        }
    }
}

/// The dew point of a day: observed, from the humidity extremes or mean, or Tmin (FAO-56).
void fill_dew_point(RawDay& r, DayWeather& d, WeatherSeries& ws) {
    auto get = [&](const char* k) { return r.v.count(k) ? r.v[k] : std::nullopt; };
    if (auto td = get("tdew_c"))
        d.tdew_c = *td;
    else if (get("rh_min_pct") && get("rh_max_pct")) {
        const double ea = (et::svp_water_kpa(d.tmin_c) * *get("rh_max_pct") +
                           et::svp_water_kpa(d.tmax_c) * *get("rh_min_pct")) /
                          200.0;
        // Invert improved Magnus for the dew point.
        const double x = std::log(ea / 0.61094);
        d.tdew_c = 243.04 * x / (17.625 - x);
    } else if (auto rh = get("rh_mean_pct")) {
        const double es = 0.5 * (et::svp_water_kpa(d.tmin_c) + et::svp_water_kpa(d.tmax_c));
        const double x = std::log(*rh / 100.0 * es / 0.61094);
        d.tdew_c = 243.04 * x / (17.625 - x);
    } else {
        d.tdew_c = d.tmin_c;
        ++ws.filled["humidity: Tdew = Tmin (FAO-56)"];
    }
}

/// A day with every value, the missing ones filled as FAO-56 recommends (counted in ws.filled).
DayWeather observed_day(RawDay& r, double lat, WeatherSeries& ws) {
    const std::string& where = ws.source;
    DayWeather d;
    d.year = r.year;
    d.doy = r.doy;
    d.tmin_c = *r.v["tmin_c"];
    d.tmax_c = *r.v["tmax_c"];
    if (d.tmax_c < d.tmin_c)
        throw InputError(where + ": tmax below tmin on " + std::to_string(r.year) + " day " +
                         std::to_string(r.doy));
    if (r.v["rain_mm"]) {
        d.rain_mm = *r.v["rain_mm"];
        if (d.rain_mm < 0)
            throw InputError(where + ": negative rain on day " + std::to_string(r.doy));
    } else {
        d.rain_mm = 0;
        ++ws.filled["rain_mm: missing, taken as 0"];
    }
    fill_dew_point(r, d, ws);
    auto get = [&](const char* k) { return r.v.count(k) ? r.v[k] : std::nullopt; };
    if (auto u = get("u2_m_per_s"))
        d.u2_m_per_s = *u;
    else {
        d.u2_m_per_s = kDefaultWindMPerS;
        ++ws.filled["u2: 2 m/s (FAO-56)"];
    }
    const double ra = et::extraterrestrial_radiation_daily(lat * std::numbers::pi / 180.0, d.doy);
    if (auto rs = get("rs_mj_per_m2_day"))
        d.rs_mj = *rs;
    else {
        d.rs_mj = et::solar_from_temperature(d.tmax_c, d.tmin_c, ra, kHargreavesKrs);
        ++ws.filled["rs: Hargreaves 0.16 sqrt(Tmax - Tmin) Ra (FAO-56 eq. 50)"];
    }
    return d;
}

} // namespace

WeatherSeries read_weather_csv(const std::filesystem::path& path, double lat, double elev) {
    const std::string where = path.string();
    std::istringstream in(io::read_text(path));
    std::string line;
    if (!std::getline(in, line)) throw InputError(where + ": empty file");
    const auto header = split_csv(line);
    const auto col = weather_columns(header, where);
    WeatherSeries ws;
    ws.source = where;
    ws.latitude_deg = lat;
    ws.elevation_m = elev;
    std::vector<RawDay> rows;
    int lineno = 1;
    while (std::getline(in, line)) {
        ++lineno;
        if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
        rows.push_back(parse_weather_line(split_csv(line), col, header.size(), lineno, where));
    }
    if (rows.empty()) throw InputError(where + ": no data rows");
    check_consecutive(rows, where);
    interpolate_temperatures(rows, ws);
    for (auto& r : rows) ws.days.push_back(observed_day(r, lat, ws));
    return ws;
}

int days_in_calendar_year(int year) {
    return leap(year) ? 366 : 365;
}

std::vector<std::string> fill_report(const WeatherSeries& ws) {
    std::vector<std::string> out;
    for (const auto& [what, count] : ws.filled)
        out.push_back(ws.source + ": " + std::to_string(count) + " of " +
                      std::to_string(ws.days.size()) + " days filled: " + what);
    return out;
}

} // namespace ecoterra::hydro
