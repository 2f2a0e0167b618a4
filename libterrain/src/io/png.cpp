// PNG reading and writing with libpng: 16-bit grayscale heightmaps (with a JSON sidecar holding
// the vertical scale) and 8-bit RGB pictures.
#include "ecoterra/io/atomic_file.hpp"
#include "ecoterra/terrain/io/raster_io.hpp"
#include "ecoterra/terrain/picture.hpp"

#include <png.h>

#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <limits>
#include <optional>

namespace ecoterra::terrain::io {

namespace {

constexpr double kUint16Max = 65535.0;
/// Unreal Engine: at Z scale 100 one 16-bit unit is 100/128 cm, so the span is Zscale x 5.12 m.
constexpr double kUnrealMetresPerZScale = 65536.0 / 128.0 / 100.0 / 100.0;

struct PngError {
    char message[512] = {0};
};

void on_png_error(png_structp png, png_const_charp msg) {
    auto* e = static_cast<PngError*>(png_get_error_ptr(png));
    std::snprintf(e->message, sizeof e->message, "%s", msg);
    longjmp(png_jmpbuf(png), 1);
}
void on_png_warning(png_structp, png_const_charp) {}

/// Writes raw rows (big-endian 16-bit or 8-bit samples) to `file`. Returns an error message or "".
std::string write_png_raw(const char* file, int w, int h, int bit_depth, int color_type,
                          const std::vector<std::uint8_t>& rows, std::size_t stride) {
    PngError err;
    std::FILE* fp = std::fopen(file, "wb");
    if (!fp) return std::string("cannot open for writing: ") + std::strerror(errno);
    png_structp png =
        png_create_write_struct(PNG_LIBPNG_VER_STRING, &err, on_png_error, on_png_warning);
    png_infop info = png ? png_create_info_struct(png) : nullptr;
    std::vector<png_bytep> ptrs(static_cast<std::size_t>(h));
    for (int y = 0; y < h; ++y)
        ptrs[y] = const_cast<png_bytep>(rows.data() + static_cast<std::size_t>(y) * stride);
    if (!png || !info || setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        std::fclose(fp);
        return err.message[0] ? err.message : "libpng could not start";
    }
    png_init_io(png, fp);
    png_set_IHDR(png, info, static_cast<png_uint_32>(w), static_cast<png_uint_32>(h), bit_depth,
                 color_type, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    png_write_image(png, ptrs.data());
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    if (std::fclose(fp) != 0) return "write failed (disk full?)";
    return {};
}

struct RawPng {
    int width = 0, height = 0, bit_depth = 0, channels = 0;
    std::vector<std::uint8_t> data; ///< rows, big-endian for 16-bit
};

std::string read_png_raw(const char* file, RawPng& out) {
    PngError err;
    std::FILE* fp = std::fopen(file, "rb");
    if (!fp) return std::string("cannot open for reading: ") + std::strerror(errno);
    png_byte sig[8];
    if (std::fread(sig, 1, 8, fp) != 8 || png_sig_cmp(sig, 0, 8)) {
        std::fclose(fp);
        return "not a PNG file";
    }
    png_structp png =
        png_create_read_struct(PNG_LIBPNG_VER_STRING, &err, on_png_error, on_png_warning);
    png_infop info = png ? png_create_info_struct(png) : nullptr;
    std::vector<png_bytep> ptrs;
    if (!png || !info || setjmp(png_jmpbuf(png))) {
        png_destroy_read_struct(&png, &info, nullptr);
        std::fclose(fp);
        return err.message[0] ? err.message : "libpng could not start";
    }
    png_init_io(png, fp);
    png_set_sig_bytes(png, 8);
    png_read_info(png, info);
    const int ct = png_get_color_type(png, info);
    if (png_get_bit_depth(png, info) < 8) png_set_expand_gray_1_2_4_to_8(png);
    if (ct == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
    png_read_update_info(png, info);
    out.width = static_cast<int>(png_get_image_width(png, info));
    out.height = static_cast<int>(png_get_image_height(png, info));
    out.bit_depth = png_get_bit_depth(png, info);
    out.channels = png_get_channels(png, info);
    const std::size_t stride = png_get_rowbytes(png, info);
    out.data.resize(stride * static_cast<std::size_t>(out.height));
    ptrs.resize(static_cast<std::size_t>(out.height));
    for (int y = 0; y < out.height; ++y) ptrs[y] = out.data.data() + stride * y;
    png_read_image(png, ptrs.data());
    png_read_end(png, nullptr);
    png_destroy_read_struct(&png, &info, nullptr);
    std::fclose(fp);
    return {};
}

bool unreal_side_ok(int n) {
    static const int quads[] = {7, 15, 31, 63, 127, 255};
    for (int q : quads)
        for (int sections : {1, 2})
            for (int comps = 1; comps <= 32; ++comps)
                if (comps * sections * q + 1 == n) return true;
    return false;
}

/// Encodes z into 16-bit rows (north first) and the sidecar describing the encoding.
void encode_png16(const RasterD& z, const std::filesystem::path& path, const WriteOptions& opt,
                  nlohmann::json extra) {
    const auto s = stats(z);
    if (s.valid == 0) throw InputError(path.string() + ": the raster holds no valid cell");
    const bool has_nodata = s.valid < z.size();
    // With NODATA present, 0 is reserved for it and heights use 1..65535.
    const double lo_code = has_nodata ? 1.0 : 0.0;
    const double span = s.max - s.min;
    const double scale = span > 0 ? span / (kUint16Max - lo_code) : 1.0;
    const double offset = s.min - lo_code * scale;
    std::vector<std::uint8_t> rows(static_cast<std::size_t>(z.size()) * 2);
    for (int r = 0; r < z.ny(); ++r)
        for (int i = 0; i < z.nx(); ++i) {
            const double v = z(i, z.ny() - 1 - r);
            const auto code = std::isnan(v) ? std::uint16_t{0}
                                            : static_cast<std::uint16_t>(std::lround(std::clamp(
                                                  (v - offset) / scale, lo_code, kUint16Max)));
            const std::size_t k = (static_cast<std::size_t>(r) * z.nx() + i) * 2;
            rows[k] = static_cast<std::uint8_t>(code >> 8);
            rows[k + 1] = static_cast<std::uint8_t>(code & 0xff);
        }
    nlohmann::json side = {
        {"format", "ecoterra-png-heightmap"},
        {"version", 1},
        {"elevation", "elevation_m = vertical_offset_m + vertical_scale_m * pixel_value"},
        {"vertical_scale_m", scale},
        {"vertical_offset_m", offset},
        {"nodata_value", has_nodata ? nlohmann::json(0) : nlohmann::json(nullptr)},
        {"cell_size_m", z.cell_size()},
        {"origin_x_m", z.grid().origin_x_m},
        {"origin_y_m", z.grid().origin_y_m},
        {"nx", z.nx()},
        {"ny", z.ny()},
        {"top_row", "north"},
        {"min_elevation_m", s.min},
        {"max_elevation_m", s.max},
        {"unreal",
         {{"xy_scale_percent", z.cell_size() * 100.0},
          {"z_scale_percent", span / kUnrealMetresPerZScale / 100.0},
          {"landscape_size_valid", z.nx() == z.ny() && unreal_side_ok(z.nx())},
          {"note", "Unreal places pixel 32768 at z = 0; at this Z scale the full 16-bit range "
                   "spans the terrain's relief"}}},
        {"provenance", opt.provenance}};
    for (auto& [k, v] : extra.items()) side[k] = v;
    // No warning for a side Unreal would not take: a PNG heightmap serves Gazebo, GIS and
    // pictures too, and `export scene --format unreal` resamples to an Unreal side itself; the
    // sidecar's unreal.landscape_size_valid says it.
    ecoterra::io::AtomicOutput png_out(path);
    ecoterra::io::AtomicOutput json_out(png_sidecar_path(path));
    const std::string e =
        write_png_raw(png_out.temp_path().c_str(), z.nx(), z.ny(), 16, PNG_COLOR_TYPE_GRAY, rows,
                      static_cast<std::size_t>(z.nx()) * 2);
    if (!e.empty()) throw IoError(path.string() + ": " + e);
    {
        std::FILE* f = std::fopen(json_out.temp_path().c_str(), "wb");
        if (!f) throw IoError(png_sidecar_path(path).string() + ": cannot open for writing");
        const std::string text = side.dump(2) + "\n";
        const bool ok = std::fwrite(text.data(), 1, text.size(), f) == text.size();
        if (std::fclose(f) != 0 || !ok)
            throw IoError(png_sidecar_path(path).string() + ": write failed (disk full?)");
    }
    png_out.commit();
    json_out.commit();
}

} // namespace

std::filesystem::path png_sidecar_path(const std::filesystem::path& png) {
    return std::filesystem::path(png.string() + ".json");
}

bool is_unreal_landscape_size(int n) {
    return unreal_side_ok(n);
}

int gazebo_side_for(int n) {
    int s = 2;
    while (s + 1 < n) s *= 2;
    return s + 1;
}

void write_png16(const RasterD& z, const std::filesystem::path& path, const WriteOptions& opt) {
    encode_png16(z, path, opt, nlohmann::json::object());
}

void write_gazebo_png(const RasterD& z, const std::filesystem::path& path,
                      const WriteOptions& opt) {
    if (std::abs(z.grid().width_m() - z.grid().height_m()) > 1e-9 * z.grid().width_m())
        throw InputError(path.string() + ": Gazebo heightmaps must be square; the raster is " +
                         std::to_string(z.grid().width_m()) + " x " +
                         std::to_string(z.grid().height_m()) + " m (crop it first)");
    const int side = gazebo_side_for(std::max(z.nx(), z.ny()));
    RasterD out = z;
    if (side != z.nx() || side != z.ny()) {
        // Resample over the same extent so that the first and last samples sit on the old
        // outermost cell centres.
        const double span = (z.nx() - 1) * z.cell_size();
        const double h = span / (side - 1);
        GridSpec g{side, side, h, z.grid().x_of(0) - 0.5 * h, z.grid().y_of(0) - 0.5 * h};
        out = RasterD(g, 0.0);
        for (int j = 0; j < side; ++j)
            for (int i = 0; i < side; ++i) out(i, j) = z.sample_bilinear(g.x_of(i), g.y_of(j));
        if (opt.warnings)
            opt.warnings->push_back(path.string() + ": resampled " + std::to_string(z.nx()) + "x" +
                                    std::to_string(z.ny()) + " to " + std::to_string(side) + "x" +
                                    std::to_string(side) +
                                    " (Gazebo needs a square of side 2^n + 1)");
    }
    const auto s = stats(out);
    const double size_xy = (side - 1) * out.cell_size();
    // Gazebo centres the heightmap on <pos>: the centre of the outermost samples, so that the
    // heightmap lands where the raster lies (and stems placed by their coordinates stand on it).
    const double cx = out.grid().x_of(0) + 0.5 * size_xy, cy = out.grid().y_of(0) + 0.5 * size_xy;
    auto num = [](double v) {
        char b[32];
        std::snprintf(b, sizeof b, "%.9g", v);
        return std::string(b);
    };
    nlohmann::json gz = {
        {"gazebo",
         {{"size_m", {size_xy, size_xy, s.max - s.min}},
          {"pos_m", {cx, cy, s.min}},
          {"sdf", "<heightmap><uri>" + path.filename().string() + "</uri><size>" + num(size_xy) +
                      " " + num(size_xy) + " " + num(s.max - s.min) + "</size><pos>" + num(cx) +
                      " " + num(cy) + " " + num(s.min) + "</pos></heightmap>"}}}};
    encode_png16(out, path, opt, gz);
}

RasterD read_png16(const std::filesystem::path& path, std::vector<std::string>* warnings) {
    const std::string where = path.string();
    RawPng raw;
    const std::string e = read_png_raw(where.c_str(), raw);
    if (!e.empty()) throw InputError(where + ": " + e);
    if (raw.channels != 1 && raw.channels != 2)
        throw InputError(where + ": PNG heightmaps must be grayscale, this one has " +
                         std::to_string(raw.channels) + " channels");
    GridSpec g{raw.width, raw.height, 1.0, 0.0, 0.0};
    double scale = 1.0 / kUint16Max, offset = 0.0;
    std::optional<long> nodata;
    const auto side = png_sidecar_path(path);
    if (std::filesystem::exists(side)) {
        nlohmann::json j;
        try {
            j = nlohmann::json::parse(ecoterra::io::read_text(side));
            scale = j.at("vertical_scale_m").get<double>();
            offset = j.at("vertical_offset_m").get<double>();
            g.cell_size_m = j.at("cell_size_m").get<double>();
            g.origin_x_m = j.value("origin_x_m", 0.0);
            g.origin_y_m = j.value("origin_y_m", 0.0);
            if (j.contains("nodata_value") && !j["nodata_value"].is_null())
                nodata = j["nodata_value"].get<long>();
        } catch (const nlohmann::json::exception& ex) {
            throw InputError(side.string() + ": malformed sidecar: " + ex.what());
        }
        if (raw.bit_depth == 8) scale *= 257.0; // an 8-bit file under a 16-bit sidecar
    } else {
        if (raw.bit_depth == 8) scale = 1.0 / 255.0;
        if (warnings)
            warnings->push_back(where + ": no sidecar " + side.filename().string() +
                                "; heights are pixel/max (0..1 m) on a 1 m grid");
    }
    g.validate(side.string());
    RasterD z(g, 0.0);
    const int bpp = raw.bit_depth / 8 * raw.channels;
    const std::size_t stride = static_cast<std::size_t>(raw.width) * bpp;
    for (int r = 0; r < raw.height; ++r)
        for (int i = 0; i < raw.width; ++i) {
            const std::uint8_t* p =
                raw.data.data() + r * stride + static_cast<std::size_t>(i) * bpp;
            const long code = raw.bit_depth == 16 ? (long(p[0]) << 8 | p[1]) : long(p[0]);
            z(i, raw.height - 1 - r) =
                (nodata && code == *nodata) ? std::nan("") : offset + scale * code;
        }
    return z;
}

} // namespace ecoterra::terrain::io
