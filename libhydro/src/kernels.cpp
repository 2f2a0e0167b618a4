#include "ecoterra/hydro/kernels.hpp"
#include "ecoterra/units.hpp"

#include "ecoterra/hydro/groundwater.hpp"
#include "ecoterra/hydro/hydrology.hpp"
#include "ecoterra/parallel.hpp"

#include <algorithm>
#include <array>
#include <sstream>

namespace ecoterra::hydro {

namespace {
constexpr double kSecondsPerDay = 86400.0;
} // namespace

void lake_losses(Catchments& lakes, const RasterD& dem, const SoilColumns& soil, double e0_mm,
                 std::vector<double>* recharge, double& evaporation_m3, double& infiltration_m3) {
    const double area = soil.cell_area_m2, depth = soil.depth_m;
    for (const auto& k : lakes.catchments()) {
        const std::int32_t id = k.id;
        evaporation_m3 +=
            lakes.remove_water(id, e0_mm / kMmPerM * area * static_cast<double>(k.wet_cells));
        lakes.for_each_wet_cell(k, [&](std::int64_t c) {
            if (!(k.level_m > dem.data()[c])) return;
            double& th = soil.theta[c];
            const double fc = soil.field_capacity[c];
            const double want = std::max(0.0, (fc - th) * depth * area);
            const double got = lakes.remove_water(id, want);
            th += got / (depth * area);
            infiltration_m3 += got;
            if (recharge)
                (*recharge)[c] +=
                    lakes.remove_water(id, soil.ksat_m_per_s[c] * kSecondsPerDay * area);
        });
    }
}

void rain_on_lakes(Catchments& lakes, double rain_m, double cell_area_m2) {
    for (const auto& k : lakes.catchments())
        lakes.add_water_to(k.id, rain_m * cell_area_m2 * static_cast<double>(k.wet_cells));
}

void partition_rain(const Catchments& lakes, const SoilColumns& soil, const RainPartition& rain,
                    std::vector<double>& runoff, std::vector<double>* recharge,
                    double& infiltration_m3) {
    const double area = soil.cell_area_m2, depth = soil.depth_m, rain_m = rain.rain_m;
    const auto sums = blocked_sums<1>(static_cast<std::int64_t>(runoff.size()), [&](std::int64_t k,
                                                                                    auto& sum) {
        if (lakes.owner(k) != 0) {
            runoff[k] = 0.0;
            return;
        }
        double r = 0;
        if (rain.method == RunoffMethod::coefficients) {
            r = rain.runoff_coefficient[k] * rain_m;
        } else if (rain.slope[k] >= rain.flat_slope) {
            r = scs_runoff_mm(rain.rain_mm, curve_number(rain.vegetation_density[k],
                                                         static_cast<Texture>(rain.texture[k]))) /
                kMmPerM;
        }
        const double inf = rain_m - r;
        sum[0] += inf * area;
        double& th = soil.theta[k];
        th += inf / depth;
        const double fc = soil.field_capacity[k];
        double excess = std::max(0.0, (th - fc) * depth); // m
        th = std::min(th, fc);
        if (recharge && excess > 0) {
            const double perc = std::min(excess, soil.ksat_m_per_s[k] * kSecondsPerDay);
            (*recharge)[k] += perc * area;
            excess -= perc;
        }
        runoff[k] = (r + excess) * area;
    });
    infiltration_m3 += sums[0];
}

void route_runoff(Catchments& lakes, const SoilColumns& soil,
                  const std::vector<std::int64_t>& order, Routing routing,
                  std::vector<double>& runoff, double& infiltration_m3) {
    const double area = soil.cell_area_m2, depth = soil.depth_m;
    const FlowDirections& fd = lakes.flow();
    for (const std::int64_t k : order) {
        double q = runoff[k];
        if (q <= 0) continue;
        if (fd.is_outlet(k)) {
            lakes.add_water(k, q); // counted as lost by the catchments
            continue;
        }
        if (lakes.owner(k) != 0) {
            lakes.add_water(k, q);
            continue;
        }
        double& th = soil.theta[k];
        const double fc = soil.field_capacity[k];
        const double absorb = std::min(q, std::max(0.0, (fc - th) * depth * area));
        if (absorb > 0) {
            th += absorb / (depth * area);
            infiltration_m3 += absorb;
            q -= absorb;
        }
        if (q <= 0) continue;
        if (fd.is_pit(k)) {
            lakes.add_to_pit(k, q);
            continue;
        }
        if (routing != Routing::mfd) {
            runoff[fd.receiver(k)] += q;
            continue;
        }
        std::array<std::pair<std::int64_t, double>, 8> shares;
        const int n = mfd_shares(fd, k, shares);
        for (int r = 0; r < n; ++r) runoff[shares[r].first] += q * shares[r].second;
    }
}

void evapotranspiration(const Catchments& lakes, const SoilColumns& soil, std::int64_t cells,
                        const SurfaceDemand& demand, const double* request_mm, double* supplied_mm,
                        double& transpiration_m3, double& evaporation_m3) {
    const double area = soil.cell_area_m2, depth = soil.depth_m;
    const auto sums = blocked_sums<2>(cells, [&](std::int64_t k, auto& sum) {
        const double req = request_mm ? std::max(0.0, request_mm[k]) / kMmPerM : 0.0; // m
        const bool lake = lakes.owner(k) != 0;
        const double surface = lake
                                   ? 0.0
                                   : (demand.vegetation_density[k] >= demand.grass_density_threshold
                                          ? demand.grass_mm
                                          : demand.bare_soil_mm) /
                                         kMmPerM;
        const double want = std::max(surface, req);
        double& th = soil.theta[k];
        const double avail = std::max(0.0, (th - soil.wilting_point[k]) * depth);
        const double actual = std::min(want, avail);
        th -= actual / depth;
        const double tr = std::min(actual, req);
        supplied_mm[k] = tr * kMmPerM;
        sum[0] += tr * area;
        sum[1] += (actual - tr) * area;
    });
    transpiration_m3 += sums[0];
    evaporation_m3 += sums[1];
}

double groundwater_exchange(Groundwater& gw, Catchments& lakes, const std::vector<double>& recharge,
                            int day, int year, int doy) {
    GroundwaterResult res;
    try {
        res = gw.step(kSecondsPerDay, recharge);
    } catch (const Error& e) {
        std::ostringstream msg;
        msg << "on day " << day << " (year " << year << ", day " << doy << "): " << e.what();
        throw Error(msg.str());
    }
    // Water table above the surface: it seeps out and joins the surface water.
    bool seeped = false;
    for (std::size_t k = 0; k < res.seepage_m3.size(); ++k)
        if (res.seepage_m3[k] > 0) {
            lakes.add_water(static_cast<std::int64_t>(k), res.seepage_m3[k]);
            seeped = true;
        }
    if (seeped) lakes.equilibrate();
    return res.outflow_m3;
}

} // namespace ecoterra::hydro
