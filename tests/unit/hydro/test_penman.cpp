// FAO-56 examples and the vectors of reference hydrology.md s1.3 and s2.2.
#include "ecoterra/error.hpp"
#include "ecoterra/hydro/penman.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using namespace ecoterra;
using namespace ecoterra::hydro::et;

namespace {
constexpr double kDaily = 0.01;  // mm/day, the tolerance
constexpr double kHourly = 0.01; // mm/h
double deg(double d, double m) {
    return d + m / 60.0;
}
} // namespace

TEST_CASE("Improved Magnus reproduces the reference saturation vapour pressures", "[et][magnus]") {
    struct V {
        double t, pa;
    };
    for (const V v :
         {V{-40, 18.97}, V{-20, 125.78}, V{0, 610.94}, V{0.01, 611.38}, V{10, 1226.02},
          V{20, 2333.44}, V{25, 3161.74}, V{30, 4236.65}, V{40, 7374.72}, V{50, 12360.58}}) {
        CAPTURE(v.t);
        CHECK(svp_water_kpa(v.t) * 1000 == Approx(v.pa).margin(0.01));
    }
    for (const V v : {V{-80, 0.0547}, V{-60, 1.0817}, V{-40, 12.834}, V{-20, 103.13},
                      V{-10, 259.67}, V{0, 611.21}}) {
        CAPTURE(v.t);
        CHECK(svp_ice_kpa(v.t) * 1000 == Approx(v.pa).epsilon(5e-4));
    }
    // Within about 0.3 % of IAPWS-IF97 / Murphy-Koop liquid over -40..50 degC (0.31 % at -40).
    CHECK(svp_water_kpa(20) * 1000 == Approx(2339.21).epsilon(0.003));
    CHECK(svp_water_kpa(-40) * 1000 == Approx(18.91).epsilon(0.0032));
    // Slope: 144.46 Pa/K at 20 degC, and equal to a centred difference.
    CHECK(svp_slope_water_kpa(20) * 1000 == Approx(144.46).margin(0.01));
    CHECK(svp_slope_water_kpa(13.7) ==
          Approx((svp_water_kpa(13.7 + 1e-4) - svp_water_kpa(13.7 - 1e-4)) / 2e-4).epsilon(1e-7));
    // FAO-56 values used by the McMahon worked example.
    CHECK(svp_fao_kpa(21) == Approx(2.4870).margin(1e-4));
    CHECK(svp_fao_kpa(2) == Approx(0.7056).margin(1e-4));
}

TEST_CASE("FAO-56 Example 18: Uccle, 6 July, daily ETo", "[et][fao56][verification]") {
    DailyWeather w;
    w.lat_deg = deg(50, 48);
    w.elevation_m = 100;
    w.doy = 187;
    w.tmax_c = 21.5;
    w.tmin_c = 12.3;
    w.rh_max_pct = 84;
    w.rh_min_pct = 63;
    w.u2_m_per_s = 2.78 * 4.87 / std::log(67.8 * 10 - 5.42); // u10 -> u2 (eq. 47)
    CHECK(w.u2_m_per_s == Approx(2.0793).margin(1e-4));
    w.sunshine_h = 9.25;
    DailyTerms t{};
    const double eto = fao56_reference_daily(w, &t);
    CHECK(t.gamma == Approx(0.066556).margin(1e-5));
    CHECK(t.delta == Approx(0.122113).margin(1e-5));
    CHECK(t.ea == Approx(1.408624).margin(1e-4));
    CHECK(t.es - t.ea == Approx(0.588862).margin(1e-4));
    CHECK(t.ra == Approx(41.08838).margin(0.01));
    CHECK(t.rs == Approx(22.07).margin(0.01));
    CHECK(t.rso == Approx(30.89846).margin(0.01));
    CHECK(t.rnl == Approx(3.711241).margin(0.01));
    CHECK(t.rn == Approx(13.28266).margin(0.01));
    CHECK(eto == Approx(3.880142).margin(kDaily));
}

TEST_CASE("FAO-56 Example 17: Bangkok, April, monthly ETo", "[et][fao56][verification]") {
    DailyWeather w;
    w.lat_deg = deg(13, 44);
    w.elevation_m = 2;
    w.doy = 105;
    w.tmax_c = 34.8;
    w.tmin_c = 25.6;
    w.ea_kpa = 2.846;
    w.u2_m_per_s = 2;
    w.rs_mj = 22.65;
    w.soil_heat_flux_mj = 0.14;
    DailyTerms t{};
    const double eto = fao56_reference_daily(w, &t);
    CHECK(t.gamma == Approx(0.067323).margin(1e-5));
    CHECK(t.delta == Approx(0.2458003).margin(1e-5));
    CHECK(t.es == Approx(4.421798).margin(1e-4));
    CHECK(t.ra == Approx(38.05769).margin(0.01));
    CHECK(t.rso == Approx(28.54479).margin(0.01));
    CHECK(t.rnl == Approx(3.11295).margin(0.01));
    CHECK(t.rn == Approx(14.32755).margin(0.01));
    CHECK(eto == Approx(5.718284).margin(kDaily));
}

