// Forest management: operations, their reading and the trees they cut (management.hpp).
#include "ecoterra/eco/management.hpp"

#include "ecoterra/error.hpp"
#include "ecoterra/json_util.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

namespace ecoterra::eco {

using nlohmann::json;

namespace {
constexpr double kM2PerHa = 1e4;
/// The largest basal area an operation may name, m2/ha (old-growth redwood stands reach ~300).
constexpr double kMaxBasalArea = 500;

const std::vector<std::pair<std::string, CutKind>>& kinds() {
    static const std::vector<std::pair<std::string, CutKind>> k = {
        {"thin_from_below", CutKind::thin_from_below},
        {"thin_from_above", CutKind::thin_from_above},
        {"selection", CutKind::selection},
        {"clear_cut", CutKind::clear_cut}};
    return k;
}

double number_at(const json& o, const std::string& key, const std::string& where, double lo,
                 double hi) {
    return get_number(o, key, 0, where, lo, hi); // callers check that the key is there
}

ManagementOp read_op(const json& o, const std::string& where, int years) {
    if (!o.is_object()) throw InputError(where + " must be an object, got " + o.dump());
    require_known_keys(o,
                       {"type", "year", "when_basal_area_above_m2_per_ha",
                        "target_basal_area_m2_per_ha", "min_dbh_m"},
                       where);
    ManagementOp op;
    const std::string type = get_string(o, "type", "", where);
    const auto it = std::find_if(kinds().begin(), kinds().end(),
                                 [&](const auto& k) { return k.first == type; });
    if (it == kinds().end())
        throw InputError(where + ".type = '" + type +
                         "': give thin_from_below, thin_from_above, selection or clear_cut");
    op.kind = it->second;
    const bool has_year = o.contains("year"),
               has_when = o.contains("when_basal_area_above_m2_per_ha");
    if (has_year == has_when)
        throw InputError(where + ": give either year or when_basal_area_above_m2_per_ha");
    if (has_year) {
        const double y = number_at(o, "year", where, 1, years);
        if (y != std::floor(y))
            throw InputError(where + ".year = " + format_number(y) + " is not a whole year");
        op.year = static_cast<int>(y);
    } else {
        op.when_basal_area_above_m2_per_ha =
            number_at(o, "when_basal_area_above_m2_per_ha", where, 0, kMaxBasalArea);
    }
    const bool thin = op.kind == CutKind::thin_from_below || op.kind == CutKind::thin_from_above;
    if (thin != o.contains("target_basal_area_m2_per_ha"))
        throw InputError(where + ": target_basal_area_m2_per_ha " +
                         (thin ? "is needed by a thinning" : "belongs to thinnings only"));
    if (thin) {
        op.target_basal_area_m2_per_ha =
            number_at(o, "target_basal_area_m2_per_ha", where, 0, kMaxBasalArea);
        if (op.when_basal_area_above_m2_per_ha &&
            *op.when_basal_area_above_m2_per_ha <= op.target_basal_area_m2_per_ha)
            throw InputError(where + ": when_basal_area_above_m2_per_ha = " +
                             format_number(*op.when_basal_area_above_m2_per_ha) +
                             " must exceed target_basal_area_m2_per_ha = " +
                             format_number(op.target_basal_area_m2_per_ha));
    }
    if ((op.kind == CutKind::selection) != o.contains("min_dbh_m"))
        throw InputError(where + ": min_dbh_m " +
                         (op.kind == CutKind::selection ? "is needed by a selection cut"
                                                        : "belongs to selection cuts only"));
    if (op.kind == CutKind::selection) op.min_dbh_m = number_at(o, "min_dbh_m", where, 0.001, 10);
    return op;
}

double basal_m2(double dbh) {
    return std::numbers::pi * dbh * dbh / 4;
}

} // namespace

const char* cut_kind_name(CutKind k) {
    for (const auto& [name, kind] : kinds())
        if (kind == k) return name.c_str();
    return "unknown";
}

ManagementOptions read_management(const json& j, int years) {
    ManagementOptions m;
    const std::string where = "vegetation.management";
    if (!j.is_object()) throw InputError(where + " must be an object, got " + j.dump());
    require_known_keys(j, {"stump_height_m", "operations"}, where);
    if (j.contains("stump_height_m"))
        m.stump_height_m = number_at(j, "stump_height_m", where, 0, 2);
    if (!j.contains("operations")) return m;
    const json& ops = j.at("operations");
    if (!ops.is_array())
        throw InputError(where + ".operations must be an array, got " + ops.dump());
    for (std::size_t k = 0; k < ops.size(); ++k)
        m.operations.push_back(
            read_op(ops[k], where + ".operations[" + std::to_string(k) + "]", years));
    return m;
}

json to_json(const ManagementOptions& m) {
    json ops = json::array();
    for (const auto& op : m.operations) {
        json o = {{"type", cut_kind_name(op.kind)}};
        if (op.year > 0) o["year"] = op.year;
        if (op.when_basal_area_above_m2_per_ha)
            o["when_basal_area_above_m2_per_ha"] = *op.when_basal_area_above_m2_per_ha;
        if (op.kind == CutKind::thin_from_below || op.kind == CutKind::thin_from_above)
            o["target_basal_area_m2_per_ha"] = op.target_basal_area_m2_per_ha;
        if (op.kind == CutKind::selection) o["min_dbh_m"] = op.min_dbh_m;
        ops.push_back(std::move(o));
    }
    return {{"stump_height_m", m.stump_height_m}, {"operations", std::move(ops)}};
}

std::int64_t mark_harvest(const ManagementOptions& m, const Population& pop,
                          const std::vector<Species>& species, double area_m2, int year,
                          std::vector<char>& dead, char mark) {
    std::int64_t cut = 0;
    for (const auto& op : m.operations) {
        // The standing trees that reach breast height (saplings are left: advance regeneration)
        // and their basal area, after the cuts before this one.
        std::vector<std::size_t> trees;
        double ba = 0;
        for (std::size_t k = 0; k < pop.size(); ++k)
            if (!dead[k] && pop.alive[k] && pop.dbh_m[k] > 0 &&
                species[pop.species[k]].life_form == LifeForm::tree) {
                trees.push_back(k);
                ba += basal_m2(pop.dbh_m[k]);
            }
        ba *= kM2PerHa / area_m2;
        const bool acts = op.year > 0 ? op.year == year : ba > *op.when_basal_area_above_m2_per_ha;
        if (!acts) continue;
        auto cut_one = [&](std::size_t k) {
            dead[k] = mark;
            ++cut;
        };
        switch (op.kind) {
        case CutKind::clear_cut:
            for (const std::size_t k : trees) cut_one(k);
            break;
        case CutKind::selection:
            for (const std::size_t k : trees)
                if (pop.dbh_m[k] >= op.min_dbh_m) cut_one(k);
            break;
        case CutKind::thin_from_below:
        case CutKind::thin_from_above: {
            const bool below = op.kind == CutKind::thin_from_below;
            std::sort(trees.begin(), trees.end(), [&](std::size_t a, std::size_t b) {
                if (pop.dbh_m[a] != pop.dbh_m[b])
                    return below ? pop.dbh_m[a] < pop.dbh_m[b] : pop.dbh_m[a] > pop.dbh_m[b];
                return pop.id[a] < pop.id[b];
            });
            for (const std::size_t k : trees) {
                if (ba <= op.target_basal_area_m2_per_ha) break;
                ba -= basal_m2(pop.dbh_m[k]) * kM2PerHa / area_m2;
                cut_one(k);
            }
            break;
        }
        }
    }
    return cut;
}

} // namespace ecoterra::eco
