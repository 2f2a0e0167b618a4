// The export's check picture: the snapshot's stems (crown circles from the run's records) beside
// a top view rendered from the exported geometry (the terrain mesh and every tree's trunk and
// crown triangles, placed by the transforms the writers write), so a person can see they agree.
#include "ecoterra/export/picture.hpp"
#include "ecoterra/export/mesh.hpp"

#include "ecoterra/error.hpp"
#include "ecoterra/run/pictures.hpp"
#include "ecoterra/terrain/picture.hpp"

#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

namespace ecoterra::exporter {

namespace {

constexpr double kPanelPx = 600, kTitlePx = 30, kGapPx = 20;
constexpr int kMaxTerrainQuads = 150; ///< per side, in the picture's terrain mesh

struct Tri {
    std::array<std::array<float, 3>, 3> p;
    std::array<double, 3> rgb;
    float z;
};

/// Lambert shading of a colour by a normal, light from the north-west, 45 degrees up.
std::array<double, 3> shade(const std::array<double, 3>& c, const std::array<float, 3>& n) {
    const double l = std::max(0.0, (-0.5 * n[0] + 0.5 * n[1] + 0.7071 * n[2]));
    const double f = 0.35 + 0.65 * l;
    return {c[0] * f, c[1] * f, c[2] * f};
}

void add(std::vector<Tri>& out, const Mesh& m, const std::array<double, 3>& rgb) {
    for (std::size_t t = 0; t < m.indices.size(); t += 3) {
        Tri tri;
        std::array<float, 3> n{0, 0, 0};
        float z = 0;
        for (int k = 0; k < 3; ++k) {
            const auto i = m.indices[t + static_cast<std::size_t>(k)];
            tri.p[static_cast<std::size_t>(k)] = m.positions[i];
            for (int d = 0; d < 3; ++d)
                n[static_cast<std::size_t>(d)] += m.normals[i][static_cast<std::size_t>(d)] / 3;
            z = std::max(z, m.positions[i][2]);
        }
        tri.rgb = shade(rgb, n);
        tri.z = z;
        out.push_back(tri);
    }
}

void label(cairo_t* cr, double x, double y, const std::string& s, const char* role = "title") {
    cairo_set_source_rgb(cr, 0, 0, 0);
    terrain::draw_text(cr, x, y, s, 13, 0, role);
}

} // namespace

namespace {

/// Two panels of the terrain side by side: world metres to pixels.
struct PanelFrame {
    GridSpec g;
    double scale, w, h;
    explicit PanelFrame(const GridSpec& grid)
        : g(grid), scale(kPanelPx / std::max(grid.width_m(), grid.height_m())),
          w(grid.width_m() * scale), h(grid.height_m() * scale) {}
    double px(double x, double off) const { return off + (x - g.origin_x_m) * scale; }
    double py(double y) const { return kTitlePx + (g.height_m() - (y - g.origin_y_m)) * scale; }
};

std::string records_title(const Scene& s) {
    return "Snapshot " + std::to_string(s.snapshot) + " (year " + std::to_string(s.year) +
           "): stems, crown circles";
}
std::string geometry_title(std::size_t triangles) {
    return "Exported geometry, top view: " + std::to_string(triangles) + " triangles";
}

/// Left: the run's records, crowns as circles over the hillshade.
void draw_records_panel(cairo_t* cr, const Scene& s, const PanelFrame& f) {
    terrain::paint_image(cr, terrain::hillshade_image(s.terrain), 0, kTitlePx, f.w, f.h, true);
    std::vector<std::size_t> order(s.trees.size());
    for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        return s.trees[a].crown_radius_m > s.trees[b].crown_radius_m;
    });
    cairo_set_line_width(cr, 0.8);
    cairo_save(cr); // crowns near the edges stay on the panel
    cairo_rectangle(cr, 0, kTitlePx, f.w, f.h);
    cairo_clip(cr);
    for (const auto k : order) {
        const Tree& t = s.trees[k];
        const auto c = run::species_colour(static_cast<std::size_t>(t.species));
        cairo_arc(cr, f.px(t.x_m, 0), f.py(t.y_m), std::max(1.0, t.crown_radius_m * f.scale), 0,
                  2 * std::numbers::pi);
        cairo_set_source_rgba(cr, c[0], c[1], c[2], 0.55);
        cairo_fill_preserve(cr);
        cairo_set_source_rgba(cr, 0.1, 0.1, 0.1, 0.8);
        cairo_stroke(cr);
    }
    cairo_restore(cr);
    label(cr, 8, 20, records_title(s));
}