TEST_CASE("FAO-56 Example 19: N'Diaye, 1 October, hourly ETo", "[et][fao56][verification]") {
    HourlyWeather w;
    w.lat_deg = deg(16, 13);
    w.lon_west_deg = deg(16, 15);
    w.lz_west_deg = 15;
    w.elevation_m = 8;
    w.doy = 274;
    w.hour_end = 15;
    w.t_c = 38;
    w.rh_pct = 52;
    w.u2_m_per_s = 3.3;
    w.rs_mj = 2.450;
    DailyTerms t{};
    const double day = fao56_reference_hourly(w, &t);
    CHECK(t.ra == Approx(3.543).margin(0.005));
    CHECK(t.rnl == Approx(0.137).margin(0.002));
    CHECK(t.rn == Approx(1.749).margin(0.003));
    CHECK(day == Approx(0.63).margin(kHourly));
    w.hour_end = 3;
    w.t_c = 28;
    w.rh_pct = 90;
    w.u2_m_per_s = 1.9;
    w.rs_mj = 0;
    const double night = fao56_reference_hourly(w, &t);
    CHECK(t.ra == 0.0);
    CHECK(t.rn == Approx(-0.100).margin(0.002));
    CHECK(night == Approx(0.00).margin(kHourly));
}

TEST_CASE("FAO-56 Example 20 and missing-data rules: Lyon, July", "[et][fao56][verification]") {
    // Tdew = Tmin and Rs from the temperature range (kRs 0.16): reference value 4.56 mm/day.
    DailyWeather w;
    w.lat_deg = deg(45, 43);
    w.elevation_m = 200;
    w.doy = 196;
    w.tmax_c = 26.6;
    w.tmin_c = 14.8;
    w.u2_m_per_s = 2;
    DailyTerms t{};
    const double eto = fao56_reference_daily(w, &t);
    CHECK(t.pressure_kpa == Approx(98.96).margin(0.01));
    CHECK(t.ra == Approx(40.55).margin(0.01));
    CHECK(t.rs == Approx(22.29).margin(0.01));
    CHECK(t.rn == Approx(13.48).margin(0.01));
    CHECK(eto == Approx(4.56).margin(kDaily));
    CHECK_THAT(std::string(t.radiation_from), Catch::Contains("Hargreaves"));
    CHECK_THAT(std::string(t.humidity_from), Catch::Contains("tmin"));
}

TEST_CASE("Penman open water: wind functions and limits", "[et][penman]") {
    DailyWeather w;
    w.lat_deg = 50.8;
    w.elevation_m = 100;
    w.doy = 187;
    w.tmin_c = 12.3;
    w.tmax_c = 21.5;
    w.rh_min_pct = 63;
    w.rh_max_pct = 84;
    w.u2_m_per_s = 2.078;
    w.sunshine_h = 9.25;
    DailyTerms t{};
    const double e48 = penman_open_water(w, WindFunction::penman1948, &t);
    const double e56 = penman_open_water(w, WindFunction::penman1956);
    // The two differ by exactly the aerodynamic term of 1.313 mm day-1 kPa-1.
    CHECK(e48 - e56 ==
          Approx(t.gamma * 1.313 * (t.es - t.ea) / (t.delta + t.gamma)).epsilon(1e-12));
    CHECK(wind_function(WindFunction::shuttleworth1993, 0.0) == Approx(2.624).margin(1e-3));
    CHECK(wind_function(WindFunction::shuttleworth1993, 1.0) -
              wind_function(WindFunction::shuttleworth1993, 0.0) ==
          Approx(1.407).margin(1e-3));
    // Radiation-only limit: no wind term when the air is saturated at every temperature.
    DailyWeather sat = w;
    sat.rh_min_pct = 100;
    sat.rh_max_pct = 100;
    sat.tmin_c = sat.tmax_c = 17;
    const double rad = penman_open_water(sat, WindFunction::penman1948, &t);
    CHECK(rad ==
          Approx(t.delta * t.rn / kLatentHeat_MJ_per_kg / (t.delta + t.gamma)).epsilon(1e-12));
    // Open water evaporates more than the grass reference on the same day; surfaces are ordered.
    const double eto = fao56_reference_daily(w);
    CHECK(e48 > eto);
    CHECK(evapotranspiration(Method::penman_bare_soil, w) == Approx(0.9 * e48));
    CHECK(evapotranspiration(Method::penman_grass, w) == Approx(0.8 * e48)); // July, north
    CHECK(penman_grass_factor(-30, 187) == 0.6);                             // July, south
    CHECK(penman_grass_factor(45, 15) == 0.6);
    CHECK(penman_grass_factor(45, 100) == 0.7);
}

TEST_CASE("Weather input is checked", "[et][errors]") {
    DailyWeather w;
    w.tmin_c = 20;
    w.tmax_c = 10;
    CHECK_THROWS_WITH(fao56_reference_daily(w),
                      Catch::Contains("tmax") && Catch::Contains("below"));
    w.tmax_c = 25;
    w.rh_min_pct = 120;
    w.rh_max_pct = 130;
    CHECK_THROWS_WITH(fao56_reference_daily(w), Catch::Contains("rh"));
    w.rh_min_pct.reset();
    w.rh_max_pct.reset();
    w.lat_deg = 95;
    CHECK_THROWS_WITH(fao56_reference_daily(w), Catch::Contains("latitude"));
}

TEST_CASE("Wind functions and methods parse from one list of names, bad names are refused",
          "[penman][errors]") {
    for (const auto& [key, w] : wind_function_keys()) {
        CHECK(parse_wind_function(key, "k") == w);
        CHECK(wind_function_name(w).rfind(key, 0) == 0); // the printed name starts with the key
    }
    CHECK(parse_wind_function("1956", "k") == WindFunction::penman1956);
    CHECK(parse_wind_function("shuttleworth", "k") == WindFunction::shuttleworth1993);
    CHECK_THROWS_WITH(parse_wind_function("1957", "--wind-function"),
                      Catch::Contains("--wind-function") && Catch::Contains("'1957'") &&
                          Catch::Contains("penman1948"));
    for (Method m :
         {Method::fao56, Method::penman_open_water, Method::penman_bare_soil, Method::penman_grass})
        CHECK(parse_method(method_name(m), "m") == m);
    CHECK_THROWS_AS(parse_method("fao-56", "--method"), InputError);
}
