#include "ecoterra/export/mesh.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <map>
#include <numbers>
#include <tuple>

namespace ecoterra::exporter {

namespace {

constexpr double kMinScale_m = 1e-3;
constexpr double kUmbrellaDepth = 0.3; ///< the umbrella crown fills the top 30 % of the height

using V3 = std::array<float, 3>;

V3 sub(const V3& a, const V3& b) {
    return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
V3 cross(const V3& a, const V3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

/// A surface of revolution about z: rings[k] = (radius, z), from the bottom up; closed at a ring
/// of radius 0 by the fan of its neighbours.
Mesh revolve(const std::vector<std::pair<double, double>>& rings, int segments, bool cap_bottom) {
    Mesh m;
    for (const auto& [r, z] : rings)
        for (int s = 0; s < segments; ++s) {
            const double a = 2 * std::numbers::pi * s / segments;
            m.positions.push_back({static_cast<float>(r * std::cos(a)),
                                   static_cast<float>(r * std::sin(a)), static_cast<float>(z)});
        }
    const auto n = static_cast<std::uint32_t>(segments);
    for (std::uint32_t k = 0; k + 1 < rings.size(); ++k)
        for (std::uint32_t s = 0; s < n; ++s) {
            const std::uint32_t a = k * n + s, b = k * n + (s + 1) % n;
            const std::uint32_t c = a + n, d = b + n;
            m.indices.insert(m.indices.end(), {a, b, d, a, d, c});
        }
    if (cap_bottom) {
        const auto centre = static_cast<std::uint32_t>(m.positions.size());
        m.positions.push_back({0, 0, static_cast<float>(rings.front().second)});
        for (std::uint32_t s = 0; s < n; ++s)
            m.indices.insert(m.indices.end(), {centre, (s + 1) % n, s});
    }
    // Rings of radius 0 leave degenerate triangles: drop them.
    std::vector<std::uint32_t> kept;
    for (std::size_t t = 0; t < m.indices.size(); t += 3) {
        const V3 e = cross(sub(m.positions[m.indices[t + 1]], m.positions[m.indices[t]]),
                           sub(m.positions[m.indices[t + 2]], m.positions[m.indices[t]]));
        if (std::abs(e[0]) + std::abs(e[1]) + std::abs(e[2]) > 1e-12f)
            kept.insert(kept.end(), m.indices.begin() + static_cast<std::ptrdiff_t>(t),
                        m.indices.begin() + static_cast<std::ptrdiff_t>(t + 3));
    }
    m.indices = std::move(kept);
    m.compute_normals();
    return m;
}

} // namespace

void Mesh::append(const Mesh& o, const std::array<double, 3>& s, double yaw,
                  const std::array<double, 3>& t) {
    const auto base = static_cast<std::uint32_t>(positions.size());
    const double c = std::cos(yaw), sn = std::sin(yaw);
    for (std::size_t k = 0; k < o.positions.size(); ++k) {
        const auto& p = o.positions[k];
        const double x = s[0] * p[0], y = s[1] * p[1], z = s[2] * p[2];
        positions.push_back({static_cast<float>(t[0] + c * x - sn * y),
                             static_cast<float>(t[1] + sn * x + c * y),
                             static_cast<float>(t[2] + z)});
        // Normals transform by the inverse transpose of the scale.
        const auto& q = o.normals[k];
        double nx = q[0] / s[0], ny = q[1] / s[1], nz = q[2] / s[2];
        const double len = std::sqrt(nx * nx + ny * ny + nz * nz);
        nx /= len, ny /= len, nz /= len;
        normals.push_back({static_cast<float>(c * nx - sn * ny),
                           static_cast<float>(sn * nx + c * ny), static_cast<float>(nz)});
    }
    for (const auto i : o.indices) indices.push_back(base + i);
}

void Mesh::compute_normals() {
    std::vector<std::array<double, 3>> acc(positions.size(), {0, 0, 0});
    for (std::size_t t = 0; t < indices.size(); t += 3) {
        const V3 e = cross(sub(positions[indices[t + 1]], positions[indices[t]]),
                           sub(positions[indices[t + 2]], positions[indices[t]]));
        for (int k = 0; k < 3; ++k)
            for (int d = 0; d < 3; ++d) acc[indices[t + k]][d] += e[d];
    }
    normals.resize(positions.size());
    for (std::size_t k = 0; k < acc.size(); ++k) {
        const double len =
            std::sqrt(acc[k][0] * acc[k][0] + acc[k][1] * acc[k][1] + acc[k][2] * acc[k][2]);
        normals[k] =
            len > 0 ? V3{static_cast<float>(acc[k][0] / len), static_cast<float>(acc[k][1] / len),
                         static_cast<float>(acc[k][2] / len)}
                    : V3{0, 0, 1};
    }
}

double trunk_base_diameter_m(double dbh_m, double height_m) {
    if (dbh_m > 0 && height_m > kBreastHeight_m)
        return dbh_m / (1 - (1 - kTopDiameterFraction) * kBreastHeight_m / height_m);
    return std::max(height_m / kSeedlingSlenderness, kMinDiameter_m);
}

double crown_base_fraction(Stage s) {
    switch (s) {
    case Stage::young:
        return 0.15;
    case Stage::medium:
        return 0.3;
    case Stage::adult:
        return 0.45;
    }
    return 0.45;
}

Mesh unit_trunk() {
    return revolve({{0.5, 0.0}, {0.5 * kTopDiameterFraction, 1.0}}, kTrunkSegments, false);
}

Mesh unit_crown(eco::CrownShape shape, Stage stage) {
    const double b = crown_base_fraction(stage);
    std::vector<std::pair<double, double>> rings;
    if (shape == eco::CrownShape::cone) {
        rings = {{1.0, b}, {0.0, 1.0}};
        return revolve(rings, kCrownSegments, true);
    }
    // Ellipsoid (or the umbrella's flattened one) of radius 1 between z0 and 1.
    const double z0 = shape == eco::CrownShape::umbrella ? 1 - kUmbrellaDepth : b;
    const double zc = 0.5 * (z0 + 1), hz = 0.5 * (1 - z0);
    for (int k = 0; k <= kCrownRings; ++k) {
        const double phi = std::numbers::pi * (static_cast<double>(k) / kCrownRings - 0.5);
        rings.push_back({std::cos(phi), zc + hz * std::sin(phi)});
    }
    rings.front().first = rings.back().first = 0;
    return revolve(rings, kCrownSegments, false);
}

Mesh deadwood_mesh(const Scene& s, double z_offset_m) {
    const Mesh unit = unit_trunk();
    Mesh out;
    for (const auto& d : s.deadwood) {
        const double dia = std::max(d.diameter_m, kMinScale_m),
                     len = std::max(d.length_m, kMinScale_m);
        // The piece's frame: its axis e3 (up when standing, along the azimuth when lying), e1 and
        // e2 across it (right-handed), and its base point.
        std::array<double, 3> e1{1, 0, 0}, e2{0, 1, 0}, e3{0, 0, 1};
        std::array<double, 3> o{d.x_m, d.y_m, d.z_m - z_offset_m};
        if (!d.standing) {
            const double c = std::cos(d.azimuth_rad), sn = std::sin(d.azimuth_rad);
            e3 = {c, sn, 0};
            e1 = {0, 0, 1};
            e2 = {sn, -c, 0};
            o[2] += d.top_height_m - 0.5 * dia; // the axis: the top at the piece's height
        }
        const auto base = static_cast<std::uint32_t>(out.positions.size());
        for (std::size_t k = 0; k < unit.positions.size(); ++k) {
            const auto& p = unit.positions[k];
            const auto& n = unit.normals[k];
            std::array<float, 3> q{}, m{};
            for (int i = 0; i < 3; ++i) {
                q[i] = static_cast<float>(o[i] + dia * p[0] * e1[i] + dia * p[1] * e2[i] +
                                          len * p[2] * e3[i]);
                m[i] = static_cast<float>(n[0] * e1[i] + n[1] * e2[i] + n[2] * e3[i]);
            }
            out.positions.push_back(q);
            out.normals.push_back(m);
        }
        for (const auto i : unit.indices) out.indices.push_back(base + i);
    }
    return out;
}

std::array<double, 3> trunk_scale(const Tree& t) {
    const double base =
        t.base_diameter_m > 0 ? t.base_diameter_m : trunk_base_diameter_m(t.dbh_m, t.height_m);
    const double d = std::max(base, kMinScale_m);
    return {d, d, std::max(t.height_m, kMinScale_m)};
}

std::array<double, 3> crown_scale(const Tree& t) {
    const double r = std::max(t.crown_radius_m, kMinScale_m);
    return {r, r, std::max(t.height_m, kMinScale_m)};
}

std::array<double, 3> tuft_scale(const Tuft& t) {
    const double d = std::max(2 * t.radius_m, kMinScale_m);
    return {d, d, std::max(t.height_m, kMinScale_m)};
}

std::vector<SizeClass> size_classes(const Scene& s, const std::function<bool(const Tree&)>& skip) {
    const double lq = std::log(kSizeClassRatio);
    auto k = [&](double v) { return static_cast<int>(std::lround(std::log(v) / lq)); };
    std::map<std::tuple<int, int, int, int, int>, SizeClass> by_key;
    for (std::size_t i = 0; i < s.trees.size(); ++i) {
        const Tree& t = s.trees[i];
        if (skip && skip(t)) continue;
        const auto ts = trunk_scale(t);
        const auto cs = crown_scale(t);
        const int kh = k(ts[2]), kd = k(ts[0]), kr = k(cs[0]);
        auto& c = by_key[{t.species, static_cast<int>(t.stage), kh, kd, kr}];
        if (c.trees.empty()) {
            c.species = t.species;
            c.stage = t.stage;
            c.kh = kh, c.kd = kd, c.kr = kr;
            c.height_m = std::pow(kSizeClassRatio, kh);
            c.base_diameter_m = std::pow(kSizeClassRatio, kd);
            c.crown_radius_m = std::pow(kSizeClassRatio, kr);
        }
        c.trees.push_back(i);
    }
    std::vector<SizeClass> out;
    for (auto& [key, c] : by_key) {
        c.name = file_safe(s.species[static_cast<std::size_t>(c.species)].name) + "_" +
                 stage_name(c.stage) + "_h" + std::to_string(c.kh) + "_d" + std::to_string(c.kd) +
                 "_r" + std::to_string(c.kr);
        for (char& ch : c.name)
            if (ch == '-') ch = 'm';
        out.push_back(std::move(c));
    }
    return out;
}

double stem_diameter_m(const Tree& t) {
    if (t.base_diameter_m > 0) return t.base_diameter_m;
    return t.dbh_m > 0 ? t.dbh_m : trunk_base_diameter_m(t.dbh_m, t.height_m);
}

std::string file_safe(const std::string& name) {
    std::string out;
    for (char ch : name) {
        const auto u = static_cast<unsigned char>(ch);
        if (std::isalnum(u))
            out += static_cast<char>(std::tolower(u));
        else if (!out.empty() && out.back() != '_')
            out += '_';
    }
    while (!out.empty() && out.back() == '_') out.pop_back();
    return out.empty() ? "species" : out;
}

Mesh terrain_mesh(const RasterD& z, int step, double z_offset_m) {
    step = std::max(step, 1);
    auto axis = [&](int n) {
        std::vector<int> v;
        for (int i = 0; i < n; i += step) v.push_back(i);
        if (v.back() != n - 1) v.push_back(n - 1);
        return v;
    };
    const auto cols = axis(z.nx()), rows = axis(z.ny());
    Mesh m;
    const GridSpec& g = z.grid();
    for (int j : rows)
        for (int i : cols)
            m.positions.push_back({static_cast<float>(g.x_of(i)), static_cast<float>(g.y_of(j)),
                                   static_cast<float>(z(i, j) - z_offset_m)});
    const auto w = static_cast<std::uint32_t>(cols.size());
    for (std::uint32_t r = 0; r + 1 < rows.size(); ++r)
        for (std::uint32_t c = 0; c + 1 < w; ++c) {
            const std::uint32_t a = r * w + c, b = a + 1, d = a + w, e = d + 1;
            m.indices.insert(m.indices.end(), {a, b, e, a, e, d}); // counter-clockwise from above
        }
    m.compute_normals();
    return m;
}

std::string to_obj(const std::vector<ObjPart>& parts, const std::string& header,
                   const std::string& mtllib) {
    std::string out = "# " + header + "\n";
    if (!mtllib.empty()) out += "mtllib " + mtllib + "\n";
    char buf[96];
    std::uint32_t base = 1;
    for (const auto& part : parts) {
        const Mesh& m = *part.mesh;
        for (const auto& p : m.positions) {
            std::snprintf(buf, sizeof buf, "v %.9g %.9g %.9g\n", p[0], p[1], p[2]);
            out += buf;
        }
        for (const auto& n : m.normals) {
            std::snprintf(buf, sizeof buf, "vn %.6g %.6g %.6g\n", n[0], n[1], n[2]);
            out += buf;
        }
        if (!part.material.empty()) out += "usemtl " + part.material + "\n";
        for (std::size_t t = 0; t < m.indices.size(); t += 3) {
            const auto a = m.indices[t] + base, b = m.indices[t + 1] + base,
                       c = m.indices[t + 2] + base;
            std::snprintf(buf, sizeof buf, "f %u//%u %u//%u %u//%u\n", a, a, b, b, c, c);
            out += buf;
        }
        base += static_cast<std::uint32_t>(m.positions.size());
    }
    return out;
}

std::string to_mtl(const std::vector<std::pair<std::string, std::array<double, 3>>>& materials) {
    std::string out = "# ecoterra materials (diffuse colours)\n";
    char buf[128];
    for (const auto& [name, c] : materials) {
        std::snprintf(buf, sizeof buf, "newmtl %s\nKd %.3f %.3f %.3f\nKa 0 0 0\nKs 0 0 0\nd 1\n",
                      name.c_str(), c[0], c[1], c[2]);
        out += buf;
    }
    return out;
}

std::array<double, 3> crown_colour(const SpeciesLook& sp, int k) {
    const double shade = sp.evergreen ? 0.6 : 1.0;
    const double hue = 0.08 * (k % 5);
    return {shade * (0.18 + hue), shade * 0.45, shade * (0.12 + 0.5 * hue)};
}

} // namespace ecoterra::exporter
