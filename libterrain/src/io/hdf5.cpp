// HDF5 elevation rasters through the HDF5 C++ API.
#include "ecoterra/terrain/io/atomic_file.hpp"
#include "ecoterra/terrain/io/raster_io.hpp"

#include <H5Cpp.h>

#include <vector>

namespace ecoterra::terrain::io {

namespace {

constexpr int kChunkSide = 256;
constexpr int kDeflateLevel = 4;

void write_double_attr(H5::H5Object& obj, const char* name, double v) {
    H5::Attribute a = obj.createAttribute(name, H5::PredType::NATIVE_DOUBLE, H5::DataSpace());
    a.write(H5::PredType::NATIVE_DOUBLE, &v);
}

void write_string_attr(H5::H5Object& obj, const char* name, const std::string& v) {
    H5::StrType t(H5::PredType::C_S1, v.empty() ? 1 : v.size());
    H5::Attribute a = obj.createAttribute(name, t, H5::DataSpace());
    a.write(t, v.empty() ? std::string(" ") : v);
}

bool read_double_attr(const H5::H5Object& obj, const char* name, double& v) {
    if (!obj.attrExists(name)) return false;
    H5::Attribute a = obj.openAttribute(name);
    a.read(H5::PredType::NATIVE_DOUBLE, &v);
    return true;
}

std::string read_string_attr(const H5::H5Object& obj, const char* name) {
    if (!obj.attrExists(name)) return {};
    H5::Attribute a = obj.openAttribute(name);
    std::string s;
    a.read(a.getStrType(), s);
    return s;
}

} // namespace

RasterD read_hdf5(const std::filesystem::path& path, const std::string& dataset) {
    H5::Exception::dontPrint();
    const std::string where = path.string();
    if (!std::filesystem::exists(path)) throw IoError(where + ": no such file");
    try {
        if (!H5::H5File::isHdf5(where)) throw IoError(where + ": not an HDF5 file");
        H5::H5File f(where, H5F_ACC_RDONLY);
        if (!f.nameExists(dataset)) throw IoError(where + ": has no dataset " + dataset);
        H5::DataSet ds = f.openDataSet(dataset);
        H5::DataSpace sp = ds.getSpace();
        if (sp.getSimpleExtentNdims() != 2)
            throw IoError(where + ": dataset " + dataset + " must be 2-D [ny, nx]");
        hsize_t dims[2];
        sp.getSimpleExtentDims(dims);
        GridSpec g;
        g.ny = static_cast<int>(dims[0]);
        g.nx = static_cast<int>(dims[1]);
        if (!read_double_attr(ds, "cell_size_m", g.cell_size_m))
            throw IoError(where + ": dataset " + dataset + " lacks the attribute cell_size_m");
        read_double_attr(ds, "origin_x_m", g.origin_x_m);
        read_double_attr(ds, "origin_y_m", g.origin_y_m);
        g.validate(where + " " + dataset);
        const std::string order = read_string_attr(ds, "row_order");
        if (!order.empty() && order != "south_to_north" && order != "north_to_south")
            throw IoError(where +
                          ": attribute row_order must be south_to_north or "
                          "north_to_south, got '" +
                          order + "'");
        ensure_fits_in_memory(g.size(), 12.0, where);
        RasterD z(g, 0.0);
        ds.read(z.data(), H5::PredType::NATIVE_DOUBLE);
        if (order == "north_to_south") z.array() = z.array().colwise().reverse().eval();
        return z;
    } catch (const H5::Exception& e) {
        throw IoError(where + ": HDF5 error: " + e.getDetailMsg());
    }
}

void write_hdf5(const RasterD& z, const std::filesystem::path& path, const WriteOptions& opt) {
    H5::Exception::dontPrint();
    AtomicOutput out(path);
    try {
        H5::H5File f(out.temp_path().string(), H5F_ACC_TRUNC);
        hsize_t dims[2] = {static_cast<hsize_t>(z.ny()), static_cast<hsize_t>(z.nx())};
        H5::DataSpace space(2, dims);
        H5::DSetCreatPropList plist;
        hsize_t chunk[2] = {std::min<hsize_t>(kChunkSide, dims[0]),
                            std::min<hsize_t>(kChunkSide, dims[1])};
        plist.setChunk(2, chunk);
        plist.setShuffle();
        plist.setDeflate(kDeflateLevel);
        float nan = std::numeric_limits<float>::quiet_NaN();
        plist.setFillValue(H5::PredType::NATIVE_FLOAT, &nan);
        H5::DataSet ds = f.createDataSet("/elevation", H5::PredType::NATIVE_FLOAT, space, plist);
        std::vector<float> buf(static_cast<std::size_t>(z.size()));
        for (std::int64_t k = 0; k < z.size(); ++k) buf[k] = static_cast<float>(z.data()[k]);
        ds.write(buf.data(), H5::PredType::NATIVE_FLOAT);
        write_double_attr(ds, "cell_size_m", z.cell_size());
        write_double_attr(ds, "origin_x_m", z.grid().origin_x_m);
        write_double_attr(ds, "origin_y_m", z.grid().origin_y_m);
        write_string_attr(ds, "units", "m");
        write_string_attr(ds, "row_order", "south_to_north");
        write_string_attr(ds, "description",
                          "elevation above the datum at cell centres; NaN = NODATA");
        H5::Group prov = f.createGroup("/provenance");
        write_string_attr(prov, "json", opt.provenance.dump());
        f.close();
    } catch (const H5::Exception& e) {
        throw IoError(path.string() + ": HDF5 write failed: " + e.getDetailMsg());
    }
    out.commit();
}

} // namespace ecoterra::terrain::io