/// The exported geometry's triangles (terrain, trunks, crowns or the user's meshes), far to
/// near (painter's order by height).
std::vector<Tri> exported_triangles(const Scene& s, const UserMeshes* user) {
    const GridSpec& g = s.terrain.grid();
    std::vector<Tri> tris;
    const int step = std::max(1, (std::max(g.nx, g.ny) + kMaxTerrainQuads - 1) / kMaxTerrainQuads);
    add(tris, terrain_mesh(s.terrain, step), kGroundColour);
    const Mesh trunk = unit_trunk();
    for (const auto& t : s.trees) {
        const auto col = run::species_colour(static_cast<std::size_t>(t.species));
        if (const UserMesh* u = user ? user->find(t.species, t.stage) : nullptr) {
            const double k = std::max(t.height_m, 1e-3) / u->height_m;
            Mesh m;
            m.append(u->mesh, {k, k, k}, t.yaw_rad, {t.x_m, t.y_m, t.z_m});
            add(tris, m, col);
            continue;
        }
        Mesh m;
        m.append(trunk, trunk_scale(t), t.yaw_rad, {t.x_m, t.y_m, t.z_m});
        add(tris, m, kBarkColour);
        Mesh c;
        c.append(unit_crown(s.species[static_cast<std::size_t>(t.species)].crown_shape, t.stage),
                 crown_scale(t), t.yaw_rad, {t.x_m, t.y_m, t.z_m});
        add(tris, c, col);
    }
    std::stable_sort(tris.begin(), tris.end(),
                     [](const Tri& a, const Tri& b) { return a.z < b.z; });
    return tris;
}

/// Right: the exported geometry seen from above.
void draw_geometry_panel(cairo_t* cr, const std::vector<Tri>& tris, const PanelFrame& f,
                         double off) {
    cairo_save(cr);
    cairo_rectangle(cr, off, kTitlePx, f.w, f.h);
    cairo_clip(cr);
    cairo_set_line_width(cr, 0.3);
    for (const auto& t : tris) {
        cairo_move_to(cr, f.px(t.p[0][0], off), f.py(t.p[0][1]));
        cairo_line_to(cr, f.px(t.p[1][0], off), f.py(t.p[1][1]));
        cairo_line_to(cr, f.px(t.p[2][0], off), f.py(t.p[2][1]));
        cairo_close_path(cr);
        cairo_set_source_rgb(cr, t.rgb[0], t.rgb[1], t.rgb[2]);
        cairo_fill_preserve(cr);
        cairo_stroke(cr); // closes hairline gaps between neighbours
    }
    cairo_restore(cr);
    label(cr, off + 8, 20, geometry_title(tris.size()));
}

} // namespace

void draw_export_picture(const Scene& s, const std::filesystem::path& png, const UserMeshes* user) {
    const GridSpec& g = s.terrain.grid();
    const PanelFrame f(g);
    const std::vector<Tri> tris = exported_triangles(s, user);
    // Each panel's column is at least as wide as its title (a tall, narrow terrain cut them).
    const double left_w = std::max(f.w, 16 + terrain::text_width(records_title(s), 13));
    const double off = left_w + kGapPx;
    const double right_w = std::max(f.w, 16 + terrain::text_width(geometry_title(tris.size()), 13));
    const int W = static_cast<int>(std::ceil(off + right_w)),
              H = static_cast<int>(std::ceil(f.h + kTitlePx + 54));
    cairo_surface_t* surf = cairo_image_surface_create(CAIRO_FORMAT_RGB24, W, H);
    cairo_t* cr = cairo_create(surf);
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_paint(cr);
    draw_records_panel(cr, s, f);
    draw_geometry_panel(cr, tris, f, off);
    label(cr, 8, kTitlePx + f.h + 18,
          std::to_string(s.trees.size()) + " trees, " +
              std::to_string(static_cast<int>(g.width_m())) + " m x " +
              std::to_string(static_cast<int>(g.height_m())) + " m; colours by species; north up",
          "note");
    // A scale under each panel (they share it; the geometry panel had none).
    const double bar_px = std::max(f.w / 4, 40.0);
    terrain::draw_scale_bar(cr, 10, kTitlePx + f.h + 40, f.scale, bar_px);
    terrain::draw_scale_bar(cr, off + 10, kTitlePx + f.h + 40, f.scale, bar_px);
    cairo_surface_flush(surf);
    const auto status = cairo_surface_write_to_png(surf, png.string().c_str());
    cairo_destroy(cr);
    cairo_surface_destroy(surf);
    if (status != CAIRO_STATUS_SUCCESS) throw IoError(png.string() + ": cannot write the picture");
}

} // namespace ecoterra::exporter
