// Wavefront OBJ meshes of rasters: one vertex per valid cell centre (x east, y north, z up, m),
// two triangles per 2x2 block of valid cells, counter-clockwise seen from above.
#include "ecoterra/io/atomic_file.hpp"
#include "ecoterra/terrain/io/raster_io.hpp"

#include <cstdio>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

namespace ecoterra::terrain::io {

void write_obj(const RasterD& z, const std::filesystem::path& path) {
    ecoterra::io::AtomicOutput out(path);
    {
        std::FILE* f = std::fopen(out.temp_path().c_str(), "wb");
        if (!f) throw IoError(path.string() + ": cannot open for writing");
        std::fprintf(f, "# ecoterra terrain mesh: %d x %d cells of %.9g m, Z up, metres\n", z.nx(),
                     z.ny(), z.cell_size());
        std::fprintf(f, "o terrain\n");
        std::vector<std::int64_t> index(static_cast<std::size_t>(z.size()), 0);
        std::int64_t next = 1;
        for (int j = 0; j < z.ny(); ++j)
            for (int i = 0; i < z.nx(); ++i) {
                if (std::isnan(z(i, j))) continue;
                index[static_cast<std::size_t>(j) * z.nx() + i] = next++;
                std::fprintf(f, "v %.9g %.9g %.9g\n", z.grid().x_of(i), z.grid().y_of(j), z(i, j));
            }
        auto id = [&](int i, int j) { return index[static_cast<std::size_t>(j) * z.nx() + i]; };
        for (int j = 0; j + 1 < z.ny(); ++j)
            for (int i = 0; i + 1 < z.nx(); ++i) {
                const auto a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
                if (a && b && c)
                    std::fprintf(f, "f %lld %lld %lld\n", (long long)a, (long long)b, (long long)c);
                if (a && c && d)
                    std::fprintf(f, "f %lld %lld %lld\n", (long long)a, (long long)c, (long long)d);
            }
        const bool bad = std::ferror(f) != 0;
        if (std::fclose(f) != 0 || bad)
            throw IoError(path.string() + ": write failed (disk full?)");
    }
    out.commit();
}

RasterD read_obj(const std::filesystem::path& path) {
    const std::string where = path.string();
    std::ifstream in(path);
    if (!in) throw InputError(where + ": cannot open for reading");
    std::vector<std::array<double, 3>> v;
    std::string line;
    long lineno = 0;
    while (std::getline(in, line)) {
        ++lineno;
        if (line.size() < 2 || line[0] != 'v' || line[1] != ' ') continue;
        std::istringstream s(line.substr(2));
        std::array<double, 3> p{};
        if (!(s >> p[0] >> p[1] >> p[2]))
            throw InputError(where + ": line " + std::to_string(lineno) + ": malformed vertex");
        v.push_back(p);
    }
    if (v.size() < 4) throw InputError(where + ": fewer than 4 vertices; not a terrain mesh");
    // The vertices must sit on a regular grid: find the spacing from the distinct x and y.
    std::set<double> xs, ys;
    for (auto& p : v) xs.insert(p[0]), ys.insert(p[1]);
    auto spacing = [&](const std::set<double>& s) {
        double h = std::numeric_limits<double>::infinity();
        for (auto it = std::next(s.begin()); it != s.end(); ++it)
            h = std::min(h, *it - *std::prev(it));
        return h;
    };
    const double hx = spacing(xs), hy = spacing(ys);
    if (!(std::abs(hx - hy) <= 1e-6 * hx))
        throw InputError(where + ": vertices do not lie on a square grid (spacing " +
                         std::to_string(hx) + " x " + std::to_string(hy) + " m)");
    const double h = hx;
    GridSpec g;
    g.cell_size_m = h;
    g.nx = static_cast<int>(std::lround((*xs.rbegin() - *xs.begin()) / h)) + 1;
    g.ny = static_cast<int>(std::lround((*ys.rbegin() - *ys.begin()) / h)) + 1;
    g.origin_x_m = *xs.begin() - 0.5 * h;
    g.origin_y_m = *ys.begin() - 0.5 * h;
    ensure_fits_in_memory(g.size(), 8.0, where);
    RasterD z(g, std::nan(""));
    for (auto& p : v) {
        const double fi = (p[0] - *xs.begin()) / h, fj = (p[1] - *ys.begin()) / h;
        const long i = std::lround(fi), j = std::lround(fj);
        if (std::abs(fi - i) > 1e-3 || std::abs(fj - j) > 1e-3)
            throw InputError(where + ": vertex (" + std::to_string(p[0]) + ", " +
                             std::to_string(p[1]) + ") is off the grid");
        z(static_cast<int>(i), static_cast<int>(j)) = p[2];
    }
    return z;
}

} // namespace ecoterra::terrain::io
