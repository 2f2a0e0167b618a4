#include "ecoterra/eco/population.hpp"

#include "ecoterra/error.hpp"

#include <cstring>

namespace ecoterra::eco {

void Population::clear() {
#define ECOTERRA_CLEAR(type, name) name.clear();
    ECOTERRA_PLANT_COLUMNS(ECOTERRA_CLEAR)
#undef ECOTERRA_CLEAR
}

void Population::reserve(std::size_t n) {
#define ECOTERRA_RESERVE(type, name) name.reserve(n);
    ECOTERRA_PLANT_COLUMNS(ECOTERRA_RESERVE)
#undef ECOTERRA_RESERVE
}

void Population::push(const Plant& p) {
#define ECOTERRA_PUSH(type, name) name.push_back(static_cast<type>(p.name));
    ECOTERRA_PLANT_COLUMNS(ECOTERRA_PUSH)
#undef ECOTERRA_PUSH
}

Plant Population::plant(std::size_t k) const {
    Plant p;
#define ECOTERRA_ROW(type, name) p.name = name[k];
    ECOTERRA_PLANT_COLUMNS(ECOTERRA_ROW)
#undef ECOTERRA_ROW
    return p;
}

namespace {
template <class T>
void keep_entries(std::vector<T>& v, const std::vector<char>& keep) {
    std::size_t out = 0;
    for (std::size_t k = 0; k < v.size(); ++k)
        if (keep[k]) v[out++] = v[k];
    v.resize(out);
}

template <class T>
void permute_entries(std::vector<T>& v, const std::vector<std::uint32_t>& order) {
    std::vector<T> out(v.size());
    for (std::size_t k = 0; k < v.size(); ++k) out[k] = v[order[k]];
    v.swap(out);
}

template <class T>
bool same_bytes(const std::vector<T>& a, const std::vector<T>& b) {
    return a.size() == b.size() &&
           (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}
} // namespace

void Population::keep_if(const std::vector<char>& keep) {
    if (keep.size() != size())
        throw Error("internal: keep_if mask length differs from the population");
#define ECOTERRA_KEEP(type, name) keep_entries(name, keep);
    ECOTERRA_PLANT_COLUMNS(ECOTERRA_KEEP)
#undef ECOTERRA_KEEP
}

void Population::permute(const std::vector<std::uint32_t>& order) {
    if (order.size() != size())
        throw Error("internal: permute order length differs from the population");
#define ECOTERRA_PERMUTE(type, name) permute_entries(name, order);
    ECOTERRA_PLANT_COLUMNS(ECOTERRA_PERMUTE)
#undef ECOTERRA_PERMUTE
}

bool Population::bitwise_equal(const Population& o) const {
    bool same = true;
#define ECOTERRA_SAME(type, name) same = same && same_bytes(name, o.name);
    ECOTERRA_PLANT_COLUMNS(ECOTERRA_SAME)
#undef ECOTERRA_SAME
    return same;
}

void Population::save(ArchiveWriter& a) const {
#define ECOTERRA_SAVE(type, name) a.put_vector(name);
    ECOTERRA_PLANT_COLUMNS(ECOTERRA_SAVE)
#undef ECOTERRA_SAVE
}

void Population::load(ArchiveReader& a) {
#define ECOTERRA_LOAD(type, name) name = a.get_vector<type>();
    ECOTERRA_PLANT_COLUMNS(ECOTERRA_LOAD)
#undef ECOTERRA_LOAD
    bool same_length = true;
#define ECOTERRA_LENGTH(type, name) same_length = same_length && name.size() == id.size();
    ECOTERRA_PLANT_COLUMNS(ECOTERRA_LENGTH)
#undef ECOTERRA_LENGTH
    if (!same_length) throw CheckpointError("plants section: the columns differ in length");
}

std::vector<Plant> rows(const Population& pop) {
    std::vector<Plant> out;
    out.reserve(pop.size());
    for (std::size_t k = 0; k < pop.size(); ++k) out.push_back(pop.plant(k));
    return out;
}

} // namespace ecoterra::eco
