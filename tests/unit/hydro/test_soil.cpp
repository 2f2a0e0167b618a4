#include "ecoterra/hydro/soil.hpp"

#include <catch2/catch.hpp>

#include <set>

using namespace ecoterra;
using namespace ecoterra::hydro;

TEST_CASE("USDA texture classes of the reference test points", "[soil]") {
    struct P {
        double sa, si, c;
        Texture t;
    };
    const P pts[] = {
        // soiltexture README dummy set
        {90, 5, 5, Texture::sand},
        {32, 8, 60, Texture::clay},
        {70, 15, 15, Texture::sandy_loam},
        {70, 25, 5, Texture::sandy_loam},
        {20, 55, 25, Texture::silt_loam},
        {10, 85, 5, Texture::silt},
        {10, 65, 25, Texture::silt_loam},
        {10, 45, 45, Texture::silty_clay},
        {20, 15, 65, Texture::clay},
        {10, 15, 75, Texture::clay},
        {70, 17, 13, Texture::sandy_loam},
        {10, 43, 47, Texture::silty_clay},
        // boundary cases
        {85, 10, 5, Texture::loamy_sand},
        {85, 15, 0, Texture::loamy_sand},
        {70, 30, 0, Texture::sandy_loam},
        {52, 28, 20, Texture::loam},
        {45, 35, 20, Texture::loam},
        {20, 50, 30, Texture::silty_clay_loam},
        {45, 20, 35, Texture::clay_loam},
        {45, 15, 40, Texture::clay},
        {20, 40, 40, Texture::silty_clay},
        {0, 80, 20, Texture::silt_loam},
        {0, 88, 12, Texture::silt_loam},
        {50, 50, 0, Texture::silt_loam},
        {23, 50, 27, Texture::clay_loam},
        {60, 10, 30, Texture::sandy_clay_loam},
        {0, 100, 0, Texture::silt},
    };
    for (const auto& p : pts) {
        CAPTURE(p.sa, p.si, p.c);
        CHECK(texture_name(classify_texture(p.sa, p.si, p.c)) == texture_name(p.t));
    }
}

TEST_CASE("Every composition of the triangle has a class", "[soil]") {
    int n = 0;
    for (double sa = 0; sa <= 100; sa += 0.5)
        for (double c = 0; sa + c <= 100; c += 0.5) {
            CHECK_NOTHROW(classify_texture(sa, 100 - sa - c, c));
            ++n;
        }
    CHECK(n > 20000);
}

TEST_CASE("Rawls 1982 class properties and the silt substitute", "[soil]") {
    const auto loam = class_properties(Texture::loam);
    CHECK(loam.porosity == Approx(0.463));
    CHECK(loam.field_capacity == Approx(0.270));
    CHECK(loam.wilting_point == Approx(0.117));
    CHECK(loam.ksat_m_per_s == Approx(1.32e-2 / 3600));
    const auto silt = class_properties(Texture::silt);
    CHECK(silt.source.find("schaake") != std::string::npos);
    for (int k = 0; k < kTextureCount; ++k) {
        const auto p = class_properties(static_cast<Texture>(k));
        CHECK(p.wilting_point < p.field_capacity);
        CHECK(p.field_capacity < p.porosity);
        CHECK(p.ksat_m_per_s > 0);
    }
    CHECK(class_properties(Texture::sand).ksat_m_per_s >
          class_properties(Texture::clay).ksat_m_per_s);
}

TEST_CASE("Saxton & Rawls 2006 reproduces the reference vectors", "[soil][verification]") {
    struct V {
        double s, c, wp, fc, sat, ks_mm_h;
    };
    const V vs[] = {{88, 5, 0.050, 0.103, 0.462, 108.1}, {80, 5, 0.051, 0.120, 0.460, 96.7},
                    {65, 10, 0.081, 0.179, 0.450, 50.3}, {40, 20, 0.137, 0.280, 0.459, 15.5},
                    {20, 15, 0.110, 0.305, 0.479, 16.1}, {10, 5, 0.057, 0.305, 0.479, 22.0},
                    {60, 25, 0.166, 0.267, 0.434, 11.3}, {30, 35, 0.218, 0.358, 0.477, 4.3},
                    {10, 35, 0.215, 0.382, 0.511, 5.7},  {10, 45, 0.268, 0.409, 0.523, 3.7},
                    {50, 40, 0.249, 0.361, 0.444, 1.4},  {25, 50, 0.298, 0.421, 0.498, 1.1}};
    for (const auto& v : vs) {
        CAPTURE(v.s, v.c);
        const auto p = saxton_rawls_2006(v.s, v.c, 2.5);
        CHECK(p.wilting_point == Approx(v.wp).margin(0.0006));
        CHECK(p.field_capacity == Approx(v.fc).margin(0.0006));
        CHECK(p.porosity == Approx(v.sat).margin(0.0006));
        CHECK(p.ksat_m_per_s * 3.6e6 == Approx(v.ks_mm_h).margin(0.06));
    }
}

TEST_CASE("Soil input is checked", "[soil][errors]") {
    CHECK_THROWS_WITH((SoilComposition{40, 40, 30, 6.5, {}}.validate("soil")),
                      Catch::Contains("110"));
    CHECK_THROWS_WITH((SoilComposition{-5, 85, 20, 6.5, {}}.validate("soil")),
                      Catch::Contains("sand") && Catch::Contains("-5"));
    CHECK_THROWS_WITH((SoilComposition{40, 40, 20, 15, {}}.validate("soil")),
                      Catch::Contains("pH"));
    CHECK_NOTHROW(SoilComposition{40, 41, 20, 7, {}}.validate("soil")); // within 2 %
    CHECK(parse_texture("silty clay loam") == Texture::silty_clay_loam);
    CHECK_FALSE(parse_texture("peat"));
}

TEST_CASE("Random soil maps are smooth, valid and reproducible", "[soil]") {
    const GridSpec g{64, 48, 2.0, 0, 0};
    RandomSoilParams p;
    p.mean = SoilComposition{20, 60, 20, 6.0, {}};
    const SoilMap a = random_soil(g, p, 5), b = random_soil(g, p, 5), c = random_soil(g, p, 6);
    CHECK((a.sand_pct.array() == b.sand_pct.array()).all());
    CHECK_FALSE((a.sand_pct.array() == c.sand_pct.array()).all());
    for (int j = 0; j < g.ny; ++j)
        for (int i = 0; i < g.nx; ++i) {
            CHECK(a.sand_pct(i, j) + a.silt_pct(i, j) + a.clay_pct(i, j) == Approx(100.0));
            CHECK(a.wilting_point(i, j) < a.field_capacity(i, j));
        }
    // Several texture classes appear.
    std::set<int> classes;
    for (int k = 0; k < a.texture.size(); ++k) classes.insert(a.texture.data()[k]);
    CHECK(classes.size() >= 2);
}
