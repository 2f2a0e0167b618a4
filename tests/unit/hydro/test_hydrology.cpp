#include "ecoterra/archive.hpp"
#include "ecoterra/hydro/hydrology.hpp"
#include "ecoterra/hydro/kernels.hpp"
#include "ecoterra/parallel.hpp"
#include "ecoterra/terrain/weierstrass.hpp"

#include <catch2/catch.hpp>
#include <omp.h>

#include <cmath>

using namespace ecoterra;
using namespace ecoterra::hydro;
using ecoterra::GridSpec;
using ecoterra::RasterD;

namespace {
RasterD rough_dem(int n, double cell) {
    const GridSpec g{n, n, cell, 0, 0};
    terrain::MultifractalParams p = terrain::majhor2023_params(2.45);
    p.relief_m = 3.0;
    return terrain::multifractal_generate(g, p, 5).z;
}
} // namespace

TEST_CASE("A flat field absorbs its rain until field capacity", "[hydrology]") {
    const GridSpec g{8, 8, 1.0, 0, 0};
    const RasterD dem(g, 5.0);
    const SoilMap soil = uniform_soil(g, SoilComposition{10, 80, 10, 6.5, {}}); // silt
    HydrologyOptions opt;
    opt.initial_saturation = 0.0; // start at the wilting point
    opt.root_zone_depth_m = 0.5;
    HydrologyModel m(dem, soil, RasterD(g, 0.0), opt, climate_preset("temperate"));
    DayWeather w;
    w.rain_mm = 20;
    w.tmin_c = w.tmax_c = w.tdew_c = 5; // saturated, cold: little evaporation
    w.rs_mj = 0;
    const DailyFluxes f = m.step(w);
    CHECK(f.runoff_out == 0.0);
    CHECK(m.catchments().catchments().empty());
    CHECK(f.infiltration == Approx(0.020 * 64));
    // theta = WP + 0.02 m / 0.5 m, less the day's evaporation and drainage.
    const double wp = soil.wilting_point(3, 3);
    CHECK(m.soil_moisture()(3, 3) ==
          Approx(wp + 0.04 - (f.evaporation + f.drainage_out) / 64 / 0.5).epsilon(1e-9));
    CHECK(f.drainage_out > 0); // wet soil drains, however little
    CHECK(f.drainage_out < 1e-3 * f.infiltration);
    CHECK(std::abs(f.residual) < 1e-12);
}

TEST_CASE("Evapotranspiration never takes soil below the wilting point", "[hydrology]") {
    const GridSpec g{6, 6, 1.0, 0, 0};
    const RasterD dem = rough_dem(6, 1.0);
    const SoilMap soil = uniform_soil(g, SoilComposition{40, 40, 20, 6.5, {}});
    HydrologyOptions opt;
    opt.evapotranspiration =
        GENERATE(EvapotranspirationMethod::paper002, EvapotranspirationMethod::fao56);
    const bool paper = opt.evapotranspiration == EvapotranspirationMethod::paper002;
    INFO((paper ? "paper 002" : "FAO-56 dual coefficients"));
    const Climate climate = climate_preset("semi_arid_desert");
    HydrologyModel m(dem, soil, RasterD(g, 0.8), opt, climate);
    DayWeather hot;
    hot.tmin_c = 25;
    hot.tmax_c = 42;
    hot.tdew_c = -5;
    hot.u2_m_per_s = 4;
    hot.rs_mj = 30;
    hot.doy = 180;
    RasterD ask(g, 50.0); // the plants ask for 50 mm a day
    double supplied_first = 0;
    for (int d = 0; d < 60; ++d) {
        m.step(hot, &ask);
        if (d == 0) supplied_first = m.transpiration_supplied_mm()(2, 2);
    }
    for (std::int64_t k = 0; k < m.soil_moisture().size(); ++k)
        CHECK(m.soil_moisture().data()[k] >= soil.wilting_point.data()[k] - 1e-15);
    // Day one has water enough: paper 002 meets the request; FAO-56 gives at most the energy
    // on the leaves, cover x Kc_max x ET0 (the vegetation density 0.8 is the cover).
    const double et0 = et::fao56_reference_daily(et_weather(hot, climate));
    CHECK(supplied_first == Approx(paper ? 50.0 : 0.8 * opt.kc_max * et0));
    // Dry by day 60: nothing left (paper 002), or transpiration fallen with the water left below
    // (1 - p) of the available water, to under 1 % of day one's (FAO-56 eq. 84).
    CHECK(m.transpiration_supplied_mm()(2, 2) <= (paper ? 1e-9 : 0.01 * supplied_first));
}

