#include "ecoterra/hydro/kernels.hpp"
#include "ecoterra/units.hpp"

#include "ecoterra/hydro/groundwater.hpp"
#include "ecoterra/hydro/hydrology.hpp"
#include "ecoterra/parallel.hpp"

#include <algorithm>
#include <array>
#include <cmath>
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
            const double want = std::max(0.0, (soil.ceiling_at(c) - th) * depth * area);
            const double got = lakes.remove_water(id, want);
            th += got / (depth * area);
            infiltration_m3 += got;
            if (soil.surface_depletion_mm) soil.surface_depletion_mm[c] = 0.0;
            // Without gravity drainage (paper 002) the water under a lake percolates at Ksat;
            // with it, the drainage kernel moves it down like any other cell's.
            if (recharge && !soil.ceiling)
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
    const auto sums =
        blocked_sums<1>(static_cast<std::int64_t>(runoff.size()), [&](std::int64_t k, auto& sum) {
            if (lakes.owner(k) != 0) {
                runoff[k] = 0.0;
                return;
            }
            // Rain that reaches the ground: less what the canopy held back.
            const double net_m = rain.intercepted_m ? rain_m - rain.intercepted_m[k] : rain_m;
            double r = 0;
            if (rain.method == RunoffMethod::coefficients) {
                r = rain.runoff_coefficient[k] * net_m;
            } else if (rain.slope[k] >= rain.flat_slope) {
                r = scs_runoff_mm(rain.intercepted_m ? net_m * kMmPerM : rain.rain_mm,
                                  curve_number(rain.vegetation_density[k],
                                               static_cast<Texture>(rain.texture[k]))) /
                    kMmPerM;
            }
            const double inf = net_m - r;
            sum[0] += inf * area;
            double& th = soil.theta[k];
            th += inf / depth;
            const double top = soil.ceiling_at(k);
            double excess = std::max(0.0, (th - top) * depth); // m
            th = std::min(th, top);
            soil.refill_surface(k, (inf - excess) * area);
            if (recharge && !soil.ceiling && excess > 0) {
                const double perc = std::min(excess, soil.ksat_m_per_s[k] * kSecondsPerDay);
                (*recharge)[k] += perc * area;
                excess -= perc;
            }
            runoff[k] = (r + excess) * area;
        });
    infiltration_m3 += sums[0];
}

/// How far ahead in the run-on's order route_runoff fetches a cell's runoff and water.
constexpr std::size_t kRunOnPrefetch = 16;

