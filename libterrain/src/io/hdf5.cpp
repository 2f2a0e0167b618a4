// HDF5 elevation rasters through the HDF5 C++ API.
#include "ecoterra/io/hdf5_writer.hpp"
#include "ecoterra/terrain/io/raster_io.hpp"

#include <H5Cpp.h>

#include <vector>

namespace ecoterra::terrain::io {

namespace {

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

namespace {
/// True when every part of the absolute `path` exists (H5Lexists fails, rather than answer
/// false, when a part before the last is missing).
bool path_exists(const H5::H5File& f, const std::string& path) {
    std::size_t at = 0;
    while ((at = path.find('/', at + 1)) != std::string::npos)
        if (!f.nameExists(path.substr(0, at))) return false;
    return f.nameExists(path);
}

/// What an HDF5 type class holds, for messages.
std::string type_class_name(H5T_class_t c) {
    switch (c) {
    case H5T_STRING:
        return "strings";
    case H5T_COMPOUND:
        return "compound records (a complex number is one)";
    case H5T_ARRAY:
        return "arrays per element";
    case H5T_ENUM:
        return "enumerated values";
    case H5T_REFERENCE:
        return "references";
    case H5T_OPAQUE:
        return "opaque bytes";
    case H5T_BITFIELD:
        return "bit fields";
    case H5T_VLEN:
        return "variable-length sequences";
    default:
        return "values of HDF5 type class " + std::to_string(static_cast<int>(c));
    }
}
} // namespace

RasterD read_hdf5(const std::filesystem::path& path, const std::string& dataset) {
    H5::Exception::dontPrint();
    const std::string where = path.string();
    if (!std::filesystem::exists(path)) throw InputError(where + ": no such file");
    std::string name = dataset;
    try {
        if (!H5::H5File::isHdf5(where)) throw InputError(where + ": not an HDF5 file");
        H5::H5File f(where, H5F_ACC_RDONLY);
        // A run file of ecoterra (hydrology or ecosystem) keeps its terrain at /terrain/elevation:
        // every raster command takes it where it asks for a DEM.
        name = dataset == "/elevation" && !f.nameExists(dataset) && f.nameExists("/terrain") &&
                       f.openGroup("/terrain").nameExists("elevation")
                   ? kRunTerrainDataset
                   : dataset;
        if (!path_exists(f, name))
            throw InputError(where + ": has no dataset " + dataset +
                             (dataset == "/elevation"
                                  ? " (nor /terrain/elevation, the terrain of a run file)"
                                  : ""));
        H5O_info_t info{};
        if (H5Oget_info_by_name(f.getId(), name.c_str(), &info, H5P_DEFAULT) < 0 ||
            info.type != H5O_TYPE_DATASET)
            throw InputError(where + ": " + name + " is " +
                             (info.type == H5O_TYPE_GROUP ? "a group" : "not a dataset") +
                             ", not a raster dataset (name a 2-D dataset, e.g. " + where +
                             ":/terrain/elevation; h5ls -r lists them)");
        H5::DataSet ds = f.openDataSet(name);
        const H5T_class_t type = ds.getTypeClass();
        if (type != H5T_INTEGER && type != H5T_FLOAT)
            throw InputError(where + ": dataset " + name + " holds " + type_class_name(type) +
                             ", not numbers; a raster is integers or floats");
        H5::DataSpace sp = ds.getSpace();
        if (sp.getSimpleExtentNdims() != 2)
            throw InputError(where + ": dataset " + name + " must be 2-D [ny, nx]");
        hsize_t dims[2];
        sp.getSimpleExtentDims(dims);
        constexpr hsize_t kMaxSide = 2147483647;
        if (dims[0] > kMaxSide || dims[1] > kMaxSide)
            throw InputError(where + ": dataset " + name + " has " + std::to_string(dims[0]) +
                             " x " + std::to_string(dims[1]) + " cells, more than a grid can hold");
        GridSpec g;
        g.ny = static_cast<int>(dims[0]);
        g.nx = static_cast<int>(dims[1]);
        if (!read_double_attr(ds, "cell_size_m", g.cell_size_m))
            throw InputError(where + ": dataset " + name + " lacks the attribute cell_size_m");
        read_double_attr(ds, "origin_x_m", g.origin_x_m);
        read_double_attr(ds, "origin_y_m", g.origin_y_m);
        g.validate(where + " " + name);
        const std::string order = read_string_attr(ds, "row_order");
        if (!order.empty() && order != "south_to_north" && order != "north_to_south")
            throw InputError(where +
                             ": attribute row_order must be south_to_north or "
                             "north_to_south, got '" +
                             order + "'");
        ensure_fits_in_memory(g.size(), 12.0, where);
        RasterD z(g, 0.0);
        ds.read(z.data(), H5::PredType::NATIVE_DOUBLE);
        if (order == "north_to_south") z.array() = z.array().colwise().reverse().eval();
        z.set_crs_wkt(read_string_attr(ds, "crs_wkt"));
        return z;
    } catch (const H5::Exception& e) {
        // Reading failed past the checks above: a truncated or damaged file is bad input.
        throw InputError(where + ": cannot read " + name +
                         ": the file is damaged or truncated (HDF5: " + e.getDetailMsg() + ")");
    }
}

void write_hdf5(const RasterD& z, const std::filesystem::path& path, const WriteOptions& opt) {
    ecoterra::io::Hdf5Writer h5(path);
    h5.raster("/elevation", z, "m", "elevation above the datum at cell centres; NaN = NODATA");
    h5.attribute("/provenance", "json", opt.provenance.dump());
    h5.commit();
}

} // namespace ecoterra::terrain::io
