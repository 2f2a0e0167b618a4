#include "ecoterra/hydro/hydrology.hpp"
#include "ecoterra/units.hpp"

#include "ecoterra/hydro/groundwater.hpp"
#include "ecoterra/hydro/kernels.hpp"
#include "ecoterra/parallel.hpp"
#include "ecoterra/terrain/roughness.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>

namespace ecoterra::hydro {

namespace {

/// Every cell after all its strictly higher neighbours (a topological order of D8 and MFD flow),
/// built by Kahn's algorithm following each chain downhill, so that consecutive cells are close
/// in memory.
std::vector<std::int64_t> upstream_first_order(const RasterD& dem) {
    const auto& g = dem.grid();
    const double* z = dem.data();
    constexpr std::uint8_t kDone = 255;
    std::vector<std::uint8_t> higher(static_cast<std::size_t>(g.size()), 0);
    for (int j = 0; j < g.ny; ++j)
        for (int i = 0; i < g.nx; ++i)
            dem.for_moore(i, j, [&](int a, int b) {
                higher[cell_index(g, i, j)] += z[cell_index(g, a, b)] > z[cell_index(g, i, j)];
            });
    std::vector<std::int64_t> order, stack;
    order.reserve(static_cast<std::size_t>(g.size()));
    for (std::int64_t c = 0; c < g.size(); ++c) {
        if (higher[c] != 0) continue;
        higher[c] = kDone;
        stack.push_back(c);
        while (!stack.empty()) {
            const std::int64_t x = stack.back();
            stack.pop_back();
            order.push_back(x);
            const int i = static_cast<int>(x % g.nx), j = static_cast<int>(x / g.nx);
            dem.for_moore(i, j, [&](int a, int b) {
                const std::int64_t y = cell_index(g, a, b);
                if (z[y] < z[x] && --higher[y] == 0) {
                    higher[y] = kDone;
                    stack.push_back(y);
                }
            });
        }
    }
    return order;
}
} // namespace

const std::vector<Column<BudgetRow>>& daily_budget_columns() {
    using R = BudgetRow;
    const char* mm = "mm/day";
    static const std::vector<Column<R>> c = {
        column("day", &R::day, "1", "simulation day, 1-based", ColumnType::int64),
        column("year", &R::year, "1", "simulation year (or calendar year)", ColumnType::int64),
        column("day_of_year", &R::day_of_year, "1", "day of year", ColumnType::int64),
        column("rain_mm", &R::rain_mm, mm, "rain over the domain"),
        column("evaporation_mm", &R::evaporation_mm, mm, "soil and open-water evaporation"),
        column("transpiration_mm", &R::transpiration_mm, mm, "transpiration supplied to plants"),
        column("interception_mm", &R::interception_mm, mm,
               "rain held on the canopy and evaporated from it"),
        column("infiltration_mm", &R::infiltration_mm, mm, "infiltration into the soil"),
        column("runoff_out_mm", &R::runoff_out_mm, mm,
               "surface water that left through the domain edge"),
        column("drainage_out_mm", &R::drainage_out_mm, mm,
               "water drained below the root zone out of the domain (groundwater off)"),
        column("groundwater_out_mm", &R::groundwater_out_mm, mm,
               "groundwater that left through fixed-head edges"),
        column("recharge_mm", &R::recharge_mm, mm, "percolation to the water table"),
        column("d_soil_storage_mm", &R::d_soil_storage_mm, mm, "change in root-zone storage"),
        column("d_surface_storage_mm", &R::d_surface_storage_mm, mm,
               "change in standing surface water"),
        column("d_groundwater_storage_mm", &R::d_groundwater_storage_mm, mm,
               "change in groundwater storage"),
        column("residual_mm", &R::residual_mm, mm, "rain - outputs - storage changes"),
    };
    return c;
}

BudgetRow daily_budget_row(int day, const DayWeather& w, const DailyFluxes& f, double domain_m2) {
    const double to_mm = kMmPerM / domain_m2;
    BudgetRow r;
    r.day = day;
    r.year = w.year;
    r.day_of_year = w.doy;
    r.rain_mm = f.rain * to_mm;
    r.evaporation_mm = f.evaporation * to_mm;
    r.transpiration_mm = f.transpiration * to_mm;
    r.interception_mm = f.interception * to_mm;
    r.infiltration_mm = f.infiltration * to_mm;
    r.runoff_out_mm = f.runoff_out * to_mm;
    r.drainage_out_mm = f.drainage_out * to_mm;
    r.groundwater_out_mm = f.groundwater_out * to_mm;
    r.recharge_mm = f.recharge * to_mm;
    r.d_soil_storage_mm = f.d_soil * to_mm;
    r.d_surface_storage_mm = f.d_surface * to_mm;
    r.d_groundwater_storage_mm = f.d_groundwater * to_mm;
    r.residual_mm = f.residual * to_mm;
    return r;
}

et::DailyWeather et_weather(const DayWeather& w, const Climate& c) {
    et::DailyWeather dw;
    dw.lat_deg = c.latitude_deg;
    dw.elevation_m = c.elevation_m;
    dw.doy = std::min(w.doy, 366);
    dw.tmin_c = w.tmin_c;
    dw.tmax_c = w.tmax_c;
    dw.tdew_c = w.tdew_c;
    dw.u2_m_per_s = w.u2_m_per_s;
    dw.rs_mj = w.rs_mj;
    return dw;
}

namespace {
/// The groundwater keys of the hydrology section, in their place in its listing.
std::vector<Param<HydrologyOptions>> groundwater_params() {
    using O = HydrologyOptions;
    return {
        flag<O>("groundwater", &O::groundwater, "lateral groundwater flow under the root zone"),
        number<O>("specific_yield", &O::specific_yield, "m3/m3", 0.001, 0.6,
                  "drainable porosity of the aquifer"),
        number<O>("aquifer_thickness_m", &O::aquifer_thickness_m, "m", 0.1, 1000,
                  "from the impermeable base to the surface"),
        number<O>("initial_water_table_depth_m", &O::initial_water_table_depth_m, "m", 0, 1000,
                  "below the surface at the start; at most aquifer_thickness_m"),
        choice<O>(
            "groundwater_solver", &O::groundwater_solver,
            std::vector<std::pair<std::string, GroundwaterSolver>>{
                {"implicit", GroundwaterSolver::implicit}, {"cvode", GroundwaterSolver::cvode}},
            "implicit: TR-BDF2 steps, each stage solved by multigrid-preconditioned "
            "conjugate gradients, work in proportion to the cells (docs/hydrology.md); cvode: "
            "the error-controlled reference (CVODE BDF + KLU), for grids up to ~128 x 128"),
        integer<O>("groundwater_steps_per_day", &O::groundwater_steps_per_day, "1/d", 1, 96,
                   "TR-BDF2 steps a day of the implicit solver; its water-table error is second "
                   "order in the step (under 1 cm a year against cvode at 2)"),
        number<O>("groundwater_head_tolerance_m", &O::groundwater_head_tolerance_m, "m", 1e-9, 1e-2,
                  "the implicit solver's stages stop when their residual stands for at most this "
                  "root mean square change of head (an order below the step's error at 2 a day)"),
        integer<O>("aquifer_cell_factor", &O::aquifer_cell_factor, "terrain cells", 1, 64,
                   "the aquifer's cells are this many terrain cells on a side (a divisor of the "
                   "terrain's columns and rows); 1 solves it on the terrain's cells, 4 on 1 m "
                   "terrain ~16 x faster with its water table interpolated back "
                   "(docs/hydrology.md s6)")};
}

/// The keys of the hydrology section before the groundwater ones.
std::vector<Param<HydrologyOptions>> surface_params() {
    using O = HydrologyOptions;
    return {number<O>("root_zone_depth_m", &O::root_zone_depth_m, "m", 0.01, 10,
                      "depth of the root zone whose water the model tracks"),
            number<O>("initial_saturation", &O::initial_saturation, "1", 0, 1,
                      "initial soil water as a fraction s of FC - WP: theta0 = WP + s (FC - WP)"),
            choice<O>(
                "routing", &O::routing,
                std::vector<std::pair<std::string, Routing>>{
                    {"d8", Routing::d8}, {"d8-lowest", Routing::d8_lowest}, {"mfd", Routing::mfd}},
                "flow directions: d8 steepest descent, d8-lowest lowest neighbour (as "
                "Fill-Spill-Merge), mfd multiple flow directions"),
            choice<O>("runoff", &O::runoff,
                      std::vector<std::pair<std::string, RunoffMethod>>{
                          {"coefficients", RunoffMethod::coefficients},
                          {"curve_number", RunoffMethod::curve_number}},
                      "rain partition: runoff coefficients (vegetation x slope x texture) or the "
                      "SCS curve number"),
            number<O>("flat_slope", &O::flat_slope, "1", 0, 1,
                      "slope (rise/run) below which a cell absorbs all its rain"),
            number<O>("grass_density_threshold", &O::grass_density_threshold, "1", 0, 1,
                      "vegetation density at which the surface evaporates as grass, not bare soil"),
            choice<O>("wind_function", &O::wind, et::wind_function_keys(), "Penman wind function")};
}

/// The keys of the hydrology section after the groundwater ones: the soil water's methods.
std::vector<Param<HydrologyOptions>> soil_water_params() {
    using O = HydrologyOptions;
    return {choice<O>("evapotranspiration", &O::evapotranspiration,
                      std::vector<std::pair<std::string, EvapotranspirationMethod>>{
                          {"fao56", EvapotranspirationMethod::fao56},
                          {"paper002", EvapotranspirationMethod::paper002}},
                      "fao56: two-stage soil evaporation plus transpiration, each limited (FAO-56 "
                      "dual coefficients); paper002: the larger of the surface's Penman demand and "
                      "the plants' request"),
            choice<O>("drainage", &O::drainage,
                      std::vector<std::pair<std::string, DrainageMethod>>{
                          {"gravity", DrainageMethod::gravity}, {"none", DrainageMethod::none}},
                      "gravity: the soil holds up to its porosity and drains at K(theta) (Saxton & "
                      "Rawls 2006); none (paper 002): it holds up to field capacity, the rest runs "
                      "off (or percolates at Ksat with groundwater on)"),
            choice<O>("interception", &O::interception,
                      std::vector<std::pair<std::string, InterceptionMethod>>{
                          {"gash", InterceptionMethod::gash}, {"none", InterceptionMethod::none}},
                      "gash: the canopy holds and evaporates rain (Gash 1979, sparse form 1995); "
                      "none (paper 002)"),
            number<O>("surface_layer_depth_m", &O::surface_layer_depth_m, "m", 0.05, 0.25,
                      "depth Ze of the evaporating surface layer (FAO-56 eq. 73: 0.10-0.15)"),
            choice<O>("evaporable_water", &O::evaporable_water,
                      std::vector<std::pair<std::string, EvaporableWater>>{
                          {"sqrt_et0", EvaporableWater::sqrt_et0}, {"eq73", EvaporableWater::eq73}},
                      "the surface layer's total evaporable water TEW: sqrt_et0 scales FAO-56 eq. "
                      "73 by min(1, sqrt(ET0 / 5 mm/day)) each day (FAO-56 ch. 6's initial-stage "
                      "TEW, 13 sqrt(ET0) up to 28 mm on medium soils); eq73: eq. 73 alone (as "
                      "pyfao56)"),
            number<O>("critical_layer_depth_m", &O::critical_layer_depth_m, "m", 0, 5,
                      "top of the root zone whose water sets the soil's strength for vehicles "
                      "(6-12 in, Priddy & Willoughby 2004); 0: none, the root zone's water"),
            number<O>("kc_max", &O::kc_max, "1", 1.0, 1.4,
                      "upper limit of the crop and evaporation coefficients, Kcb + Ke (FAO-56 eq. "
                      "72)"),
            number<O>("depletion_fraction", &O::depletion_fraction, "1", 0, 0.9,
                      "fraction p of the available water plants use before transpiration falls "
                      "(FAO-56 eq. 84, Table 22)"),
            number<O>("canopy_storage_per_lai_mm", &O::canopy_storage_per_lai_mm, "mm", 0, 2,
                      "rain a unit of leaf area index holds (Gash interception)"),
            number<O>("wet_canopy_evaporation_ratio", &O::wet_canopy_evaporation_ratio, "1", 0.01,
                      0.9,
                      "mean evaporation rate from a wet canopy over the mean rain rate (Gash)"),
            number<O>("canopy_extinction", &O::canopy_extinction, "1", 0.1, 2,
                      "k of cover = 1 - exp(-k LAI) when hydrology runs without plants (the "
                      "vegetation density is the cover)")};
}
} // namespace

const ParamCatalog<HydrologyOptions>& hydrology_catalog() {
    static const ParamCatalog<HydrologyOptions> c("hydrology", [] {
        std::vector<Param<HydrologyOptions>> p = surface_params();
        for (auto&& part : {groundwater_params(), soil_water_params()})
            for (const auto& q : part) p.push_back(q);
        return p;
    }());
    return c;
}

void HydrologyOptions::validate() const {
    hydrology_catalog().check(*this);
    if (!(initial_water_table_depth_m <= aquifer_thickness_m))
        throw InputError("hydrology.initial_water_table_depth_m = " +
                         format_number(initial_water_table_depth_m) +
                         " is below the aquifer base (aquifer_thickness_m = " +
                         format_number(aquifer_thickness_m) + ")");
    if (critical_layer_depth_m != 0 && !(critical_layer_depth_m >= 0.01))
        throw InputError(
            "hydrology.critical_layer_depth_m = " + format_number(critical_layer_depth_m) +
            " is too thin: give at least 0.01 m, or 0 for none");
    if (!(critical_layer_depth_m < root_zone_depth_m))
        throw InputError(
            "hydrology.critical_layer_depth_m = " + format_number(critical_layer_depth_m) +
            " must be less than hydrology.root_zone_depth_m = " + format_number(root_zone_depth_m));
    if (!(budget_tolerance >= 0 && budget_tolerance <= 1))
        throw InputError("hydrology budget_tolerance = " + format_number(budget_tolerance) +
                         " is outside [0, 1]");
}

HydrologyModel::HydrologyModel(const RasterD& dem, const SoilMap& soil, const RasterD& veg,
                               const HydrologyOptions& opt, const Climate& climate)
    : m_dem(dem), m_soil(soil), m_veg(veg), m_opt(opt), m_climate(climate),
      m_catch(dem, d8_rule(opt.routing)), m_table(RunoffTable::standard()),
      m_area(dem.cell_size() * dem.cell_size()) {
    opt.validate();
    climate.validate();
    if (!(soil.grid() == dem.grid()))
        throw InputError("the soil map's grid does not match the terrain's");
    if (!(veg.grid() == dem.grid()))
        throw InputError("the vegetation-density raster's grid does not match the terrain's");
    for (std::int64_t k = 0; k < dem.size(); ++k)
        if (std::isnan(dem.data()[k]))
            throw InputError("the terrain has NODATA cells; fill or crop them before a hydrology "
                             "run");
    const auto& g = dem.grid();
    m_theta = RasterD(g);
    m_coef = RasterD(g);
    m_transp_supplied = RasterD(g, 0.0);
    m_slope = terrain::slope_aspect(dem).slope;
    for (std::int64_t k = 0; k < dem.size(); ++k) {
        const double wp = soil.wilting_point.data()[k], fc = soil.field_capacity.data()[k];
        m_theta.data()[k] = wp + opt.initial_saturation * (fc - wp);
    }
    m_top_theta = m_theta;
    set_vegetation_density(veg);
    m_order = upstream_first_order(dem);
    m_runoff.assign(static_cast<std::size_t>(dem.size()), 0.0);
    m_recharge.assign(static_cast<std::size_t>(dem.size()), 0.0);
    init_soil_layers();
    if (opt.groundwater &&
        (dem.nx() % opt.aquifer_cell_factor || dem.ny() % opt.aquifer_cell_factor))
        throw InputError(
            "hydrology.aquifer_cell_factor = " + std::to_string(opt.aquifer_cell_factor) +
            " does not divide the terrain's " + std::to_string(dem.nx()) + " x " +
            std::to_string(dem.ny()) + " cells; choose a divisor of both");
    if (opt.groundwater)
        m_gw = std::make_unique<Groundwater>(
            dem, soil.ksat_m_per_s, opt.specific_yield, opt.aquifer_thickness_m,
            opt.initial_water_table_depth_m,
            GroundwaterNumerics{opt.groundwater_solver, opt.groundwater_steps_per_day,
                                opt.groundwater_head_tolerance_m, opt.aquifer_cell_factor});
}

HydrologyModel::~HydrologyModel() = default;

void HydrologyModel::init_soil_layers() {
    const std::int64_t n = m_dem.size();
    const auto un = static_cast<std::size_t>(n);
    m_de = RasterD(m_dem.grid(), 0.0);
    m_tew.assign(un, 0.0f);
    m_rew.assign(un, 0.0f);
    m_drain_exponent.assign(un, 0.0f);
    m_scratch.assign(un, 0.0);
    m_kr.assign(un, 1.0);
    m_intercepted.assign(un, 0.0);
    for (std::int64_t k = 0; k < n; ++k) {
        const double fc = m_soil.field_capacity.data()[k], wp = m_soil.wilting_point.data()[k];
        // FAO-56 eq. 73; REW at most 90 % of TEW (thin sandy layers).
        const double tew = 1000.0 * (fc - 0.5 * wp) * m_opt.surface_layer_depth_m;
        const double rew = std::min(
            readily_evaporable_water_mm(static_cast<Texture>(m_soil.texture.data()[k])), 0.9 * tew);
        m_tew[k] = static_cast<float>(tew);
        m_rew[k] = static_cast<float>(rew);
        m_drain_exponent[k] = static_cast<float>(conductivity_exponent(fc, wp));
        if (m_opt.drainage == DrainageMethod::gravity &&
            (!(wp > 0 && fc > wp && m_soil.porosity.data()[k] > fc) ||
             !std::isfinite(m_drain_exponent[k])))
            throw InputError("soil at cell " + std::to_string(k) +
                             ": gravity drainage needs 0 < "
                             "wilting point < field capacity < porosity, got " +
                             format_number(wp) + ", " + format_number(fc) + " and " +
                             format_number(m_soil.porosity.data()[k]) +
                             " (hydrology.drainage = none keeps paper 002's soil water)");
        // The surface layer starts as wet as the root zone.
        if (m_opt.evapotranspiration == EvapotranspirationMethod::fao56)
            m_de.data()[k] = tew * (1.0 - m_opt.initial_saturation);
    }
}

void HydrologyModel::leaves_of_the_day(const RasterD* lai, const RasterD* cover) {
    if (lai) { // the plants' rasters, read in place for the day
        m_day_lai = lai->data();
        m_day_cover = cover->data();
        return;
    }
    if (!m_leaves_from_density) { // the density changed (or is new): its leaves
        const auto n = static_cast<std::size_t>(m_dem.size());
        m_lai.resize(n);
        m_cover.resize(n);
        for (std::size_t k = 0; k < n; ++k) {
            const double v = std::min(m_veg.data()[k], 0.99);
            m_cover[k] = v;
            m_lai[k] = -std::log1p(-v) / m_opt.canopy_extinction;
        }
        m_leaves_from_density = true;
    }
    m_day_lai = m_lai.data();
    m_day_cover = m_cover.data();
}

void HydrologyModel::set_vegetation_density(const RasterD& veg) {
    if (!(veg.grid() == m_dem.grid()))
        throw InputError("the vegetation-density raster's grid does not match the terrain's");
    for (std::int64_t k = 0; k < veg.size(); ++k) {
        const double v = veg.data()[k];
        if (!(v >= 0 && v <= 1))
            throw InputError("vegetation density must be in [0, 1], got " + std::to_string(v) +
                             " at cell " + std::to_string(k));
    }
    m_veg = veg;
    m_leaves_from_density = false; // recomputed from the new density unless the plants give theirs
    update_runoff_coefficients();
}

void HydrologyModel::update_runoff_coefficients() {
    for (std::int64_t k = 0; k < m_dem.size(); ++k)
        m_coef.data()[k] =
            m_slope.data()[k] < m_opt.flat_slope
                ? 0.0
                : m_table.coefficient(m_veg.data()[k], m_slope.data()[k],
                                      static_cast<Texture>(m_soil.texture.data()[k]));
}

double HydrologyModel::soil_storage_m3() const {
    if (!std::isnan(m_soil_storage_end_m3)) return m_soil_storage_end_m3;
    const double* th = m_theta.data();
    // Blocked sums are off by ~1e-9 m3 a day at 512^2 here (soil water is a small fraction of
    // each cell), far inside the budget's tolerance; the groundwater storage, large and nearly
    // constant, needs the compensated sum.
    return blocked_sums<1>(m_theta.size(), [&](std::int64_t k, auto& s) { s[0] += th[k]; })[0] *
           m_opt.root_zone_depth_m * m_area;
}

double HydrologyModel::groundwater_storage_m3() const {
    return m_gw ? m_gw->storage_m3() : 0.0;
}

RasterD HydrologyModel::water_table_depth() const {
    if (!m_gw) return RasterD(m_dem.grid(), std::nan(""));
    RasterD d = m_gw->head();
    d.array() = m_dem.array() - d.array();
    return d;
}

DailyFluxes HydrologyModel::step(const DayWeather& w, const RasterD* transp_mm, const RasterD* lai,
                                 const RasterD* cover) {
    if (transp_mm && !(transp_mm->grid() == m_dem.grid()))
        throw InputError("the transpiration demand raster's grid does not match the terrain's");
    if ((lai == nullptr) != (cover == nullptr) ||
        (lai && (!(lai->grid() == m_dem.grid()) || !(cover->grid() == m_dem.grid()))))
        throw InputError("the leaf-area and cover rasters must both be given, on the terrain's "
                         "grid");
    ++m_day;
    DailyFluxes f;
    const std::int64_t cells = m_dem.grid().size();
    const double soil0 = soil_storage_m3(), surf0 = m_catch.total_volume_m3(),
                 gw0 = groundwater_storage_m3(), lost0 = m_catch.lost_m3();
    m_soil_storage_end_m3 = std::nan(""); // theta changes from here; close_budget sets it
    const bool fao = m_opt.evapotranspiration == EvapotranspirationMethod::fao56;
    const bool gash = m_opt.interception == InterceptionMethod::gash;
    const et::DailyWeather dw = et_weather(w, m_climate);
    const double e0_mm = std::max(0.0, et::penman_open_water(dw, m_opt.wind));
    const double rain_m = w.rain_mm / kMmPerM;
    f.rain = rain_m * m_area * static_cast<double>(cells);
    const SoilColumns soil{m_theta.data(),
                           m_soil.field_capacity.data(),
                           m_soil.wilting_point.data(),
                           m_soil.ksat_m_per_s.data(),
                           m_opt.root_zone_depth_m,
                           m_area,
                           m_opt.drainage == DrainageMethod::gravity ? m_soil.porosity.data()
                                                                     : nullptr,
                           fao ? m_de.data() : nullptr};
    std::vector<double>* recharge = m_gw ? &m_recharge : nullptr; // m3 per cell
    if (recharge) std::fill(recharge->begin(), recharge->end(), 0.0);
    const bool layer = has_critical_layer();
    if (fao || gash) leaves_of_the_day(lai, cover);
    if (layer) m_theta_start.resize(static_cast<std::size_t>(cells));
    const double et0_mm = fao ? std::max(0.0, et::fao56_reference_daily(dw)) : 0.0;
    const double scale = tew_scale(et0_mm);
    if (fao || layer) {
        // The root zone's water at the day's start (for the critical layer); FAO-56 eq. 74 takes
        // the surface layer's depletion at the end of the previous day.
        const double *de = m_de.data(), *th = m_theta.data();
#pragma omp parallel for schedule(static) if (cells >= parallel_min_items())
        for (std::int64_t k = 0; k < cells; ++k) {
            if (layer) m_theta_start[k] = th[k];
            if (!fao) continue;
            m_kr[k] = evaporation_reduction(m_tew[k], m_rew[k], scale, de[k]);
        }
    }

    lake_losses(m_catch, m_dem, soil, e0_mm, recharge, f.evaporation, f.infiltration);
    if (rain_m > 0) {
        rain_on_lakes(m_catch, rain_m, m_area);
        if (gash)
            canopy_interception(
                m_catch, m_day_lai, m_day_cover, w.rain_mm,
                {m_opt.canopy_storage_per_lai_mm, m_opt.wet_canopy_evaporation_ratio}, m_area,
                m_intercepted, f.interception);
        RainPartition rain{m_opt.runoff,   rain_m,           w.rain_mm,    m_coef.data(),
                           m_slope.data(), m_opt.flat_slope, m_veg.data(), m_soil.texture.data()};
        if (gash) rain.intercepted_m = m_intercepted.data();
        partition_rain(m_catch, soil, rain, m_runoff, recharge, f.infiltration);
        route_runoff(m_catch, soil, m_order, m_opt.routing, m_runoff, f.infiltration);
    }
    m_catch.equilibrate();
    // Today's interception (its energy is not the leaves' to transpire); none on a dry day.
    const double* intercepted = gash && rain_m > 0 ? m_intercepted.data() : nullptr;
    double theta_sum = soil_day(f, soil, e0_mm, et0_mm, dw, transp_mm ? transp_mm->data() : nullptr,
                                intercepted, recharge);
    if (m_gw) {
        f.recharge =
            blocked_sums<1>(cells, [&](std::int64_t k, auto& sum) { sum[0] += m_recharge[k]; })[0];
        f.groundwater_out = groundwater_exchange(*m_gw, m_catch, m_recharge, m_day, w.year, w.doy);
        theta_sum = blocked_range_sums<1>(
            cells, [&](std::int64_t b, std::int64_t e, auto& sum) { soil_day_end(b, e, sum[0]); },
            parallel_min_items())[0];
    }
    close_budget(f, w, soil0, theta_sum * m_opt.root_zone_depth_m * m_area, surf0, gw0, lost0);
    return f;
}

void HydrologyModel::critical_layer_range(std::int64_t k0, std::int64_t k1) {
    const bool gravity = m_opt.drainage == DrainageMethod::gravity;
    const auto at = [k0](auto* p) { return p + k0; };
    CriticalLayerCells c;
    c.depth_m = m_opt.critical_layer_depth_m;
    c.root_depth_m = m_opt.root_zone_depth_m;
    c.ceiling = at(gravity ? m_soil.porosity.data() : m_soil.field_capacity.data());
    c.wilting_point = at(m_soil.wilting_point.data());
    c.porosity = at(m_soil.porosity.data());
    c.exponent = at(m_drain_exponent.data());
    c.theta_start = at(m_theta_start.data());
    c.theta_wet = at(m_theta_wet.data());
    c.theta_et = at(m_theta_et.data());
    c.column_theta = at(m_theta.data());
    c.transpiration_mm = at(m_transp_supplied.data());
    // critical_layer_day in three passes, so the drainage runs over the block's draining cells
    // gathered together (drained_theta_cells), with the same result. The layer drains on 50-74 %
    // of cell-days (bench_hydro, a 1 km2 year, the quickstart's century: measured 2026-11-27).
    struct Gathered {
        std::vector<double> drains, drained, theta0, theta1;
        std::vector<float> porosity, exponent, ksat;
        std::vector<std::int32_t> cell;
    };
    thread_local Gathered g;
    const auto len = static_cast<std::size_t>(k1 - k0);
    if (g.theta0.size() < len) {
        for (auto* v : {&g.drains, &g.drained, &g.theta0, &g.theta1}) v->resize(len);
        for (auto* v : {&g.porosity, &g.exponent, &g.ksat}) v->resize(len);
        g.cell.resize(len);
    }
    double* wetted = at(m_scratch.data());
    critical_layer_wetted_cells(k1 - k0, c, at(m_top_theta.data()), wetted, g.drains.data());
    std::size_t n = 0;
    for (std::size_t i = 0; i < len; ++i) {
        if (g.drains[i] == 0.0) continue;
        g.cell[n] = static_cast<std::int32_t>(i);
        g.theta0[n] = wetted[i];
        g.porosity[n] = c.porosity[i];
        g.exponent[n] = c.exponent[i];
        g.ksat[n] = m_soil.ksat_m_per_s.data()[k0 + static_cast<std::int64_t>(i)];
        ++n;
    }
    drained_theta_cells(static_cast<std::int64_t>(n), g.theta0.data(), g.porosity.data(),
                        g.exponent.data(), g.ksat.data(), c.depth_m, 86400.0, g.theta1.data());
    for (std::size_t j = 0; j < n; ++j)
        g.drained[static_cast<std::size_t>(g.cell[j])] = g.theta1[j];
    critical_layer_rest_cells(k1 - k0, c, wetted, g.drains.data(), g.drained.data(),
                              at(m_top_theta.data()));
}

void HydrologyModel::soil_day_end(std::int64_t begin, std::int64_t end, double& theta_sum) {
    if (has_critical_layer()) critical_layer_range(begin, end);
    const double* th = m_theta.data();
    double s = 0; // in cell order, as soil_storage_m3
    for (std::int64_t k = begin; k < end; ++k) s += th[k];
    theta_sum += s;
}

double HydrologyModel::tew_scale(double et0_mm) const {
    // 1 unless FAO-56's evaporation runs with the ET0-scaled TEW (without FAO-56 et0_mm is 0).
    return m_opt.evapotranspiration == EvapotranspirationMethod::fao56 &&
                   m_opt.evaporable_water == EvaporableWater::sqrt_et0
               ? evaporable_water_scale(et0_mm)
               : 1.0;
}

double HydrologyModel::soil_day(DailyFluxes& f, const SoilColumns& soil, double e0_mm,
                                double et0_mm, const et::DailyWeather& dw, const double* request_mm,
                                const double* intercepted_m, std::vector<double>* recharge) {
    const std::int64_t cells = m_dem.grid().size();
    const bool fao = m_opt.evapotranspiration == EvapotranspirationMethod::fao56;
    const bool gravity = m_opt.drainage == DrainageMethod::gravity;
    const bool layer = has_critical_layer();
    const SurfaceDemand demand{et::kPenmanBareSoilFactor * e0_mm,
                               et::penman_grass_factor(m_climate.latitude_deg, dw.doy) * e0_mm,
                               m_veg.data(), m_opt.grass_density_threshold};
    Fao56Day day;
    day.et0_mm = et0_mm;
    day.kc_max = m_opt.kc_max;
    day.depletion_fraction = m_opt.depletion_fraction;
    day.cover = m_day_cover;
    day.intercepted_m = intercepted_m;
    day.tew_mm = m_tew.data();
    day.tew_scale = tew_scale(et0_mm);
    day.kr = m_kr.data();
    if (layer) {
        m_theta_wet.resize(static_cast<std::size_t>(cells));
        m_theta_et.resize(static_cast<std::size_t>(cells));
    }
    double* th = m_theta.data();
    double* supplied = m_transp_supplied.data();
    // Steps 6 and 6b and, without groundwater, 9 and the soil's storage, a block of cells at a
    // time while it is in cache; each sum in cell order within a block and then in block order,
    // as the grid-wide kernels take them.
    const auto sums = blocked_range_sums<4>(
        cells,
        [&](std::int64_t b, std::int64_t e, auto& sum) {
            if (layer) std::copy(th + b, th + e, m_theta_wet.data() + b);
            if (fao)
                evapotranspiration_fao56_range(m_catch, soil, b, e, day, request_mm, supplied,
                                               sum[0], sum[1]);
            else
                evapotranspiration_range(m_catch, soil, b, e, demand, request_mm, supplied, sum[0],
                                         sum[1]);
            if (layer) std::copy(th + b, th + e, m_theta_et.data() + b);
            if (gravity)
                gravity_drainage_range(soil, m_soil.porosity.data(), m_drain_exponent.data(), b, e,
                                       86400.0, recharge, sum[2], m_scratch.data());
            if (!m_gw) soil_day_end(b, e, sum[3]);
        },
        parallel_min_items());
    f.transpiration += sums[0];
    f.evaporation += sums[1];
    f.drainage_out += sums[2];
    return m_gw ? std::nan("") : sums[3];
}

void HydrologyModel::close_budget(DailyFluxes& f, const DayWeather& w, double soil0, double soil1,
                                  double surf0, double gw0, double lost0) {
    f.runoff_out = m_catch.lost_m3() - lost0;
    f.d_soil = soil1 - soil0;
    f.d_surface = m_catch.total_volume_m3() - surf0;
    f.d_groundwater = groundwater_storage_m3() - gw0;
    f.residual = f.rain - f.evaporation - f.transpiration - f.interception - f.runoff_out -
                 f.drainage_out - f.groundwater_out - f.d_soil - f.d_surface - f.d_groundwater;
    m_cum_residual += f.residual;
    m_cum_throughput += f.rain + f.evaporation + f.transpiration + f.interception + f.runoff_out +
                        f.drainage_out + std::abs(f.groundwater_out);
    // Written so that NaN (from a non-finite input that got this far) fails the check too.
    if (!(std::abs(m_cum_residual) <= m_opt.budget_tolerance * std::max(m_cum_throughput, 1.0))) {
        std::ostringstream s;
        s << "water budget broke on day " << m_day << " (year " << w.year << ", day " << w.doy
          << "): cumulative residual " << m_cum_residual << " m3 against a throughput of "
          << m_cum_throughput << " m3";
        throw Error(s.str());
    }
    m_soil_storage_end_m3 = soil1; // the same sum as soil_storage_m3's: the next day's start
}

} // namespace ecoterra::hydro

