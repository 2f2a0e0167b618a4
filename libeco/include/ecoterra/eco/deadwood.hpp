#pragma once
// Dead wood as individuals (docs/ecosystem.md s8). A tree of at least min_dbh_m that dies becomes
// a snag, which falls in a year drawn at its death (FVS-FFE's size-dependent fall rate: the
// standing share of a cohort falls linearly, as FFE's does) and then lies as a log along its fall
// direction (downhill on a slope, any direction on the flat). Snags and logs lose mass
// exponentially at their species' rates (standing wood more slowly), pass through the five decay
// classes by the share of mass left (iLand's thresholds), and vanish when 5 % is left. A snag loses
// its top with its class (Domke et al. 2011's structural loss); a log sinks toward the ground
// (class 4 oval, class 5 mostly buried). Geometry is derived from the mass: the mass is the state.
//
// The pieces are kept in the order they died; every random draw comes from the dead-wood stream,
// so the living stand is the same with dead wood on or off.
#include "ecoterra/archive.hpp"
#include "ecoterra/eco/population.hpp"
#include "ecoterra/eco/species.hpp"
#include "ecoterra/random.hpp"
#include "ecoterra/raster.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace ecoterra::eco {

/// Why a plant died (0: it did not). The yearly deaths_* columns count the same causes.
enum class DeathCause : std::uint8_t {
    none = 0,
    starvation,
    age,
    background,
    suppression,
    overlap,
    harvest,       ///< cut by a management operation (management.hpp)
    wind_uprooted, ///< overturned by a storm (windthrow.hpp)
    wind_broken,   ///< snapped by a storm
};
const char* death_cause_name(DeathCause c);

/// Scene keys vegetation.deadwood.* (scene_config.cpp lists them with their sources).
struct DeadWoodOptions {
    bool enabled = true;
    double stump_height_m = 0.2;         ///< vegetation.management.stump_height_m
    double min_dbh_m = 0.0762;           ///< FIA's coarse woody debris: >= 3 in at the small end
    double removal_mass_fraction = 0.05; ///< iLand: a piece goes when < 5 % of its mass is left
};

/// What part of a tree a piece is.
enum class PieceKind : std::uint8_t {
    stem = 0,       ///< the whole stem: a snag, then a log
    stump = 1,      ///< the stump left by a cut (standing, never falls)
    slash = 2,      ///< a top lying apart from its stem: the slash of a cut, a storm's broken top
    snapped = 3,    ///< the standing lower stem of a tree a storm broke (a snag that falls later)
    root_plate = 4, ///< the root plate of an uprooted tree, standing on edge (no wood mass)
};

/// One snag, log, stump or piece of slash. No padding: the checkpoint stores the rows as bytes.
struct DeadStem {
    double x_m = 0, y_m = 0, z_m = 0; ///< the piece's base (slash: its thick end)
    double dbh_m = 0;                 ///< the tree's at death
    double tree_height_m = 0;         ///< the tree's at death
    double length_m = 0;              ///< a snag's or stump's standing height, a log's length
    double azimuth_rad = 0;           ///< a log: direction base -> top, counterclockwise from east
    double mass0_kg = 0;              ///< the piece's dry mass at death
    double mass_kg = 0;               ///< dry mass left
    double offset_m = 0; ///< where along the tree's stem the piece starts (slash: the cut top)
    std::int64_t id = 0; ///< the tree's plant id
    std::int32_t year_died = 0, year_falls = 0, year_down = -1; ///< -1: standing
    std::uint16_t species = 0;
    std::uint8_t cause = 0;    ///< DeathCause
    std::uint8_t standing = 1; ///< 1 standing (snag, stump), 0 lying (log, slash)
    std::uint8_t piece = 0;    ///< PieceKind
    std::uint8_t spare[7] = {};
};
static_assert(sizeof(DeadStem) == 10 * 8 + 8 + 3 * 4 + 2 + 1 + 1 + 8, "DeadStem has padding");

/// The year's dead-wood fluxes, kg dry mass (the carbon budget's terms), and its events.
struct DeadWoodSums {
    double input_kg = 0, decay_kg = 0;
    double cut_kept_kg = 0; ///< the stumps and slash of cut trees (part of input_kg)
    double new_snags = 0, snags_fallen = 0, pieces_gone = 0;
};

/// An uprooted tree's root plate (docs/ecosystem.md s13): a disc 12 DBH across (at most 5 m) and
/// a quarter of that thick (0.3-1 m), the upper ends of the ranges the reference gathers
/// (deadwood.md s4: 10-20 DBH, capped at 3-5 m; 0.5-1 m thick; not a fitted relation). The pit
/// beside it is half the plate's thickness deep.
double root_plate_diameter_m(double dbh_m);
double root_plate_thickness_m(double dbh_m);

