#include "support/temp_dir.hpp"

#include "ecoterra/hydro/weather.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdio>
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
    const auto report = fill_report(s);
    REQUIRE(report.size() == s.filled.size());
    for (const auto& line : report) CHECK_THAT(line, Catch::Contains("w.csv: "));
    CHECK(std::count(report.begin(), report.end(),
                     (dir / "w.csv").string() + ": 1 of 3 days filled: tmin_c: interpolated") == 1);
    std::ofstream(dir / "bad.csv") << "date,tmin_c,tmax_c,rain_mm,snow\n";
    CHECK_THROWS_WITH(read_weather_csv(dir / "bad.csv", 0, 0), Catch::Contains("snow"));
    std::ofstream(dir / "bad2.csv") << "date,tmin_c,tmax_c,rain_mm\n2024-13-01,1,2,3\n";
    CHECK_THROWS_WITH(read_weather_csv(dir / "bad2.csv", 0, 0),
                      Catch::Contains("line 2") && Catch::Contains("YYYY-MM-DD"));
    std::ofstream(dir / "bad3.csv") << "date,tmin_c,tmax_c,rain_mm\n2024-01-01,1,x,3\n";
    CHECK_THROWS_WITH(read_weather_csv(dir / "bad3.csv", 0, 0), Catch::Contains("tmax_c"));
}

namespace {
/// Rows "date,tmin_c,tmax_c,rain_mm" for every day from 1 January `first` to 31 December `last`.
std::vector<std::string> calendar_rows(int first, int last) {
    std::vector<std::string> rows;
    static constexpr int kDays[12] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
    for (int y = first; y <= last; ++y)
        for (int m = 1; m <= 12; ++m) {
            const bool leap = (y % 4 == 0 && y % 100 != 0) || y % 400 == 0;
            for (int d = 1; d <= kDays[m - 1] + (m == 2 && leap); ++d) {
                char buf[64];
                std::snprintf(buf, sizeof buf, "%04d-%02d-%02d,%d,%d,%d", y, m, d, 5 + d % 3,
                              15 + d % 5, d % 4);
                rows.push_back(buf);
            }
        }
    return rows;
}
std::string csv(const std::vector<std::string>& rows) {
    std::string s = "date,tmin_c,tmax_c,rain_mm\n";
    for (const auto& r : rows) s += r + "\n";
    return s;
}
} // namespace

TEST_CASE("Observed weather: every day once and in order, a missing, repeated or misplaced day is "
          "refused wherever it is",
          "[weather][bad-input]") {
    test::TempDir dir;
    const auto rows = calendar_rows(2023, 2024); // 2024 is a leap year
    std::ofstream(dir / "ok.csv") << csv(rows);
    REQUIRE(read_weather_csv(dir / "ok.csv", 45, 0).days.size() == 365 + 366);
    // The row index of 29 February 2024 (and of every 30th day): each mutation at each place.
    std::vector<std::size_t> at;
    for (std::size_t k = 1; k + 1 < rows.size(); k += 30) at.push_back(k);
    const auto feb29 = static_cast<std::size_t>(
        std::find_if(rows.begin(), rows.end(),
                     [](const std::string& r) { return r.rfind("2024-02-29", 0) == 0; }) -
        rows.begin());
    at.push_back(feb29);
    for (const std::size_t k : at) {
        CAPTURE(k);
        const std::string line = "line " + std::to_string(k + 2); // the header is line 1
        const std::string day = rows[k].substr(0, 10);
        auto missing = rows;
        missing.erase(missing.begin() + static_cast<std::ptrdiff_t>(k));
        std::ofstream(dir / "m.csv") << csv(missing);
        CHECK_THROWS_WITH(read_weather_csv(dir / "m.csv", 45, 0),
                          Catch::Contains("m.csv " + line) && Catch::Contains(day + " is missing"));
        auto twice = rows;
        twice.insert(twice.begin() + static_cast<std::ptrdiff_t>(k), rows[k]);
        std::ofstream(dir / "t.csv") << csv(twice);
        CHECK_THROWS_WITH(read_weather_csv(dir / "t.csv", 45, 0),
                          Catch::Contains("line " + std::to_string(k + 3)) &&
                              Catch::Contains("given twice"));
        auto swapped = rows;
        std::swap(swapped[k], swapped[k + 1]);
        std::ofstream(dir / "s.csv") << csv(swapped);
        CHECK_THROWS_WITH(read_weather_csv(dir / "s.csv", 45, 0),
                          Catch::Contains("s.csv " + line) && Catch::Contains("is missing"));
    }
    // Days the calendar does not have, and dates with more after them.
    for (const auto& [date, why] :
         std::vector<std::pair<std::string, std::string>>{{"2023-02-29", "not a leap year"},
                                                          {"2100-02-29", "not a leap year"},
                                                          {"2024-04-31", "30 days"},
                                                          {"2024-01-01x", "YYYY-MM-DD"},
                                                          {"2024-1-1-1", "YYYY-MM-DD"}}) {
        CAPTURE(date);
        std::ofstream(dir / "d.csv") << "date,tmin_c,tmax_c,rain_mm\n" << date << ",1,2,3\n";
        CHECK_THROWS_WITH(read_weather_csv(dir / "d.csv", 0, 0),
                          Catch::Contains(date) && Catch::Contains(why));
    }
    std::ofstream(dir / "leap.csv") << "date,tmin_c,tmax_c,rain_mm\n2000-02-29,1,2,3\n";
    CHECK(read_weather_csv(dir / "leap.csv", 0, 0).days.at(0).doy == 60);
}