void route_runoff(Catchments& lakes, const SoilColumns& soil,
                  const std::vector<std::int64_t>& order, Routing routing,
                  std::vector<double>& runoff, double& infiltration_m3) {
    const double area = soil.cell_area_m2, depth = soil.depth_m;
    const FlowDirections& fd = lakes.flow();
    const std::size_t cells = order.size();
    for (std::size_t i = 0; i < cells; ++i) {
        const std::int64_t k = order[i];
        if (i + kRunOnPrefetch < cells) {
            const std::int64_t ahead = order[i + kRunOnPrefetch];
            __builtin_prefetch(runoff.data() + ahead);
            __builtin_prefetch(soil.theta + ahead);
        }
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
        const double absorb = std::min(q, std::max(0.0, (soil.ceiling_at(k) - th) * depth * area));
        if (absorb > 0) {
            th += absorb / (depth * area);
            soil.refill_surface(k, absorb);
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

namespace {
/// Runs range(begin, end, a, b) over the fixed blocks of `cells` (each block's sums from zero)
/// and adds the two totals, in block order, to `a_total` and `b_total`.
template <class F>
void block_pass(std::int64_t cells, double& a_total, double& b_total, F&& range) {
    const auto sums = blocked_range_sums<2>(
        cells, [&](std::int64_t b, std::int64_t e, auto& s) { range(b, e, s[0], s[1]); });
    a_total += sums[0];
    b_total += sums[1];
}
} // namespace

void evapotranspiration_range(const Catchments& lakes, const SoilColumns& soil, std::int64_t begin,
                              std::int64_t end, const SurfaceDemand& demand,
                              const double* request_mm, double* supplied_mm,
                              double& transpiration_m3, double& evaporation_m3) {
    const double area = soil.cell_area_m2, depth = soil.depth_m;
    double t_m3 = 0, e_m3 = 0; // the range's sums, in cell order (locals: theta may alias)
    for (std::int64_t k = begin; k < end; ++k) {
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
        t_m3 += tr * area;
        e_m3 += (actual - tr) * area;
    }
    transpiration_m3 += t_m3;
    evaporation_m3 += e_m3;
}

void evapotranspiration(const Catchments& lakes, const SoilColumns& soil, std::int64_t cells,
                        const SurfaceDemand& demand, const double* request_mm, double* supplied_mm,
                        double& transpiration_m3, double& evaporation_m3) {
    block_pass(cells, transpiration_m3, evaporation_m3,
               [&](std::int64_t b, std::int64_t e, double& t, double& v) {
                   evapotranspiration_range(lakes, soil, b, e, demand, request_mm, supplied_mm, t,
                                            v);
               });
}

namespace {
/// Gash's loss, given ln(1 - e) (`log_dry`: the same for every cell, taken once a day).
double gash_loss_mm(double rain_mm, double lai, double cover, const InterceptionParams& p,
                    double log_dry) {
    if (!(rain_mm > 0) || !(lai > 0) || !(cover > 0)) return 0.0;
    const double e = p.evaporation_to_rain;
    const double sc = p.storage_per_lai_mm * lai / cover; // per unit of covered ground
    const double saturating = -sc / e * log_dry;          // P'
    if (rain_mm < saturating) return cover * rain_mm;
    return cover * (saturating + e * (rain_mm - saturating));
}
} // namespace

double gash_interception_mm(double rain_mm, double lai, double cover, const InterceptionParams& p) {
    return gash_loss_mm(rain_mm, lai, cover, p, std::log1p(-p.evaporation_to_rain));
}

void canopy_interception(const Catchments& lakes, const double* lai, const double* cover,
                         double rain_mm, const InterceptionParams& p, double cell_area_m2,
                         std::vector<double>& intercepted_m, double& interception_m3) {
    const auto cells = static_cast<std::int64_t>(intercepted_m.size());
    const double log_dry = std::log1p(-p.evaporation_to_rain);
    const auto sums = blocked_sums<1>(cells, [&](std::int64_t k, auto& sum) {
        const double mm =
            lakes.owner(k) != 0 ? 0.0 : gash_loss_mm(rain_mm, lai[k], cover[k], p, log_dry);
        intercepted_m[k] = mm / kMmPerM;
        sum[0] += intercepted_m[k] * cell_area_m2;
    });
    interception_m3 += sums[0];
}

void evapotranspiration_fao56_range(const Catchments& lakes, const SoilColumns& soil,
                                    std::int64_t begin, std::int64_t end, const Fao56Day& day,
                                    const double* request_mm, double* supplied_mm,
                                    double& transpiration_m3, double& evaporation_m3) {
    // The standing water's cells (a walk up the depression tree each), then the vectorised
    // arithmetic, then the sums in cell order.
    struct Scratch {
        std::vector<double> lake, transpiration_m3, evaporation_m3;
    };
    thread_local Scratch w;
    const auto len = static_cast<std::size_t>(end - begin);
    if (w.lake.size() < len)
        for (auto* v : {&w.lake, &w.transpiration_m3, &w.evaporation_m3}) v->resize(len);
    for (std::int64_t k = begin; k < end; ++k)
        w.lake[static_cast<std::size_t>(k - begin)] = lakes.owner(k) != 0 ? 1.0 : 0.0;
    auto at = [&](auto* p) { return p ? p + begin : nullptr; };
    const Fao56Cells cells{day.cover + begin,
                           at(day.intercepted_m),
                           at(request_mm),
                           day.kr + begin,
                           day.tew_mm + begin,
                           soil.wilting_point + begin,
                           soil.field_capacity + begin,
                           w.lake.data(),
                           soil.theta + begin,
                           at(soil.surface_depletion_mm),
                           supplied_mm + begin,
                           w.transpiration_m3.data(),
                           w.evaporation_m3.data()};
    evapotranspiration_fao56_cells(end - begin, day, cells, soil.depth_m, soil.cell_area_m2);
    double t_m3 = 0, e_m3 = 0;
    for (std::size_t i = 0; i < len; ++i) {
        t_m3 += w.transpiration_m3[i];
        e_m3 += w.evaporation_m3[i];
    }
    transpiration_m3 += t_m3;
    evaporation_m3 += e_m3;
}

double critical_layer_day(const CriticalLayerCell& c, double theta0, double inflow_m,
                          double evaporation_m, double transpiration_m, double column_theta,
                          double dt_s) {
    const double wetted = critical_layer_wetted(c, theta0, inflow_m);
    const double drained = critical_layer_drains(c, wetted, column_theta)
                               ? std::max(drained_theta(wetted, c.porosity, c.exponent,
                                                        c.ksat_m_per_s, c.depth_m, dt_s),
                                          column_theta)
                               : wetted;
    return critical_layer_rest(c, drained, evaporation_m, transpiration_m, column_theta);
}

void gravity_drainage_range(const SoilColumns& soil, const float* porosity, const float* exponent,
                            std::int64_t begin, std::int64_t end, double dt_s,
                            std::vector<double>* recharge, double& drained_m3, double* scratch) {
    const double area = soil.cell_area_m2, depth = soil.depth_m;
    drained_theta_cells(end - begin, soil.theta + begin, porosity + begin, exponent + begin,
                        soil.ksat_m_per_s + begin, depth, dt_s, scratch + begin);
    double sum_m3 = 0; // in cell order
    for (std::int64_t k = begin; k < end; ++k) {
        double& th = soil.theta[k];
        const double wp = soil.wilting_point[k];
        if (!(th > wp)) continue;
        const double th1 = std::max(wp, scratch[k]);
        const double m3 = (th - th1) * depth * area;
        th = th1;
        if (recharge)
            (*recharge)[k] += m3;
        else
            sum_m3 += m3;
    }
    drained_m3 += sum_m3;
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
