// The Basic Model Interface 2.0 over the engine, driven as the specification describes it
// (https://bmi.readthedocs.io): only BMI calls, checked against each other and against the engine
// run directly.
#include "support/scenes.hpp"
#include "support/temp_dir.hpp"

#include "ecoterra/archive.hpp"
#include "ecoterra/bmi/ecoterra_bmi.hpp"
#include "ecoterra/error.hpp"
#include "ecoterra/io/atomic_file.hpp"

#include <catch2/catch.hpp>

#include <numeric>

using namespace ecoterra;

namespace {

/// A small quickstart scene file for Initialize.
std::string scene_file(const test::TempDir& dir) {
    auto j = nlohmann::json::parse(io::read_text(test::data_dir() / "scenes/quickstart.json"));
    j["terrain"]["generate"]["size"] = 20;
    j["simulation"]["years"] = 2;
    j["vegetation"]["ecosystem"] =
        (test::data_dir() / "ecosystems/humid_subtropical_broadleaf.json").string();
    const auto path = dir / "scene.json";
    io::write_text_atomic(path, j.dump());
    return path.string();
}

std::vector<std::uint8_t> state(eco::Ecosystem& e) {
    ArchiveWriter a;
    e.save_state(a);
    return a.bytes();
}

} // namespace

TEST_CASE("BMI: grids, variables and time agree with each other as the specification asks",
          "[bmi]") {
    test::TempDir dir;
    bmi_impl::EcoterraBmi m;
    CHECK_THROWS_WITH(m.GetCurrentTime(), Catch::Contains("not initialized"));
    m.Initialize(scene_file(dir));
    CHECK(m.GetComponentName() == "ecoterra");
    CHECK(m.GetStartTime() == 0);
    CHECK(m.GetEndTime() == 2 * 365);
    CHECK(m.GetTimeUnits() == "d");
    CHECK(m.GetOutputItemCount() == static_cast<int>(m.GetOutputVarNames().size()));
    CHECK(m.GetInputItemCount() == static_cast<int>(m.GetInputVarNames().size()));
    for (const auto& name : m.GetOutputVarNames()) {
        CAPTURE(name);
        const int g = m.GetVarGrid(name);
        const int n = m.GetGridSize(g);
        CHECK(m.GetVarType(name) == "double");
        CHECK(m.GetVarNbytes(name) == n * m.GetVarItemsize(name));
        CHECK(m.GetVarLocation(name) == "node");
        CHECK(!m.GetVarUnits(name).empty());
        if (m.GetGridType(g) == "uniform_rectilinear") {
            REQUIRE(m.GetGridRank(g) == 2);
            int shape[2];
            double spacing[2], origin[2];
            m.GetGridShape(g, shape);
            m.GetGridSpacing(g, spacing);
            m.GetGridOrigin(g, origin);
            CHECK(shape[0] * shape[1] == n);
            CHECK(m.GetGridNodeCount(g) == n);
            std::vector<double> x(static_cast<std::size_t>(shape[1])),
                y(static_cast<std::size_t>(shape[0]));
            m.GetGridX(g, x.data());
            m.GetGridY(g, y.data());
            CHECK(x[0] == Approx(origin[1]));
            CHECK(y[0] == Approx(origin[0]));
            CHECK(x[1] - x[0] == Approx(spacing[1]));
            CHECK(y.back() - y[0] == Approx(spacing[0] * (shape[0] - 1)));
            CHECK_THROWS_WITH(m.GetGridFaceCount(g), Catch::Contains("unstructured"));
        } else {
            CHECK(m.GetGridType(g) == "scalar");
            CHECK(m.GetGridRank(g) == 0);
            CHECK(n == 1);
        }
        // GetValue, GetValueAtIndices and (where there is one) GetValuePtr agree.
        std::vector<double> all(static_cast<std::size_t>(n));
        m.GetValue(name, all.data());
        std::vector<int> inds{0, n - 1, n / 2};
        std::vector<double> some(inds.size());
        m.GetValueAtIndices(name, some.data(), inds.data(), static_cast<int>(inds.size()));
        for (std::size_t k = 0; k < inds.size(); ++k)
            CHECK(some[k] == all[static_cast<std::size_t>(inds[k])]);
        if (name == "soil_water__volume_fraction" || name == "land_surface__elevation") {
            const auto* p = static_cast<const double*>(m.GetValuePtr(name));
            CHECK(std::equal(all.begin(), all.end(), p));
        } else {
            CHECK_THROWS_WITH(m.GetValuePtr(name), Catch::Contains("GetValue"));
        }
    }
    // Time: an update is one time step; UpdateUntil goes to the first day at or after the time.
    const double t0 = m.GetCurrentTime();
    m.Update();
    CHECK(m.GetCurrentTime() == t0 + m.GetTimeStep());
    m.UpdateUntil(10.5);
    CHECK(m.GetCurrentTime() == 11);
    CHECK_THROWS_WITH(m.UpdateUntil(3), Catch::Contains("steps forward only"));
    // Errors name what is wrong.
    CHECK_THROWS_WITH(m.GetVarGrid("soil_moisture"),
                      Catch::Contains("no variable 'soil_moisture'"));
    CHECK_THROWS_WITH(m.GetGridRank(7), Catch::Contains("no grid 7"));
    double one = 1.0;
    CHECK_THROWS_WITH(m.SetValue("soil_water__volume_fraction", &one),
                      Catch::Contains("output only"));
    double negative = -1e-6;
    CHECK_THROWS_WITH(m.SetValue("atmosphere_water__precipitation_leq-volume_flux", &negative),
                      Catch::Contains(">= 0 mm"));
    m.Finalize();
    CHECK_THROWS_WITH(m.Update(), Catch::Contains("not initialized"));
}

TEST_CASE("BMI: updates are the engine's days bit for bit, rain set through BMI is the day's rain "
          "and the budget closes",
          "[bmi]") {
    test::TempDir dir;
    const auto file = scene_file(dir);
    bmi_impl::EcoterraBmi m;
    m.Initialize(file);
    m.UpdateUntil(400);
    auto j = nlohmann::json::parse(io::read_text(file));
    eco::Ecosystem direct(eco::load_eco_scene(j, dir.path()));
    for (int d = 0; d < 400; ++d) direct.step_day();
    CHECK(state(m.engine()) == state(direct));
    // Rain from another model: 30 mm on a day the generator keeps dry or not, then none.
    const std::string rain = "atmosphere_water__precipitation_leq-volume_flux";
    for (const double mm : {30.0, 0.0, 12.5}) {
        double flux = mm / 1000.0 / 86400.0;
        m.SetValue(rain, &flux);
        m.Update();
        double back = 0;
        m.GetValue(rain, &back);
        CHECK(back * 86400.0 * 1000.0 == Approx(mm).margin(1e-12));
        CHECK(m.engine().daily().column("rain_mm").back() == Approx(mm).margin(1e-12));
    }
    const auto& h = m.engine().hydrology();
    CHECK(std::abs(h.cumulative_residual_m3()) <= 1e-9 * h.cumulative_throughput_m3());
    // Without input the weather is the generator's again: the other variables were not touched.
    direct.step_day();
    direct.step_day();
    direct.step_day();
    m.Update();
    direct.step_day();
    CHECK(m.engine().last_weather().tmax_c == direct.last_weather().tmax_c);
    CHECK(m.engine().last_weather().rain_mm == direct.last_weather().rain_mm);
}
