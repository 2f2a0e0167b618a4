// Every kind of picture, on a small and a large case: its size, every label inside the picture,
// distinct tick labels on each axis, labelled axes and a title, a scale on maps, and nothing of
// the map drawn outside its frame. The texts come from terrain::FigureLog, which records what
// draw_text put where; the pixels from the PNG files.
#include "support/png_size.hpp"
#include "support/run_cli.hpp"
#include "support/scenes.hpp"

#include "ecoterra/eco/ecosystem.hpp"
#include "ecoterra/eco/population.hpp"
#include "ecoterra/eco/scene_config.hpp"
#include "ecoterra/export/picture.hpp"
#include "ecoterra/export/scene.hpp"
#include "ecoterra/mobility/map.hpp"
#include "ecoterra/mobility/route.hpp"
#include "ecoterra/mobility/stand.hpp"
#include "ecoterra/mobility/traverse.hpp"
#include "ecoterra/mobility/vehicle.hpp"
#include "ecoterra/run/pictures.hpp"
#include "ecoterra/run/run_reader.hpp"
#include "ecoterra/terrain/analysis.hpp"
#include "ecoterra/terrain/picture.hpp"

#include <cairo.h>
#include <catch2/catch.hpp>

#include <fstream>
#include <map>
#include <set>

using namespace ecoterra;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

/// The texts of each picture (by surface), in drawing order.
std::vector<std::vector<terrain::DrawnText>> by_picture(const terrain::FigureLog& log) {
    std::vector<std::vector<terrain::DrawnText>> out;
    std::map<const void*, std::size_t> index;
    for (const auto& t : log.texts) {
        auto [it, fresh] = index.emplace(t.surface, out.size());
        if (fresh) out.emplace_back();
        out[it->second].push_back(t);
    }
    return out;
}

/// Labels inside the picture, ticks distinct per axis; the roles every picture of `kind` needs.
void check_picture(const std::vector<terrain::DrawnText>& texts,
                   const std::vector<std::string>& roles) {
    REQUIRE(!texts.empty());
    const int w = texts.front().surface_width, h = texts.front().surface_height;
    CAPTURE(w, h, texts.front().text);
    REQUIRE(w > 0);
    std::map<std::string, std::vector<std::string>> ticks;
    std::set<std::string> seen;
    for (const auto& t : texts) {
        CAPTURE(t.text, t.role, t.x0, t.y0, t.x1, t.y1);
        CHECK(t.x0 >= -0.5);
        CHECK(t.y0 >= -0.5);
        CHECK(t.x1 <= w + 0.5);
        CHECK(t.y1 <= h + 0.5);
        seen.insert(t.role);
        // One axis per role and panel (a picture may hold several).
        if (t.role == "xtick" || t.role == "ytick" || t.role == "bar_tick")
            ticks[t.role + " of axes " + std::to_string(t.axes)].push_back(t.text);
    }
    for (const auto& [role, labels] : ticks) {
        CAPTURE(role);
        CHECK(std::set<std::string>(labels.begin(), labels.end()).size() == labels.size());
        CHECK(labels.size() >= 2);
    }
    for (const auto& r : roles) {
        CAPTURE(r);
        CHECK(seen.count(r) == 1);
    }
}

/// The PNG files are the pictures the log saw, in order, at the sizes it saw.
void check_files(const std::vector<std::vector<terrain::DrawnText>>& pics,
                 const std::vector<fs::path>& files) {
    REQUIRE(pics.size() == files.size());
    for (std::size_t k = 0; k < files.size(); ++k) {
        CAPTURE(files[k]);
        const auto [w, h] = test::png_size(files[k]);
        CHECK(w == static_cast<unsigned>(pics[k].front().surface_width));
        CHECK(h == static_cast<unsigned>(pics[k].front().surface_height));
        CHECK(w >= 600);
        CHECK(h >= 300);
    }
}

/// True if every pixel of the rectangle is white (nothing drawn there).
bool white_strip(const fs::path& png, int x0, int y0, int x1, int y1) {
    cairo_surface_t* s = cairo_image_surface_create_from_png(png.string().c_str());
    REQUIRE(cairo_surface_status(s) == CAIRO_STATUS_SUCCESS);
    const int w = cairo_image_surface_get_width(s), h = cairo_image_surface_get_height(s);
    const int stride = cairo_image_surface_get_stride(s);
    const unsigned char* data = cairo_image_surface_get_data(s);
    bool white = true;
    for (int y = std::max(0, y0); y < std::min(h, y1); ++y)
        for (int x = std::max(0, x0); x < std::min(w, x1); ++x) {
            const auto px = *reinterpret_cast<const std::uint32_t*>(data + y * stride + 4 * x);
            white = white && (px & 0xFFFFFF) == 0xFFFFFF;
        }
    cairo_surface_destroy(s);
    return white;
}

json scene(int size, double cell, int years, int seed, double stems_per_ha) {
    json s = test::small_scene(years, "coupled", seed);
    s["terrain"]["generate"]["size"] = size;
    s["terrain"]["generate"]["cell_size_m"] = cell;
    s["vegetation"]["initial"] = {{"random", {{"stems_per_ha", stems_per_ha}, {"max_dbh_m", 0.4}}}};
    return s;
}

} // namespace

