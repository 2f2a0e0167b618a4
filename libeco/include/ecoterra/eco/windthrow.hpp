#pragma once
// Windthrow (docs/ecosystem.md s13): a storm at each year's end, from a seeded series of annual
// maximum wind speeds (ForestGALES' wind climate) or given in the scene, fells the trees whose
// critical wind speed it exceeds. The critical speeds are ForestGALES' single-tree (TMC) method
// (Hale et al. 2015, Can. J. For. Res. 45:1, as the fgr package implements it): the turning moment
// coefficient from the tree's size and competition, the edge and gap factor of Gardiner et al.
// 2000 from the canopy upwind, the resistance to breakage from the stem's base and the modulus
// of rupture, to overturning from the stem's green mass and the species' Creg. A tree fails by
// the mode with the lower critical speed: uprooted (the stem falls downwind, the root plate
// stands on edge where it stood) or broken (iLand's split: the lower half of the stem's mass
// stands as a snag, the top falls downwind).
//
//   "vegetation": {"windthrow": {"enabled": true, "weibull_shape": 1.85,
//       "weibull_scale_m_per_s": 5.0, "storm_from_deg": 270,
//       "storms": [{"year": 40, "wind_m_per_s": 30, "from_deg": 250}]}}
//
// Every draw (the storm's speed and direction) comes from the stream "eco.wind", so the series is
// the same whatever else the run does; the storms named in the scene replace the drawn ones in
// their years.
//
// Severe convective storms (downbursts, derechos) are a second population the Weibull of the
// mean wind does not carry, and they fell most of eastern North America's forests (Canham &
// Loucks 1984). They strike a site as a Poisson process with a mean return period (default
// 1210 years: the catastrophic windthrow of Canham & Loucks), with a 3-s gust drawn uniformly in
// [40, 50] m/s (large forest damage needs gusts of about 40 m/s, Gregow et al. 2017; severe
// windstorms average 30-50 m/s, Xi & Peet's review) turned into an hourly mean by the gust
// factor 1.53 (ASCE 7-95 commentary, Durst's curve for a 3-s gust over open terrain). Their
// draws come from the stream "eco.wind.severe" indexed by year (three draws, stateless), so a
// resumed run draws the same and the synoptic series is unchanged.
#include "ecoterra/archive.hpp"
#include "ecoterra/catalog.hpp"
#include "ecoterra/eco/population.hpp"
#include "ecoterra/eco/species.hpp"
#include "ecoterra/random.hpp"
#include "ecoterra/raster.hpp"

#include <nlohmann/json.hpp>

#include <optional>
#include <vector>

