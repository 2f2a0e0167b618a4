#include "ecoterra/eco/stand_metrics.hpp"

#include "ecoterra/error.hpp"

#include <cmath>
#include <numbers>

namespace ecoterra::eco {

namespace {}

StandMetrics stand_metrics(const std::vector<double>& dbh, double area_m2, double width_cm) {
    StandMetrics m;
    m.class_width_cm = width_cm;
    m.area_ha = area_m2 / kM2PerHa;
    double sum = 0, sum2 = 0;
    for (const double d : dbh) {
        if (!(d > 0)) continue;
        ++m.stems;
        sum += d;
        sum2 += d * d;
        const auto cls = static_cast<std::size_t>(std::floor(d * 100.0 / width_cm));
        if (m.histogram.size() <= cls) m.histogram.resize(cls + 1, 0);
        ++m.histogram[cls];
    }
    if (m.stems == 0 || !(m.area_ha > 0)) return m;
    const double n = static_cast<double>(m.stems);
    m.basal_area_m2_per_ha = 0.25 * std::numbers::pi * sum2 / m.area_ha;
    m.stems_per_ha = n / m.area_ha;
    m.mean_dbh_m = sum / n;
    m.quadratic_mean_dbh_m = std::sqrt(sum2 / n);
    m.sdi_per_ha =
        m.stems_per_ha *
        std::pow(m.quadratic_mean_dbh_m * 100.0 / kReinekeReferenceDbhCm, kReinekeExponent);
    // Log-linear least squares over non-empty classes.
    double sx = 0, sy = 0, sxx = 0, sxy = 0, syy = 0;
    int k = 0;
    for (std::size_t i = 0; i < m.histogram.size(); ++i) {
        if (m.histogram[i] == 0) continue;
        const double x = (static_cast<double>(i) + 0.5) * width_cm;
        const double y = std::log(static_cast<double>(m.histogram[i]));
        sx += x, sy += y, sxx += x * x, sxy += x * y, syy += y * y;
        ++k;
    }
    if (k >= 3) {
        const double vx = sxx - sx * sx / k, vy = syy - sy * sy / k, cxy = sxy - sx * sy / k;
        const double slope = cxy / vx;
        m.rate_per_cm = -slope;
        m.intercept = (sy - slope * sx) / k;
        m.q_per_class = std::exp(m.rate_per_cm * width_cm);
        m.r2 = vy > 0 ? cxy * cxy / (vx * vy) : 1.0;
        m.fit_valid = true;
    }
    return m;
}

std::vector<StandMetrics> stand_metrics_by_species(const std::vector<double>& dbh_m,
                                                   const std::vector<int>& species,
                                                   std::size_t n_species, double area_m2,
                                                   double class_width_cm) {
    if (dbh_m.size() != species.size())
        throw InputError("stand metrics by species: " + std::to_string(dbh_m.size()) +
                         " diameters but " + std::to_string(species.size()) + " species indices");
    std::vector<std::vector<double>> split(n_species);
    for (std::size_t k = 0; k < dbh_m.size(); ++k) {
        if (species[k] < 0 || static_cast<std::size_t>(species[k]) >= n_species)
            throw InputError("stand metrics by species: stem " + std::to_string(k) +
                             " has species index " + std::to_string(species[k]) + ", not in [0, " +
                             std::to_string(n_species) + ")");
        split[static_cast<std::size_t>(species[k])].push_back(dbh_m[k]);
    }
    std::vector<StandMetrics> out;
    for (const auto& d : split) out.push_back(stand_metrics(d, area_m2, class_width_cm));
    return out;
}

namespace {

/// The DBH classes with their edges (cm), the stems in each and the same per ha.
nlohmann::json dbh_histogram_json(const StandMetrics& m) {
    std::vector<double> edges, per_ha;
    for (std::size_t k = 0; k <= m.histogram.size(); ++k)
        edges.push_back(static_cast<double>(k) * m.class_width_cm);
    for (const auto c : m.histogram)
        per_ha.push_back(m.area_ha > 0 ? static_cast<double>(c) / m.area_ha : 0.0);
    return {{"class_width_cm", m.class_width_cm},
            {"edges_cm", edges},
            {"counts", m.histogram},
            {"counts_unit", "stems in the class over the whole area (area_ha)"},
            {"stems_per_ha", per_ha},
            {"classes", "class k holds edges_cm[k] <= DBH < edges_cm[k + 1]"}};
}

} // namespace

nlohmann::json to_json(const StandMetrics& m) {
    nlohmann::json fit = nullptr;
    if (m.fit_valid)
        fit = {{"rate_per_cm", m.rate_per_cm},
               {"q_per_5cm", std::exp(m.rate_per_cm * 5.0)},
               {"r2", m.r2},
               {"intercept_ln_count", m.intercept}};
    return {{"dbh_histogram", dbh_histogram_json(m)}, {"exponential_fit", fit}};
}

nlohmann::json to_json(const UndergrowthMetrics& m, const std::vector<std::string>& names) {
    nlohmann::json cover = nlohmann::json::array();
    for (const auto& c : m.ground_cover_by_species)
        cover.push_back({{"species", c.species < static_cast<int>(names.size())
                                         ? names[static_cast<std::size_t>(c.species)]
                                         : std::to_string(c.species)},
                         {"cover_fraction", c.fraction}});
    return {{"shrubs_per_ha", m.shrubs_per_ha},
            {"shrub_crown_cover_fraction", m.shrub_crown_cover_fraction},
            {"shrub_mean_height_m", m.shrub_mean_height_m},
            {"objects_per_ha", m.objects_per_ha},
            {"ground_cover_fraction", m.ground_cover_fraction},
            {"ground_cover_by_species", cover}};
}

void UndergrowthCounter::add(LifeForm form, double crown_radius_m, double height_m) {
    if (form == LifeForm::shrub) {
        m_shrubs += 1;
        m_crown_m2 += std::numbers::pi * crown_radius_m * crown_radius_m;
        m_height_m += height_m;
    } else if (form == LifeForm::object) {
        m_objects += 1;
    }
}

UndergrowthMetrics UndergrowthCounter::metrics(double area_m2) const {
    UndergrowthMetrics u;
    u.area_ha = area_m2 / kM2PerHa;
    u.shrubs_per_ha = m_shrubs / u.area_ha;
    u.shrub_crown_cover_fraction = m_crown_m2 / area_m2;
    u.shrub_mean_height_m = m_shrubs > 0 ? m_height_m / m_shrubs : 0.0;
    u.objects_per_ha = m_objects / u.area_ha;
    return u;
}

} // namespace ecoterra::eco