TEST_CASE("Run pictures hold their labels, ticks and crowns", "[pictures]") {
    struct Case {
        const char* name;
        json scene;
        int years;
    };
    // Small: 3 years from bare ground, so the basal areas are hundredths of m2/ha (their ticks
    // all read 0.0 before); large: a 160 m x 160 m stand of ~1,000 stems for 2 years (240 m took
    // 30 s under the sanitizers).
    json bare = scene(20, 2.0, 3, 4, 0);
    bare["vegetation"]["initial"] = "bare";
    for (const Case& c : {Case{"small", bare, 3}, Case{"large", scene(80, 2.0, 2, 5, 400), 2}}) {
        CAPTURE(c.name);
        test::TempDir dir;
        const eco::EcoScene sc = eco::load_eco_scene(c.scene, test::data_dir());
        eco::Ecosystem e(sc);
        for (int y = 0; y < c.years; ++y) e.run_year();
        terrain::FigureLog log;
        run::draw_run_pictures(e, dir.path());
        const auto pics = by_picture(log);
        check_files(pics, {dir / "stems.png", dir / "dbh_histogram.png", dir / "stand_history.png",
                           dir / "soil_moisture.png", dir / "surface_water_depth.png"});
        check_picture(pics[0], {"title", "legend", "scale_bar"});
        check_picture(pics[1], {"title", "xtick", "ytick", "xlabel", "ylabel"});
        check_picture(pics[2], {"title", "xtick", "ytick", "xlabel", "ylabel"});
        check_picture(pics[3], {"title", "bar_label", "bar_tick", "scale_bar"});
        check_picture(pics[4], {"title", "scale_bar"});
        // The soil-moisture map says which day it shows.
        bool dated = false;
        for (const auto& t : pics[3])
            dated =
                dated || (t.role == "title" && t.text.find("simulation day") != std::string::npos);
        CHECK(dated);
        // Crowns stay on the map: the strip under it and the gap right of it are white.
        const auto& g = e.plant_grid();
        const double scale = 760.0 / std::max(g.width_m(), g.height_m());
        const int mw = static_cast<int>(std::ceil(g.width_m() * scale));
        const int mh = static_cast<int>(std::ceil(g.height_m() * scale));
        const auto [pw, ph] = test::png_size(dir / "stems.png");
        CHECK(pw >= static_cast<unsigned>(mw + 200));
        CHECK(ph >= static_cast<unsigned>(mh + 40));
        CHECK(white_strip(dir / "stems.png", 0, 30 + mh + 1, mw, 30 + mh + 9));
        CHECK(white_strip(dir / "stems.png", mw + 1, 30, mw + 11, 30 + mh));
    }
}

TEST_CASE("Mobility, traverse and analysis pictures hold their labels and scales",
          "[pictures][slow]") {
    for (const int lines : {10, 200}) {
        CAPTURE(lines);
        test::TempDir dir;
        const eco::EcoScene sc = eco::load_eco_scene(scene(30, 2.0, 1, 3, 800), test::data_dir());
        eco::Ecosystem e(sc);
        e.run_year();
        std::vector<mobility::StandStem> stems;
        const auto rows = eco::rows(e.plants());
        for (const auto& p : rows)
            stems.push_back(mobility::StandStem{p.x_m, p.y_m, p.dbh_m, p.height_m});
        const auto v = mobility::load_vehicle(test::data_dir() / "vehicles/mrzr4.json");
        mobility::StandLinesOptions opt;
        opt.lines = lines;
        opt.length_m = 40;
        const auto m = mobility::analyse_stand(v, stems, sc.hydro.dem, opt);
        terrain::FigureLog log;
        run::draw_mobility_pictures(m, v, sc.hydro.dem, dir.path());
        const auto pics = by_picture(log);
        check_files(pics, {dir / "smg_lines.png", dir / "smg_histogram.png"});
        check_picture(pics[0], {"title", "legend", "bar_label", "bar_tick", "scale_bar"});
        check_picture(pics[1], {"title", "xtick", "ytick", "xlabel", "ylabel"});
    }
    for (const int size : {48, 150}) {
        CAPTURE(size);
        test::TempDir dir;
        const eco::EcoScene sc = eco::load_eco_scene(scene(size, 1.0, 1, 3, 600), test::data_dir());
        const RasterD& dem = sc.hydro.dem;
        {
            terrain::FigureLog log;
            terrain::AnalysisOptions opt;
            const auto a = terrain::analyze_terrain(dem, opt);
            const auto files = terrain::write_analysis_pictures(dem, a, opt, dir.path());
            const auto pics = by_picture(log);
            check_files(pics, files);
            for (const auto& p : pics) check_picture(p, {"title", "scale_bar"});
        }
        const auto v = mobility::load_vehicle(test::data_dir() / "vehicles/husky_a200.json");
        {
            terrain::FigureLog log;
            std::vector<mobility::MissionLine> missions;
            const double w = dem.grid().width_m();
            for (int k = 0; k < 6; ++k)
                missions.push_back(
                    {k, 0.1 * w, (0.1 + 0.15 * k) * w, 0.9 * w, (0.9 - 0.15 * k) * w});
            const auto r = mobility::traverse_missions(v, dem, missions);
            run::draw_traverse_picture(r.missions, r.results, dem, dir / "traverse");
            const auto pics = by_picture(log);
            check_files(pics, {dir / "traverse/missions.png"});
            check_picture(pics[0], {"title", "bar_label", "bar_tick", "scale_bar"});
        }
        {
            terrain::FigureLog log;
            eco::Ecosystem e(sc);
            e.run_year();
            std::vector<mobility::StandStem> stems;
            for (const auto& p : eco::rows(e.plants()))
                stems.push_back(mobility::StandStem{p.x_m, p.y_m, p.dbh_m, p.height_m});
            const mobility::MapPlan plan(v, dem, stems, {}, mobility::MapOptions{});
            const auto m = plan.map({});
            run::draw_mobility_map_pictures(m, dem, dir / "speed.png", dir / "limit.png");
            const double w = dem.grid().width_m();
            const auto route = mobility::fastest_route(m.speed_m_per_s, m.headings_deg,
                                                       {0.1 * w, 0.1 * w}, {0.9 * w, 0.8 * w});
            run::draw_route_picture(m.speed_mean_m_per_s, v.top_speed_m_per_s, route,
                                    dir / "route.png");
            const auto pics = by_picture(log);
            check_files(pics, {dir / "speed.png", dir / "limit.png", dir / "route.png"});
            check_picture(pics[0], {"title", "bar_label", "bar_tick", "scale_bar"});
            check_picture(pics[1], {"title", "legend", "scale_bar"});
            check_picture(pics[2], {"title", "bar_label", "bar_tick", "scale_bar", "note"});
        }
    }
}

