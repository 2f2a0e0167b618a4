#include "ecoterra/terrain/io/hdf5_writer.hpp"

#include <H5Cpp.h>

namespace ecoterra::terrain::io {

namespace {
constexpr hsize_t kChunk = 256;
constexpr int kDeflate = 4;

void string_attr(H5::H5Object& obj, const std::string& name, const std::string& v) {
    const std::string value = v.empty() ? std::string(" ") : v;
    H5::StrType t(H5::PredType::C_S1, value.size());
    if (obj.attrExists(name)) obj.removeAttr(name);
    obj.createAttribute(name, t, H5::DataSpace()).write(t, value);
}
void double_attr(H5::H5Object& obj, const std::string& name, double v) {
    if (obj.attrExists(name)) obj.removeAttr(name);
    obj.createAttribute(name, H5::PredType::NATIVE_DOUBLE, H5::DataSpace())
        .write(H5::PredType::NATIVE_DOUBLE, &v);
}
} // namespace

struct Hdf5Writer::Impl {
    H5::H5File file;
    std::string where;

    /// Creates the groups above `path`.
    void ensure_parents(const std::string& path) {
        std::size_t pos = 1;
        while ((pos = path.find('/', pos)) != std::string::npos) {
            const std::string g = path.substr(0, pos);
            if (!file.nameExists(g)) file.createGroup(g);
            ++pos;
        }
    }

    /// Calls f on the dataset or group at `object`, creating the group if it does not exist.
    template <class F>
    void on_object(const std::string& object, F&& f) {
        if (object != "/" && !file.nameExists(object)) ensure_parents(object + "/");
        if (object != "/" && file.childObjType(object) == H5O_TYPE_DATASET) {
            H5::DataSet ds = file.openDataSet(object);
            f(ds);
        } else {
            H5::Group g = file.openGroup(object);
            f(g);
        }
    }

    template <class T>
    void raster(const std::string& path, const Raster<T>& r, const H5::PredType& mem,
                const H5::PredType& disk, const std::string& units, const std::string& desc) {
        ensure_parents(path);
        hsize_t dims[2] = {static_cast<hsize_t>(r.ny()), static_cast<hsize_t>(r.nx())};
        H5::DataSpace space(2, dims);
        H5::DSetCreatPropList plist;
        hsize_t chunk[2] = {std::min(kChunk, dims[0]), std::min(kChunk, dims[1])};
        plist.setChunk(2, chunk);
        plist.setShuffle();
        plist.setDeflate(kDeflate);
        H5::DataSet ds = file.createDataSet(path, disk, space, plist);
        ds.write(r.data(), mem);
        string_attr(ds, "units", units);
        string_attr(ds, "description", desc);
        string_attr(ds, "row_order", "south_to_north");
        double_attr(ds, "cell_size_m", r.cell_size());
        double_attr(ds, "origin_x_m", r.grid().origin_x_m);
        double_attr(ds, "origin_y_m", r.grid().origin_y_m);
    }

