#include "ecoterra/hydro/runoff.hpp"

#include "ecoterra/data_dir.hpp"
#include "ecoterra/io/atomic_file.hpp"
#include "ecoterra/json_util.hpp"

#include <cmath>
#include <cstdlib>

namespace ecoterra::hydro {

namespace {
/// TR-55 Table 2-2 (A/B/C/D): fallow bare soil (confirmed in GRASS r.cn) and woods, fair.
constexpr double kCnBare[4] = {77, 86, 91, 94};
constexpr double kCnWoods[4] = {36, 60, 73, 79};
} // namespace

RunoffTable RunoffTable::standard() {
    return load(data_dir() / "hydro" / "runoff_coefficients.json");
}

RunoffTable RunoffTable::load(const std::filesystem::path& path) {
    const std::string where = path.string();
    const auto j = parse_json(io::read_text(path), where);
    RunoffTable t;
    try {
        t.m_source = j.value("source", "");
        const auto& veg = j.at("vegetation_classes");
        if (veg.size() != 3) throw InputError(where + ": vegetation_classes must have 3 entries");
        std::array<std::string, 3> veg_names;
        for (int v = 0; v < 3; ++v) {
            veg_names[v] = veg[v].at("name").get<std::string>();
            t.m_veg_max[v] = veg[v].at("max_density").get<double>();
        }
        const auto& sl = j.at("slope_class_upper_pct");
        if (sl.size() != 3) throw InputError(where + ": slope_class_upper_pct must have 3 entries");
        for (int s = 0; s < 3; ++s) t.m_slope_max[s] = sl[s].get<double>() / 100.0;
        const auto& order = j.at("texture_group_order");
        t.m_group.fill(-1);
        for (int g = 0; g < 3; ++g)
            for (const auto& name : j.at("texture_groups").at(order[g].get<std::string>())) {
                const auto tex = parse_texture(name.get<std::string>());
                if (!tex)
                    throw InputError(where + ": texture_groups: unknown texture '" +
                                     name.get<std::string>() + "'");
                t.m_group[static_cast<int>(*tex)] = g;
            }
        for (int k = 0; k < kTextureCount; ++k)
            if (t.m_group[k] < 0)
                throw InputError(where + ": texture_groups does not place '" +
                                 texture_name(static_cast<Texture>(k)) + "'");
        for (int v = 0; v < 3; ++v) {
            const auto& rows = j.at("coefficients").at(veg_names[v]);
            for (int s = 0; s < 3; ++s)
                for (int g = 0; g < 3; ++g) {
                    const double c = rows.at(s).at(g).get<double>();
                    if (!(c >= 0 && c <= 1))
                        throw InputError(where + ": coefficients." + veg_names[v] +
                                         " must lie in [0, 1]");
                    t.m_c[v][s][g] = c;
                }
        }
    } catch (const nlohmann::json::exception& e) {
        throw InputError(where + ": malformed runoff table: " + e.what());
    }
    return t;
}

double RunoffTable::coefficient(double density, double slope, Texture tex) const {
    int v = 0;
    while (v < 2 && density > m_veg_max[v]) ++v;
    // The table's vegetation order is low cover first; its rows are stored the same way.
    int s = 0;
    while (s < 2 && slope > m_slope_max[s]) ++s;
    return m_c[v][s][m_group[static_cast<int>(tex)]];
}

double scs_runoff_mm(double p, double cn) {
    const double s = 25400.0 / cn - 254.0;
    const double ia = 0.2 * s;
    return p > ia ? (p - ia) * (p - ia) / (p - ia + s) : 0.0;
}
int hydrologic_soil_group(Texture t) {
    switch (t) {
    case Texture::sand:
    case Texture::loamy_sand:
    case Texture::sandy_loam:
        return 0;
    case Texture::loam:
    case Texture::silt_loam:
    case Texture::silt:
        return 1;
    case Texture::sandy_clay_loam:
        return 2;
    default:
        return 3;
    }
}

double curve_number(double density, Texture t) {
    const int g = hydrologic_soil_group(t);
    const double d = std::clamp(density, 0.0, 1.0);
    return kCnBare[g] + (kCnWoods[g] - kCnBare[g]) * d;
}

} // namespace ecoterra::hydro