TEST_CASE("The water budget closes over years, with and without groundwater",
          "[hydrology][budget][slow]") {
    const RasterD dem = rough_dem(48, 2.0);
    const GridSpec& g = dem.grid();
    RandomSoilParams rs;
    rs.mean = SoilComposition{20, 60, 20, 6.0, {}};
    const SoilMap soil = random_soil(g, rs, 3);
    for (bool gw : {false, true}) {
        HydrologyOptions opt;
        opt.groundwater = gw;
        opt.initial_water_table_depth_m = 2.0;
        const Climate c = climate_preset("humid_subtropical");
        HydrologyModel m(dem, soil, RasterD(g, 0.5), opt, c);
        WeatherGenerator wg(c, 11);
        double rain = 0, out = 0, et = 0;
        for (int d = 0; d < 3 * 365; ++d) {
            const DailyFluxes f = m.step(wg.next());
            rain += f.rain;
            out += f.runoff_out + f.groundwater_out + f.drainage_out;
            et += f.evaporation + f.transpiration + f.interception;
        }
        CAPTURE(gw);
        CHECK(std::abs(m.cumulative_residual_m3()) < 1e-9 * m.cumulative_throughput_m3());
        // The water the catchments hold is the water their depth map shows.
        const RasterD depth = m.surface_water_depth();
        CHECK(depth.array().sum() * 4.0 ==
              Approx(m.catchments().total_volume_m3()).epsilon(1e-9).margin(1e-9));
        CHECK(rain > 0);
        CHECK(et > 0.2 * rain);   // humid subtropics lose much of their rain to ET
        CHECK(out > 0.01 * rain); // and some runs off or drains away
        if (gw)
            CHECK(m.water_table_depth()(24, 24) >= 0.0);
        else
            CHECK(std::isnan(m.water_table_depth()(24, 24)));
    }
}

TEST_CASE("Hydrology input is checked", "[hydrology][errors]") {
    const GridSpec g{4, 4, 1.0, 0, 0};
    const SoilMap soil = uniform_soil(g, SoilComposition{});
    HydrologyOptions opt;
    opt.root_zone_depth_m = -1;
    CHECK_THROWS_WITH(
        HydrologyModel(RasterD(g, 1.0), soil, RasterD(g, 0.0), opt, climate_preset("temperate")),
        Catch::Contains("root_zone_depth_m"));
    opt = HydrologyOptions{};
    CHECK_THROWS_WITH(HydrologyModel(RasterD(GridSpec{5, 4, 1.0, 0, 0}, 1.0), soil, RasterD(g, 0.0),
                                     opt, climate_preset("temperate")),
                      Catch::Contains("grid"));
    CHECK_THROWS_WITH(
        HydrologyModel(RasterD(g, 1.0), soil, RasterD(g, 2.0), opt, climate_preset("temperate")),
        Catch::Contains("vegetation density"));
}

TEST_CASE("A 30-year run keeps its budget residual below 1e-9 of the throughput",
          "[hydrology][budget][slow]") {
    // The closure criterion over 30 years (10950 daily steps), with groundwater.
    const RasterD dem = rough_dem(16, 2.0);
    const GridSpec& g = dem.grid();
    RandomSoilParams rs;
    rs.mean = SoilComposition{20, 60, 20, 6.0, {}};
    const SoilMap soil = random_soil(g, rs, 3);
    HydrologyOptions opt;
    opt.groundwater = true;
    opt.initial_water_table_depth_m = 2.0;
    const Climate c = climate_preset("humid_subtropical");
    HydrologyModel m(dem, soil, RasterD(g, 0.5), opt, c);
    WeatherGenerator wg(c, 1);
    for (int d = 0; d < 30 * 365; ++d) m.step(wg.next());
    CHECK(m.day() == 10950);
    CHECK(std::abs(m.cumulative_residual_m3()) < 1e-9 * m.cumulative_throughput_m3());
    CHECK(m.cumulative_throughput_m3() > 0);
}

