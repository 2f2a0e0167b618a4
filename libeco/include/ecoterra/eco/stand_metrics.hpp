#pragma once
// Stand metrics (forest mensuration).
//   basal area        BA = sum(pi D^2 / 4) / area                 m2/ha (x 4.356 = ft2/acre)
//   quadratic mean D  Dq = sqrt(mean(D^2))
//   Reineke SDI       SDI = N (Dq / 25.4 cm)^1.605                per ha (Reineke 1933)
//   reverse-J fit     ln N_i = ln k0 - k1 d_i over 5 cm classes with N_i > 0 (least squares);
//                     q = exp(5 k1) per 5 cm class (de Liocourt; Meyer 1952), R2 of the log fit.
// Only stems that reached breast height (D > 0) count.
#include "ecoterra/eco/species.hpp"
#include "ecoterra/units.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace ecoterra::eco {

inline constexpr double kReinekeExponent = 1.605;
inline constexpr double kReinekeReferenceDbhCm = 25.4;

struct StandMetrics {
    double area_ha = 0;
    double basal_area_m2_per_ha = 0, stems_per_ha = 0;
    double mean_dbh_m = 0, quadratic_mean_dbh_m = 0;
    double sdi_per_ha = 0;
    double class_width_cm = 5.0;
    std::vector<std::int64_t> histogram; ///< counts per class [i w, (i+1) w) cm
    double rate_per_cm = 0, q_per_class = 0, r2 = 0, intercept = 0;
    bool fit_valid = false; ///< at least 3 non-empty classes
    std::int64_t stems = 0;
};

StandMetrics stand_metrics(const std::vector<double>& dbh_m, double area_m2,
                           double class_width_cm = 5.0);
/// The metrics of each species alone: species[k] is the species index (0 .. n_species-1) of the
/// stem with dbh_m[k]; throws InputError when the lists differ in length or an index is out of
/// range.
std::vector<StandMetrics> stand_metrics_by_species(const std::vector<double>& dbh_m,
                                                   const std::vector<int>& species,
                                                   std::size_t n_species, double area_m2,
                                                   double class_width_cm = 5.0);
/// The details of the metrics: the diameter histogram and the exponential fit. The figures are the
/// stand analysis's metrics (analyses::stand_json writes both).
nlohmann::json to_json(const StandMetrics& m);

/// What grows beside the trees: shrubs (individuals, measured at the ground), objects and the
/// ground layer of grasses and herbs (cover fractions of the ground).
struct UndergrowthMetrics {
    double area_ha = 0;
    double shrubs_per_ha = 0;
    double shrub_crown_cover_fraction = 0; ///< sum of the shrubs' crown areas over the area
    double shrub_mean_height_m = 0;
    double objects_per_ha = 0;
    double ground_cover_fraction = 0; ///< mean ground-layer cover over the area, 0..1
    struct Cover {
        int species = 0;     ///< index in the run's species
        double fraction = 0; ///< mean cover over the area, 0..1
    };
    std::vector<Cover> ground_cover_by_species;
};
/// `names` are the run's species names (for the JSON).
nlohmann::json to_json(const UndergrowthMetrics& m, const std::vector<std::string>& names);

/// The shrub and object figures of UndergrowthMetrics over the plants of a stand: add() each
/// plant, then metrics(area) (the caller adds the ground layer's cover).
class UndergrowthCounter {
public:
    void add(LifeForm form, double crown_radius_m, double height_m);
    UndergrowthMetrics metrics(double area_m2) const;

private:
    double m_shrubs = 0, m_crown_m2 = 0, m_height_m = 0, m_objects = 0;
};

} // namespace ecoterra::eco