    template <class T>
    void series(const std::string& path, const std::vector<T>& v, const H5::PredType& type,
                const std::string& units, const std::string& desc) {
        ensure_parents(path);
        hsize_t dims[1] = {static_cast<hsize_t>(v.size())};
        H5::DataSpace space(1, dims);
        H5::DSetCreatPropList plist;
        if (!v.empty()) {
            hsize_t chunk[1] = {std::min<hsize_t>(4096, dims[0])};
            plist.setChunk(1, chunk);
            plist.setDeflate(kDeflate);
        }
        H5::DataSet ds = file.createDataSet(path, type, space, plist);
        if (!v.empty()) ds.write(v.data(), type);
        string_attr(ds, "units", units);
        string_attr(ds, "description", desc);
    }
};

Hdf5Writer::Hdf5Writer(const std::filesystem::path& target) : m_out(target) {
    H5::Exception::dontPrint();
    m_impl = std::make_unique<Impl>();
    m_impl->where = target.string();
    try {
        m_impl->file = H5::H5File(m_out.temp_path().string(), H5F_ACC_TRUNC);
    } catch (const H5::Exception& e) {
        throw IoError(m_impl->where + ": cannot create HDF5 file: " + e.getDetailMsg());
    }
}

Hdf5Writer::~Hdf5Writer() = default;

#define ECOTERRA_H5_GUARD(expr)                                                                    \
    try {                                                                                          \
        expr;                                                                                      \
    } catch (const H5::Exception& e) {                                                             \
        throw IoError(m_impl->where + ": HDF5 write of " + path + " failed: " + e.getDetailMsg()); \
    }

void Hdf5Writer::raster(const std::string& path, const RasterD& r, const std::string& units,
                        const std::string& d) {
    Raster<float> f(r.grid());
    for (std::int64_t k = 0; k < r.size(); ++k) f.data()[k] = static_cast<float>(r.data()[k]);
    raster(path, f, units, d);
}
void Hdf5Writer::raster(const std::string& path, const Raster<float>& r, const std::string& units,
                        const std::string& d) {
    ECOTERRA_H5_GUARD(
        m_impl->raster(path, r, H5::PredType::NATIVE_FLOAT, H5::PredType::NATIVE_FLOAT, units, d))
}
void Hdf5Writer::raster(const std::string& path, const Raster<std::int32_t>& r,
                        const std::string& units, const std::string& d) {
    ECOTERRA_H5_GUARD(
        m_impl->raster(path, r, H5::PredType::NATIVE_INT32, H5::PredType::NATIVE_INT32, units, d))
}
void Hdf5Writer::raster(const std::string& path, const Raster<std::uint8_t>& r,
                        const std::string& units, const std::string& d) {
    ECOTERRA_H5_GUARD(
        m_impl->raster(path, r, H5::PredType::NATIVE_UINT8, H5::PredType::NATIVE_UINT8, units, d))
}
void Hdf5Writer::series(const std::string& path, const std::vector<double>& v,
                        const std::string& units, const std::string& d) {
    ECOTERRA_H5_GUARD(m_impl->series(path, v, H5::PredType::NATIVE_DOUBLE, units, d))
}
void Hdf5Writer::series(const std::string& path, const std::vector<std::int32_t>& v,
                        const std::string& units, const std::string& d) {
    ECOTERRA_H5_GUARD(m_impl->series(path, v, H5::PredType::NATIVE_INT32, units, d))
}

void Hdf5Writer::series(const std::string& path, const std::vector<std::int64_t>& v,
                        const std::string& units, const std::string& d) {
    ECOTERRA_H5_GUARD(m_impl->series(path, v, H5::PredType::NATIVE_INT64, units, d))
}
void Hdf5Writer::series(const std::string& path, const std::vector<std::uint8_t>& v,
                        const std::string& units, const std::string& d) {
    ECOTERRA_H5_GUARD(m_impl->series(path, v, H5::PredType::NATIVE_UINT8, units, d))
}

void Hdf5Writer::external_link(const std::string& path, const std::string& file,
                               const std::string& object) {
    ECOTERRA_H5_GUARD(m_impl->ensure_parents(path));
    if (H5Lcreate_external(file.c_str(), object.c_str(), m_impl->file.getId(), path.c_str(),
                           H5P_DEFAULT, H5P_DEFAULT) < 0)
        throw IoError(m_impl->where + ": cannot create the external link " + path + " -> " + file +
                      ":" + object);
}

void Hdf5Writer::attribute(const std::string& object, const std::string& name,
                           const std::string& value) {
    const std::string& path = object;
    ECOTERRA_H5_GUARD(
        m_impl->on_object(object, [&](H5::H5Object& o) { string_attr(o, name, value); }))
}

void Hdf5Writer::attribute(const std::string& object, const std::string& name, double value) {
    const std::string& path = object;
    ECOTERRA_H5_GUARD(
        m_impl->on_object(object, [&](H5::H5Object& o) { double_attr(o, name, value); }))
}

void Hdf5Writer::commit() {
    try {
        m_impl->file.close();
    } catch (const H5::Exception& e) {
        throw IoError(m_impl->where + ": HDF5 close failed: " + e.getDetailMsg());
    }
    m_out.commit();
}

} // namespace ecoterra::terrain::io
