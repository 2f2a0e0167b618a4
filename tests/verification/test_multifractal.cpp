// The multifractal combination of paper 000 and its roughness-class trend.
#include "ecoterra/terrain/roughness.hpp"
#include "ecoterra/terrain/weierstrass.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

using namespace ecoterra;
using namespace ecoterra::terrain;

TEST_CASE("Multifractal layers are zero-mean in [-1, 1] and the result spans the relief",
          "[multifractal]") {
    const GridSpec g{200, 160, 0.05, 0, 0};
    MultifractalParams p = majhor2023_params(2.6);
    p.relief_m = 4.0;
    p.base_elevation_m = 100.0;
    const auto r = multifractal_generate(g, p, 3, true);
    for (const auto& layer : r.layers) {
        CHECK(layer.array().mean() == Approx(0.0).margin(1e-12));
        CHECK(layer.array().abs().maxCoeff() == Approx(1.0));
    }
    CHECK(r.z.array().minCoeff() == Approx(100.0));
    CHECK(r.z.array().maxCoeff() == Approx(104.0));
    // The result is the product of the layers, affinely mapped.
    const RasterD::Array prod = r.layers[0].array() * r.layers[1].array() * r.layers[2].array();
    const double lo = prod.minCoeff(), hi = prod.maxCoeff();
    CHECK(r.z(17, 23) == Approx(100.0 + 4.0 * (prod(23, 17) - lo) / (hi - lo)));
}

TEST_CASE("Multifractal layers scaled to [0, 1] keep the product positive, without the flat "
          "bands where zero-mean layers cross zero",
          "[multifractal]") {
    const GridSpec g{200, 160, 0.05, 0, 0};
    MultifractalParams p = majhor2023_params(2.6);
    p.relief_m = 4.0;
    const auto zero = multifractal_generate(g, p, 3, true);
    p.layer_scaling = LayerScaling::unit_interval;
    const auto unit = multifractal_generate(g, p, 3, true);
    for (std::size_t k = 0; k < 3; ++k) {
        CHECK(unit.layers[k].array().minCoeff() == Approx(0.0).margin(1e-12));
        CHECK(unit.layers[k].array().maxCoeff() == Approx(1.0));
        // The same layer, affinely mapped: the zero-mean one's shape.
        const auto& a = zero.layers[k].array();
        const double lo = a.minCoeff(), hi = a.maxCoeff();
        CHECK(unit.layers[k](17, 23) == Approx((zero.layers[k](17, 23) - lo) / (hi - lo)));
    }
    const RasterD::Array prod =
        unit.layers[0].array() * unit.layers[1].array() * unit.layers[2].array();
    CHECK(prod.minCoeff() >= 0.0);
    const double lo = prod.minCoeff(), hi = prod.maxCoeff();
    CHECK(unit.z(40, 90) == Approx(4.0 * (prod(90, 40) - lo) / (hi - lo)));
    // Flat bands: cells whose product is within 1e-4 of the relief's value at a layer's zero.
    // Zero-mean layers pin the product to 0 along every layer's zero crossing; [0, 1] layers
    // only at each layer's single minimum.
    auto near_zero = [](const RasterD::Array& a) {
        const double span = a.maxCoeff() - a.minCoeff();
        return (a.abs() < 1e-4 * span).count();
    };
    const RasterD::Array zprod =
        zero.layers[0].array() * zero.layers[1].array() * zero.layers[2].array();
    CHECK(near_zero(zprod) > 10 * std::max<Eigen::Index>(near_zero(prod), 1));
}

TEST_CASE("Multifractal parameters are checked", "[multifractal][errors]") {
    MultifractalParams p;
    p.relief_m = 0;
    CHECK_THROWS_WITH(validate(p), Catch::Contains("relief"));
    p = MultifractalParams{};
    p.filter_sigma_m = -1;
    CHECK_THROWS_WITH(validate(p), Catch::Contains("sigma"));
    p = MultifractalParams{};
    p.high.D = 2.0;
    CHECK_THROWS_WITH(validate(p), Catch::Contains("(2, 3)"));
    p = MultifractalParams{};
    p.layer_offset = std::nan("");
    CHECK_THROWS_WITH(validate(p), Catch::Contains("layer offset"));
}

TEST_CASE("A layer offset shifts each rescaled layer before the product", "[multifractal]") {
    const GridSpec g{120, 100, 0.05, 0, 0};
    MultifractalParams p = majhor2023_params(2.45);
    const auto zero = multifractal_generate(g, p, 5, true);
    for (const double c : {0.5, 1.0, 2.5}) {
        p.layer_offset = c;
        const auto r = multifractal_generate(g, p, 5, true);
        for (std::size_t k = 0; k < 3; ++k) {
            CHECK(r.layers[k].array().mean() == Approx(c).margin(1e-12));
            CHECK(r.layers[k](30, 40) == Approx(zero.layers[k](30, 40) + c).margin(1e-15));
        }
        // Above 1 no layer crosses zero, so the product has a single sign.
        const RasterD::Array prod = r.layers[0].array() * r.layers[1].array() * r.layers[2].array();
        if (c > 1) CHECK(prod.minCoeff() > 0);
        const double lo = prod.minCoeff(), hi = prod.maxCoeff();
        CHECK(r.z(55, 61) == Approx(p.relief_m * (prod(61, 55) - lo) / (hi - lo)));
    }
}

TEST_CASE("majhor2023: rougher high-frequency layers shrink the low-roughness area",
          "[multifractal][verification][slow]") {
    // Paper 000 s3.1: as D_high rises 2.3 -> 2.45 -> 2.6 the median low-roughness area falls and
    // the semi and high areas grow. Median over 3 seeds on the paper's grid.
    const GridSpec g = majhor2023_grid();
    auto median_areas = [&](double d) {
        std::vector<double> lo, se, hi;
        for (int s = 1; s <= 3; ++s) {
            const auto z = multifractal_generate(g, majhor2023_params(d), s).z;
            const auto a = class_areas(classify_gradient(max_gradient_map(z)), 5.0);
            lo.push_back(a.low_pct);
            se.push_back(a.semi_pct);
            hi.push_back(a.high_pct);
        }
        for (auto* v : {&lo, &se, &hi}) std::sort(v->begin(), v->end());
        return std::array<double, 3>{lo[1], se[1], hi[1]};
    };
    const auto a = median_areas(2.3), b = median_areas(2.45), c = median_areas(2.6);
    CAPTURE(a, b, c);
    CHECK(a[0] > b[0]);
    CHECK(b[0] > c[0]);
    CHECK(a[1] < c[1]);
    CHECK(a[2] < c[2]);
    // Large semi and high areas (the paper's terrain was hard to cross): together > 20 %.
    CHECK(b[1] + b[2] > 20.0);
    // The total fall in the low area is of the paper's order (13.8 + 7.16 = 21 points).
    CHECK(a[0] - c[0] > 5.0);
    CHECK(a[0] - c[0] < 40.0);
}