namespace deadwood {
/// An angle in [0, 2 pi), rad.
double wrap_azimuth(double a_rad);
/// Decay class 1 (sound) .. 5 from the share of the mass left: iLand's thresholds 0.9, 0.7, 0.4,
/// 0.2 (deadtree.cpp, decayClassThresholds).
int decay_class(double mass_fraction);
/// Share of a snag's top (the stem above a 10.16 cm (4 in) diameter) still standing in a class:
/// 1, 0.5, 0.2, 0.1, 0 (Domke et al. 2011, Carbon Balance Manage. 6:14, Table 2).
double top_retained(int decay_class);
/// A log's height above the ground over its diameter in a class: round to class 3, oval in 4,
/// mostly buried in 5 (the five-class descriptions; the figures are ours).
double log_collapse(int decay_class);
/// The stem's diameter at distance `s_m` from its base: the DBH up to 1.3 m, then a linear taper
/// to 0 at the tree's height.
double stem_diameter_m(double dbh_m, double tree_height_m, double s_m);
/// Where the stem's taper reaches 10.16 cm (4 in), the merchantable top (at least 1.3 m, at most
/// the tree's height), m.
double top_start_m(double dbh_m, double tree_height_m);
/// A snag's standing height in a class: its top (above the 10.16 cm diameter) lost with the class.
double snag_height_m(double dbh_m, double tree_height_m, int decay_class);
/// Years over which a cohort of snags of this diameter all fall (FVS-FFE, NI variant:
/// 1 / max(0.01, 0.064311 - 0.001679 D_in), divided by the species' multiplier).
double snag_fall_span_yr(const Species& s, double dbh_m);
/// Density of dead wood over sound wood in a decay class: 0.93, 0.79, 0.57, 0.52, 0.52 (Domke et
/// al. 2011, Table 2: the mean of quaking aspen's and Douglas-fir's reduction factors).
double density_reduction(int decay_class);
/// Share of a stem's volume below height z (the taper above: a cylinder to 1.3 m, then a cone).
double stem_volume_fraction_below(double tree_height_m, double z_m);
/// Volume of a piece, m3, as an inventory would find it from its mass: V = m / (rho DRF(class)),
/// at most the stem volume at death m0 / rho.
double volume_m3(const Species& s, const DeadStem& d);
/// Direction a stem falls, radians counterclockwise from east: toward the downhill azimuth
/// (+-45 degrees) with probability min(1, slope / 0.3), else any direction. Two draws of `rng`.
double fall_azimuth_rad(const RasterD& dem, double x_m, double y_m, Rng& rng);
} // namespace deadwood

/// The dead wood of a stand and its yearly dynamics.
class DeadWood {
public:
    DeadWood(const DeadWoodOptions& options, std::uint64_t seed);

    const DeadWoodOptions& options() const { return m_opt; }
    const std::vector<DeadStem>& pieces() const { return m_pieces; }
    const DeadWoodSums& sums() const { return m_sums; }
    void reset_sums() { m_sums = DeadWoodSums{}; }
    /// Dry mass of all pieces, kg.
    double stock_kg() const;

    /// Where the year's storm blows to (counterclockwise from east): wind-felled stems fall along
    /// it (+-22.5 degrees).
    void set_storm_azimuth(double to_azimuth_rad) { m_storm_to_az = to_azimuth_rad; }
    /// Takes the trees that died (alive 0, or `causes[k]` non-zero) into dead wood in `year` (the
    /// year being simulated, 1-based). The stem mass is the wood (coupled) or the allometric stem
    /// mass (light-only, `allometric_mass`). Plants below min_dbh_m, shrubs and objects are not
    /// taken. Each is a snag; its fall year is drawn now (one draw of the dead-wood stream).
    void take_dead(const Population& pop, const std::vector<Species>& species,
                   const std::vector<char>* causes, bool allometric_mass, int year);
    /// One year of the pieces that died before `year`: decay, snags that fall, pieces that go.
    void step_year(const std::vector<Species>& species, const RasterD& dem, int year);

    /// The checkpoint section: the stream, the pieces and the year's sums.
    void save(ArchiveWriter& a) const;
    void load(ArchiveReader& a);

private:
    void add(const Species& s, const Population& pop, std::size_t k, DeathCause cause,
             double mass_kg, int year);
    /// A cut tree: its stump and its top (slash) stay, the stem between leaves the stand.
    void add_cut(const Population& pop, std::size_t k, double mass_kg, int year);
    /// A wind-felled tree: uprooted (its stem lies downwind, its root plate stands on edge) or
    /// broken (the lower half of its mass stands as a snag, the top lies downwind).
    void add_wind(const Species& s, const Population& pop, std::size_t k, DeathCause cause,
                  double mass_kg, int year);
    void fall(DeadStem& d, const RasterD& dem, int year);
    /// The year a snag of this species and DBH that died in `year` falls: uniform over FFE's
    /// span after its death (one draw of the stream).
    std::int32_t fall_year(const Species& s, double dbh_m, int year);

    DeadWoodOptions m_opt;
    Rng m_rng;
    double m_storm_to_az = 0;
    std::vector<DeadStem> m_pieces;
    DeadWoodSums m_sums;
};

/// The dead wood of one moment summed for the yearly series (per hectare of `area_m2`).
struct DeadWoodMetrics {
    double snags_per_ha = 0, logs_per_ha = 0, stumps_per_ha = 0, root_plates_per_ha = 0;
    double snag_volume_m3_per_ha = 0, log_volume_m3_per_ha = 0, stump_volume_m3_per_ha = 0;
    std::array<double, 5> volume_by_class_m3_per_ha{};
    double stock_kg = 0;
};
DeadWoodMetrics deadwood_metrics(const DeadWood& dw, const std::vector<Species>& species,
                                 double area_m2);

} // namespace ecoterra::eco