TEST_CASE("kernels alone: rain partition and evapotranspiration conserve water cell by cell",
          "[hydrology][kernels]") {
    // A tilted plane (no depression, so no standing water) with sandy and clay halves.
    const GridSpec g{12, 12, 2.0, 0, 0};
    RasterD dem(g);
    for (int j = 0; j < g.ny; ++j)
        for (int i = 0; i < g.nx; ++i) dem(i, j) = 10.0 + 0.05 * i + 0.02 * j;
    const SoilMap soil = uniform_soil(g, SoilComposition{20, 60, 20, 6.5, {}});
    Catchments lakes(dem);
    const double depth = 0.8, area = g.cell_size_m * g.cell_size_m;
    std::vector<double> theta(static_cast<std::size_t>(g.size()));
    for (std::int64_t k = 0; k < g.size(); ++k) // from the wilting point to above field capacity
        theta[k] = soil.wilting_point.data()[k] +
                   (k % 7) / 5.0 * (soil.field_capacity.data()[k] - soil.wilting_point.data()[k]);
    const SoilColumns cols{theta.data(),
                           soil.field_capacity.data(),
                           soil.wilting_point.data(),
                           soil.ksat_m_per_s.data(),
                           depth,
                           area};
    const std::vector<double> before = theta;
    const std::vector<double> coef(static_cast<std::size_t>(g.size()), 0.3);
    const RasterD slope(g, 0.05), veg(g, 0.5);
    const RainPartition rain{
        RunoffMethod::coefficients, 0.025, 25.0, coef.data(), slope.data(), 0.005, veg.data(),
        soil.texture.data()};
    std::vector<double> runoff(static_cast<std::size_t>(g.size())), recharge(runoff.size(), 0.0);
    double infiltration = 0;
    partition_rain(lakes, cols, rain, runoff, &recharge, infiltration);
    double stored = 0, off = 0, perc = 0;
    for (std::int64_t k = 0; k < g.size(); ++k) {
        // Each cell: rain = soil gain + runoff + percolation, and theta never above capacity.
        const double gain = (theta[k] - before[k]) * depth * area;
        CHECK(gain + runoff[k] + recharge[k] == Approx(0.025 * area).epsilon(1e-12));
        CHECK(theta[k] <= soil.field_capacity.data()[k] + 1e-15);
        CHECK(runoff[k] >= 0.3 * 0.025 * area * (1 - 1e-12));
        stored += gain, off += runoff[k], perc += recharge[k];
    }
    CHECK(infiltration == Approx(0.7 * 0.025 * area * static_cast<double>(g.size())));
    CHECK(stored + off + perc == Approx(0.025 * area * static_cast<double>(g.size())));

    // Evapotranspiration: requests on half the cells, more than the soil holds on some.
    std::vector<double> request(runoff.size()), supplied(runoff.size());
    for (std::size_t k = 0; k < request.size(); ++k) request[k] = k % 2 ? 0.0 : 3.0 * (k % 50);
    const std::vector<double> mid = theta;
    const SurfaceDemand demand{2.0, 4.0, veg.data(), 0.3};
    double transpiration = 0, evaporation = 0;
    evapotranspiration(lakes, cols, g.size(), demand, request.data(), supplied.data(),
                       transpiration, evaporation);
    double removed = 0, given = 0;
    for (std::size_t k = 0; k < request.size(); ++k) {
        removed += (mid[k] - theta[k]) * depth * area;
        given += supplied[k] / 1000.0 * area;
        CHECK(supplied[k] <= request[k] + 1e-12);                // never more than asked
        CHECK(theta[k] >= soil.wilting_point.data()[k] - 1e-15); // never below wilting
        CHECK((mid[k] - theta[k]) * depth * 1000.0 <= std::max(4.0, request[k]) + 1e-9);
    }
    CHECK(transpiration == Approx(given));
    CHECK(transpiration + evaporation == Approx(removed));
    CHECK(transpiration > 0);
}

TEST_CASE("The soil's storage kept from a day's end is the sum a fresh pass over the cells gives",
          "[hydrology][budget]") {
    // HydrologyModel::step keeps the root zone's storage summed at the day's end and takes it as
    // the next day's start. Checked against the storage a model restored from the state sums
    // afresh (load_state forgets the kept one), bit for bit: on grids of one and several summing
    // blocks (16384 cells each), the default soil water, paper 002's and groundwater, 1 and 2
    // threads.
    const std::int64_t min_items = parallel_min_items();
    const int threads = omp_get_max_threads();
    set_parallel_min_items(1);
    int compared = 0;
    for (const int n : {24, 130}) { // 130^2: two summing blocks
        const RasterD dem = rough_dem(n, 1.0);
        RandomSoilParams rs;
        rs.mean = SoilComposition{30, 50, 20, 6.0, {}};
        const SoilMap soil = random_soil(dem.grid(), rs, 3);
        HydrologyOptions paper;
        paper.evapotranspiration = EvapotranspirationMethod::paper002;
        paper.drainage = DrainageMethod::none;
        HydrologyOptions gw;
        gw.groundwater = true;
        for (const HydrologyOptions& opt : {HydrologyOptions{}, paper, gw})
            for (const int t : {1, 2}) {
                omp_set_num_threads(t);
                const Climate climate = climate_preset("humid_subtropical");
                HydrologyModel m(dem, soil, RasterD(dem.grid(), 0.4), opt, climate);
                WeatherGenerator wg(climate, 7);
                for (int d = 1; d <= 24; ++d) {
                    const DailyFluxes f = m.step(wg.next());
                    if (d % 6 != 0) continue;
                    ArchiveWriter a;
                    m.save_state(a);
                    HydrologyModel fresh(dem, soil, RasterD(dem.grid(), 0.4), opt, climate);
                    ArchiveReader in(a.bytes().data(), a.bytes().size(), "test");
                    fresh.load_state(in);
                    CHECK(m.soil_storage_m3() == fresh.soil_storage_m3());
                    CHECK(std::isfinite(f.d_soil));
                    ++compared;
                }
            }
    }
    omp_set_num_threads(threads);
    set_parallel_min_items(min_items);
    CHECK(compared == 2 * 3 * 2 * 4);
}
