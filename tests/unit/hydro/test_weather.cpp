#include "support/temp_dir.hpp"

#include "ecoterra/hydro/weather.hpp"

#include <catch2/catch.hpp>

#include <fstream>

using namespace ecoterra;
using namespace ecoterra::hydro;

TEST_CASE("Climate presets give their annual rain and wet-day frequency", "[weather]") {
    struct Target {
        const char* name;
        double annual_mm, wet_days;
    };
    for (const Target t : {Target{"humid_subtropical", 1575, 122},
                           Target{"semi_arid_desert", 300, 31}, Target{"temperate", 800, 175}}) {
        const Climate c = climate_preset(t.name);
        CHECK(c.expected_annual_rain_mm() == Approx(t.annual_mm).epsilon(0.02));
        WeatherGenerator g(c, 42);
        const int years = 30;
        double rain = 0;
        int wet = 0;
        double tmax_jul = 0, tmax_jan = 0;
        for (int d = 0; d < 365 * years; ++d) {
            const DayWeather w = g.next();
            rain += w.rain_mm;
            wet += w.rain_mm > 0;
            CHECK(w.tmax_c >= w.tmin_c);
            CHECK(w.tdew_c <= w.tmin_c + 1e-12);
            CHECK(w.rs_mj >= 0);
            CHECK(w.u2_m_per_s >= 0);
            if (w.doy == 200) tmax_jul += w.tmax_c;
            if (w.doy == 15) tmax_jan += w.tmax_c;
        }
        CAPTURE(t.name);
        CHECK(rain / years == Approx(t.annual_mm).epsilon(0.12));
        CHECK(static_cast<double>(wet) / years == Approx(t.wet_days).epsilon(0.12));
        CHECK(tmax_jul > tmax_jan); // northern-hemisphere seasons
    }
    CHECK_THROWS_WITH(climate_preset("tundra"), Catch::Contains("tundra"));
}

TEST_CASE("The generator is seeded and its state can be saved and restored", "[weather]") {
    const Climate c = climate_preset("temperate");
    WeatherGenerator a(c, 7), b(c, 7), other(c, 8);
    for (int d = 0; d < 100; ++d) {
        const auto x = a.next(), y = b.next();
        CHECK(x.rain_mm == y.rain_mm);
        CHECK(x.tmax_c == y.tmax_c);
    }
    const auto saved = a.state();
    const auto next1 = a.next();
    WeatherGenerator c2(c, 99);
    c2.set_state(saved);
    const auto next2 = c2.next();
    CHECK(next1.rain_mm == next2.rain_mm);
    CHECK(next1.rs_mj == next2.rs_mj);
    CHECK(next1.doy == next2.doy);
    double diff = 0;
    WeatherGenerator a2(c, 7);
    for (int d = 0; d < 100; ++d) diff += std::abs(a2.next().tmax_c - other.next().tmax_c);
    CHECK(diff > 1.0);
}

TEST_CASE("Observed weather: gaps are filled as FAO-56 recommends and reported", "[weather]") {
    test::TempDir dir;
    std::ofstream(dir / "w.csv")
        << "date,tmin_c,tmax_c,rain_mm,rh_min_pct,rh_max_pct,u2_m_per_s,rs_mj_per_m2_day\n"
           "2024-07-05,12.0,21.0,0,63,84,2.1,22.0\n"
           "2024-07-06,,22.0,1.5,,,NA,\n"
           "2024-07-07,14.0,23.0,,60,80,1.5,20\n";
    const WeatherSeries s = read_weather_csv(dir / "w.csv", 50.8, 100);
    REQUIRE(s.days.size() == 3);
    CHECK(s.days[0].doy == 187);             // 2024 is a leap year
    CHECK(s.days[1].tmin_c == Approx(13.0)); // interpolated
    CHECK(s.days[1].tdew_c == Approx(13.0)); // Tdew = Tmin
    CHECK(s.days[1].u2_m_per_s == 2.0);
    CHECK(s.days[1].rs_mj > 0);
    CHECK(s.days[2].rain_mm == 0.0);
    CHECK(s.filled.at("tmin_c: interpolated") == 1);
    CHECK(s.filled.at("u2: 2 m/s (FAO-56)") == 1);
    CHECK(s.filled.at("rain_mm: missing, taken as 0") == 1);
    std::ofstream(dir / "bad.csv") << "date,tmin_c,tmax_c,rain_mm,snow\n";
    CHECK_THROWS_WITH(read_weather_csv(dir / "bad.csv", 0, 0), Catch::Contains("snow"));
    std::ofstream(dir / "bad2.csv") << "date,tmin_c,tmax_c,rain_mm\n2024-13-01,1,2,3\n";
    CHECK_THROWS_WITH(read_weather_csv(dir / "bad2.csv", 0, 0),
                      Catch::Contains("line 2") && Catch::Contains("YYYY-MM-DD"));
    std::ofstream(dir / "bad3.csv") << "date,tmin_c,tmax_c,rain_mm\n2024-01-01,1,x,3\n";
    CHECK_THROWS_WITH(read_weather_csv(dir / "bad3.csv", 0, 0), Catch::Contains("tmax_c"));
}
