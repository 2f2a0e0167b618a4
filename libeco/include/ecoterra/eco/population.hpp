#pragma once
// The plants as a population in structure-of-arrays form: one column per attribute, a plant is an
// index. The process kernels (processes.hpp) read and write whole columns; a Plant (plant.hpp) is
// one row, for the places that build or report a single plant (recruits, snapshots, tests).
//
// The columns are listed once, in ECOTERRA_PLANT_COLUMNS; adding an attribute there adds it to the
// row conversions, the compaction and the checkpoint section (whose version then goes up).
#include "ecoterra/archive.hpp"
#include "ecoterra/eco/plant.hpp"

#include <cstdint>
#include <vector>

namespace ecoterra::eco {

// clang-format off
/// X(type, name): every column of the population, named as the Plant member it mirrors.
#define ECOTERRA_PLANT_COLUMNS(X)                                                                  \
    X(std::int64_t, id)                                                                            \
    X(double, x_m) X(double, y_m) X(double, z_m)                                                   \
    X(double, dbh_m) X(double, height_m) X(double, crown_radius_m)                                 \
    X(double, age_yr) X(double, reserve_kg) X(double, wood_kg)                                     \
    X(double, leaf_area_m2) X(double, shade_fraction) X(double, soil_factor)                       \
    X(double, growth_sum) X(double, growth_days)                                                   \
    X(double, mass_at_year_start_kg) X(double, turnover_kg) X(double, growth_efficiency)           \
    X(std::uint16_t, species) X(std::uint8_t, alive)
// clang-format on

struct Population {
#define ECOTERRA_DECLARE_COLUMN(type, name) std::vector<type> name;
    ECOTERRA_PLANT_COLUMNS(ECOTERRA_DECLARE_COLUMN)
#undef ECOTERRA_DECLARE_COLUMN

    std::size_t size() const {
        return id.size();
    }
    bool empty() const {
        return id.empty();
    }
    void clear();
    void reserve(std::size_t n);
    /// Appends one plant (a row) at the end.
    void push(const Plant& p);
    /// Plant k as a row.
    Plant plant(std::size_t k) const;
    /// Keeps the plants whose `keep` entry is non-zero, in their order.
    void keep_if(const std::vector<char>& keep);
    /// Reorders the plants: row k becomes the former row order[k] (order is a permutation).
    void permute(const std::vector<std::uint32_t>& order);
    /// True when every column holds the same bytes (the resume tests' comparison).
    bool bitwise_equal(const Population& o) const;

    /// The checkpoint section: every column in the order of ECOTERRA_PLANT_COLUMNS.
    void save(ArchiveWriter& a) const;
    /// Reads a section save() wrote; throws CheckpointError when the columns differ in length.
    void load(ArchiveReader& a);
};

/// The rows of a population, in order.
std::vector<Plant> rows(const Population& pop);

} // namespace ecoterra::eco