TEST_CASE("The export picture holds its titles, scales and crowns", "[pictures][slow]") {
    for (const int size : {20, 150}) {
        CAPTURE(size);
        test::TempDir dir;
        json s = scene(size, 2.0, 2, 6, 500);
        std::ofstream(dir / "scene.json") << s.dump();
        const auto r = test::run(dir, "run scene.json -o run.h5 --no-pictures");
        REQUIRE(r.code == 0);
        const exporter::Scene sc = exporter::load_scene(dir / "run.h5", -1);
        terrain::FigureLog log;
        exporter::draw_export_picture(sc, dir / "picture.png");
        const auto pics = by_picture(log);
        check_files(pics, {dir / "picture.png"});
        check_picture(pics[0], {"title", "note", "scale_bar"});
        // Two scale bars: one under each panel.
        int bars = 0;
        for (const auto& t : pics[0]) bars += t.role == "scale_bar";
        CHECK(bars == 2);
    }
}

TEST_CASE("Ensemble plots hold their labels, ticks at class edges and fits in the frame",
          "[pictures]") {
    for (const double scale : {1e-3, 1e4}) {
        CAPTURE(scale);
        test::TempDir dir;
        terrain::FigureLog log;
        std::vector<run::HistogramSeries> hs(2);
        hs[0].label = "coupled";
        hs[1].label = "light-only";
        for (int k = 0; k < 9; ++k) {
            hs[0].stems_per_ha.push_back(scale * 300 * std::exp(-0.3 * k));
            hs[1].stems_per_ha.push_back(scale * 100 * (k % 3));
        }
        // A fit far above the bars at the first class: the curve is cut at the frame's edge.
        hs[0].fit = true;
        hs[0].intercept = std::log(scale * 5000);
        hs[0].rate_per_cm = 0.1;
        run::draw_histogram_plot(hs, 3.0, "Diameters", "50 members", dir / "h.png");
        std::vector<run::PlotSeries> ps(1);
        ps[0].label = "SMG";
        for (int k = 0; k < 6; ++k) {
            ps[0].x.push_back(10.0 * k);
            ps[0].y.push_back(scale * (5 + k));
            ps[0].lo.push_back(scale * (4 + k));
            ps[0].hi.push_back(scale * (6 + k));
        }
        run::draw_line_plot(ps, "SMG by basal area", "basal area (m2/ha)", "SMG (m/s)",
                            "band: p10-p90", dir / "l.png");
        const auto pics = by_picture(log);
        REQUIRE(pics.size() == 2);
        check_picture(pics[0], {"title", "xtick", "ytick", "xlabel", "ylabel"});
        check_picture(pics[1], {"title", "xtick", "ytick", "xlabel", "ylabel"});
        // The histogram's x ticks sit on class edges (whole multiples of 3 cm).
        for (const auto& t : pics[0])
            if (t.role == "xtick") {
                CAPTURE(t.text);
                const double v = std::stod(t.text);
                CHECK(std::abs(v / 3.0 - std::round(v / 3.0)) < 1e-9);
            }
        // Nothing above the frame (y0 = 40) beside the title (centred at x 405): the fit is
        // clipped.
        CHECK(white_strip(dir / "h.png", 100, 32, 330, 39));
        CHECK(white_strip(dir / "h.png", 480, 32, 700, 39));
    }
}