namespace ecoterra::eco {

struct StormSpec {
    int year = 0;                   ///< the year-end it strikes at (1-based)
    double wind_m_per_s = 0;        ///< hourly mean wind 10 m above the zero-plane displacement
    std::optional<double> from_deg; ///< where it blows from, clockwise from north; none: drawn
};

/// Scene keys vegetation.windthrow.*.
struct WindthrowOptions {
    bool enabled = true;
    /// A storm each year drawn from the wind climate (false: only the storms listed).
    bool random_storms = true;
    /// Weibull shape of the hourly mean wind (ForestGALES' default 1.85, fgr).
    double weibull_shape = 1.85;
    /// Weibull scale of the hourly mean wind 10 m above the canopy's zero-plane displacement,
    /// m/s; none: from the climate's mean wind at 2 m (scene_config resolves it).
    std::optional<double> weibull_scale_m_per_s;
    /// Where the storms blow from, degrees clockwise from north; none: each storm's drawn.
    std::optional<double> storm_from_deg;
    /// Trees at least this tall are exposed (iLand's wind module: 4 m).
    double min_height_m = 4.0;
    /// What lies around the simulated area: "forest" (the stand continues: the canopy wraps
    /// around) or "open" (the area is an island of forest: the upwind border is an edge).
    bool open_surroundings = false;
    std::vector<StormSpec> storms;
    /// Severe convective storms (drawn like the synoptic ones: only with random_storms).
    bool severe_storms = true;
    /// Mean years between severe storms at a site (Canham & Loucks 1984: 1210).
    double severe_return_period_yr = 1210;
    /// The severe storm's 3-s gust is uniform in [min, max], m/s.
    double severe_gust_min_m_per_s = 40, severe_gust_max_m_per_s = 50;
    /// 3-s gust over the hourly mean (ASCE 7-95 commentary Fig. C6-1, Durst: 1.53).
    double gust_factor = 1.53;
};

const ParamCatalog<WindthrowOptions>& windthrow_catalog();
/// Reads vegetation.windthrow (the catalogue's keys plus "storms"); storms past `years`, at a
/// repeated year, or with speeds outside [0, 100] m/s are InputErrors naming
/// vegetation.windthrow.storms[K].KEY and the value.
WindthrowOptions read_windthrow(const nlohmann::json& j, int years);
nlohmann::json to_json(const WindthrowOptions& w);

namespace wind {
/// The Weibull scale of the hourly mean wind 10 m up from a mean wind at 2 m: FAO-56 Eq 47's
/// logarithmic profile lifts the mean (u10 = u2 ln(67.8 10 - 5.42) / 4.87), and a Weibull of
/// shape k has mean scale Gamma(1 + 1/k).
double weibull_scale_from_u2(double u2_mean_m_per_s, double shape);
/// ForestGALES' annual maximum: the square of the year's highest hourly mean wind follows a
/// Fisher-Tippett type I (Gumbel) distribution with mode U = (u_c a)^2 and dispersion U / 5,
/// u_c = -0.5903 k^3 + 4.4345 k^2 - 11.8633 k + 13.569 (fgr, annual_exceedance_prob and
/// fgr_constants). Probability that the year's maximum exceeds u.
double annual_exceedance(double u_m_per_s, double scale, double shape);
/// The year's maximum wind from a uniform draw p in (0, 1): the inverse of annual_exceedance.
double annual_maximum(double p, double scale, double shape);
/// The severe storm of `year` at a site, hourly mean m/s (0: none that year), and where it blows
/// from (drawn uniformly), from three draws of the stream "eco.wind.severe" indexed by the year.
struct SevereDraw {
    double wind_m_per_s = 0, from_deg = 0;
};
SevereDraw severe_storm(const WindthrowOptions& o, std::uint64_t seed, int year);

/// The edge and gap factor of the TMC method (Gardiner et al. 2000, fgr edge_gap_factor): how
/// much more bending moment a tree `dist_edge_m` downwind of an edge, behind a gap `gap_m` long,
/// takes than one deep in the stand; 1 inside (9 heights from the edge or no gap).
double edge_gap_factor(double spacing_m, double stand_height_m, double dist_edge_m, double gap_m);
/// Turning moment coefficient, N m per (m/s)^2 of canopy-top wind (Hale et al. 2015, fgr's
/// zero-intercept regression with Hegyi's competition index c): (124.252 - 17.285 c) D^2 H, D in
/// m. fgr's regression adds 3.86 c, fit to trees of 10-50 cm DBH: kept, it gives a 5 cm sapling
/// under the canopy the moment of a 20 cm tree (felled by a 10 m/s wind), so it is left out.
double turning_moment_coefficient(double dbh_m, double height_m, double hegyi);
/// Hegyi's index from the light a tree gets (iLand's wind module: c = 3.733 - 6.467 LRI,
/// within [0.5, 3.41]).
double hegyi_from_light(double light_fraction);

/// The stand as the wind sees it: the mean of the exposed trees.
struct StandAero {
    double mean_height_m = 0, top_height_m = 0, spacing_m = 0;
    double crown_width_m = 0, crown_depth_m = 0;
    double drag_c = 2.4, drag_n = 0.8; ///< the stand's mean streamlining
};
/// Zero-plane displacement and roughness length of the canopy, m, at the canopy-top wind `uh`
/// (Raupach 1994 as ForestGALES uses it: the crowns streamline as the drag c u^-n).
void displacement_and_roughness(const StandAero& a, double uh_m_per_s, double& d_m, double& z0_m);
/// The wind 10 m above the zero-plane displacement for a canopy-top wind uh (the logarithmic
/// profile from 1.05 times the top height, fgr's elevate).
double u10_from_uh(const StandAero& a, double uh_m_per_s);

/// One tree's critical winds, m/s (10 m above the displacement), and the factors behind them.
struct TreeWind {
    double breakage_m_per_s = 0, overturning_m_per_s = 0;
    double edge_gap_factor = 1, hegyi = 0;
    bool uproots() const { return overturning_m_per_s <= breakage_m_per_s; }
    double critical_m_per_s() const { return std::min(breakage_m_per_s, overturning_m_per_s); }
};
/// The critical winds of a tree of this species and size.
/// `tmr` is ForestGALES' turning-moment ratio after a thinning (1 without).
TreeWind tree_wind(const Species& s, double dbh_m, double height_m, double light_fraction,
                   const StandAero& stand, double dist_edge_m, double gap_m, double tmr);
/// The breakage resistance, N m: MOR f_knot pi D_base^3 / 32, D_base the diameter at the ground
/// of the stem that tapers from the DBH to the wind's point of action (fgr diam_base).
double breaking_moment_nm(const Species& s, double dbh_m, double height_m);
/// The overturning resistance, N m: Creg times the stem's green mass.
double overturning_moment_nm(const Species& s, double dbh_m, double height_m);
double crown_depth_m(const Species& s, double height_m);
} // namespace wind

/// The year's storm and what it did.
struct StormResult {
    double wind_m_per_s = 0;   ///< 0: no storm (windthrow off)
    double to_azimuth_rad = 0; ///< where it blows to, counterclockwise from east
    double uprooted = 0, broken = 0, basal_area_m2_per_ha = 0;
    bool severe = false; ///< the storm was a severe convective one
};

class Windthrow {
public:
    Windthrow(const WindthrowOptions& options, std::uint64_t seed);
    const WindthrowOptions& options() const { return m_opt; }

    /// The storm at the end of `year`: draws it (two draws of the stream, every year, so the
    /// series does not depend on the stand), then marks in `dead` with `uprooted` or `broken`
    /// the live trees (not yet marked) whose critical wind it exceeds.
    StormResult strike(const Population& pop, const std::vector<Species>& species,
                       const GridSpec& area, int year, std::vector<char>& dead, char uprooted,
                       char broken);
    /// Remembers a thinning (the spacing before it) for the turning-moment ratio of the next
    /// five years.
    void thinned(double spacing_before_m, int year);

    /// The critical winds of every plant (NaN for plants not exposed) for a wind from
    /// `to_azimuth_rad`.
    std::vector<wind::TreeWind> critical_winds(const Population& pop,
                                               const std::vector<Species>& species,
                                               const GridSpec& area, double to_azimuth_rad,
                                               int year) const;

    void save(ArchiveWriter& a) const;
    void load(ArchiveReader& a);

private:
    WindthrowOptions m_opt;
    std::uint64_t m_seed;
    Rng m_rng;
    double m_spacing_before_m = 0; ///< 0: no thinning yet
    int m_thin_year = -1000;
};

/// The mean spacing of the exposed trees (at least `min_height_m` tall), m; 0 with none.
double exposed_spacing_m(const Population& pop, const std::vector<Species>& species, double area_m2,
                         double min_height_m);

} // namespace ecoterra::eco