namespace ecoterra::hydro {

void HydrologyModel::save_state(ArchiveWriter& a) const {
    a.put_raster(m_theta);
    a.put_raster(m_transp_supplied);
    m_catch.save_state(a);
    a.put<bool>(m_gw != nullptr);
    if (m_gw) m_gw->save_state(a);
    a.put(m_cum_residual);
    a.put(m_cum_throughput);
    a.put(m_day);
    a.put_raster(m_de);        // state version 2
    a.put_raster(m_top_theta); // state version 3
}

void HydrologyModel::load_state(ArchiveReader& a, std::uint32_t version) {
    auto theta = a.get_raster<double>();
    auto supplied = a.get_raster<double>();
    if (!(theta.grid() == m_dem.grid()) || !(supplied.grid() == m_dem.grid()))
        throw CheckpointError("hydrology checkpoint: its grid differs from the terrain's");
    m_theta = std::move(theta);
    m_soil_storage_end_m3 = std::nan("");
    m_transp_supplied = std::move(supplied);
    m_catch.load_state(a);
    const bool gw = a.get<bool>();
    if (gw != (m_gw != nullptr))
        throw CheckpointError("hydrology checkpoint: groundwater is " +
                              std::string(gw ? "on" : "off") + " in the checkpoint and " +
                              (m_gw ? "on" : "off") + " in the scene");
    if (m_gw) m_gw->load_state(a);
    m_cum_residual = a.get<double>();
    m_cum_throughput = a.get<double>();
    m_day = a.get<int>();
    if (version >= 2) {
        auto de = a.get_raster<double>();
        if (!(de.grid() == m_dem.grid()))
            throw CheckpointError("hydrology checkpoint: its grid differs from the terrain's");
        m_de = std::move(de);
    } else if (m_opt.evapotranspiration == EvapotranspirationMethod::fao56) {
        // Older checkpoints have no surface layer: it starts as wet as the root zone.
        for (std::int64_t k = 0; k < m_de.size(); ++k) {
            const double fc = m_soil.field_capacity.data()[k], wp = m_soil.wilting_point.data()[k];
            const double s = std::clamp((m_theta.data()[k] - wp) / (fc - wp), 0.0, 1.0);
            m_de.data()[k] = m_tew[static_cast<std::size_t>(k)] * (1.0 - s);
        }
    }
    if (version >= 3) {
        auto top = a.get_raster<double>();
        if (!(top.grid() == m_dem.grid()))
            throw CheckpointError("hydrology checkpoint: its grid differs from the terrain's");
        m_top_theta = std::move(top);
    } else {
        m_top_theta = m_theta; // older checkpoints: the critical layer as wet as the root zone
    }
}

} // namespace ecoterra::hydro
