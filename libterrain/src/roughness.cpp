#include "ecoterra/terrain/roughness.hpp"

#include "ecoterra/terrain/filters.hpp"

#include <cmath>
#include <numbers>
#include <sstream>

namespace ecoterra::terrain {

namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

/// Horn (1981) gradients (dz/dx east, dz/dy north) at (i, j); edges replicate, NaN neighbours
/// take the centre value.
std::array<double, 2> horn_gradient(const RasterD& z, int i, int j) {
    const double c = z(i, j);
    auto at = [&](int di, int dj) {
        const int a = std::clamp(i + di, 0, z.nx() - 1);
        const int b = std::clamp(j + dj, 0, z.ny() - 1);
        const double v = z(a, b);
        return std::isnan(v) ? c : v;
    };
    const double h = z.cell_size();
    const double dzdx =
        ((at(1, 1) + 2 * at(1, 0) + at(1, -1)) - (at(-1, 1) + 2 * at(-1, 0) + at(-1, -1))) /
        (8 * h);
    const double dzdy =
        ((at(-1, 1) + 2 * at(0, 1) + at(1, 1)) - (at(-1, -1) + 2 * at(0, -1) + at(1, -1))) /
        (8 * h);
    return {dzdx, dzdy};
}

} // namespace

double rms_about_zero(const RasterD& r, int margin) {
    // Leave out the edge cells where a filter window was truncated, if enough cells remain.
    if (2 * margin >= r.nx() || 2 * margin >= r.ny()) margin = 0;
    double ss = 0.0;
    std::int64_t n = 0;
    for (int j = margin; j < r.ny() - margin; ++j)
        for (int i = margin; i < r.nx() - margin; ++i) {
            const double v = r(i, j);
            if (std::isnan(v)) continue;
            ss += v * v;
            ++n;
        }
    return n ? std::sqrt(ss / static_cast<double>(n)) : std::nan("");
}

RmsResult rms_roughness(const RasterD& z, const RmsOptions& opt) {
    require_valid_cells(z, "RMS roughness");
    if (!(opt.detrend_window_m > 0.0))
        throw InputError("RMS roughness: detrend window must be > 0 m");
    if (!(opt.band_long_cutoff_m > 0.0))
        throw InputError("RMS roughness: long-wavelength cutoff must be > 0 m");
    if (opt.band_short_cutoff_m < 0.0 || opt.band_short_cutoff_m >= opt.band_long_cutoff_m)
        throw InputError("RMS roughness: short-wavelength cutoff must be in [0, long cutoff)");
    RmsResult r;
    r.rms_m = stats(z).stddev;

    RasterD local = box_mean(z, opt.detrend_window_m);
    RasterD resid(z.grid());
    resid.array() = z.array() - local.array();
    r.rms_detrended_m = rms_about_zero(
        resid, static_cast<int>(std::ceil(0.5 * opt.detrend_window_m / z.cell_size())));

    const double sigma_long = gaussian_sigma_for_cutoff(opt.band_long_cutoff_m);
    RasterD longwave = gaussian_filter(z, sigma_long);
    RasterD band(z.grid());
    if (opt.band_short_cutoff_m > 0.0) {
        RasterD smooth = gaussian_filter(z, gaussian_sigma_for_cutoff(opt.band_short_cutoff_m));
        band.array() = smooth.array() - longwave.array();
    } else {
        band.array() = z.array() - longwave.array();
    }
    r.rms_band_limited_m = rms_about_zero(
        band, static_cast<int>(std::ceil(gaussian_kernel_radius_m(sigma_long) / z.cell_size())));
    return r;
}

RasterD max_gradient_map(const RasterD& z) {
    RasterD g(z.grid(), 0.0);
    const double h = z.cell_size();
    const double diag = h * std::numbers::sqrt2;
#pragma omp parallel for schedule(static)
    for (int j = 0; j < z.ny(); ++j)
        for (int i = 0; i < z.nx(); ++i) {
            const double c = z(i, j);
            if (std::isnan(c)) {
                g(i, j) = std::nan("");
                continue;
            }
            double m = 0.0;
            for (const auto& o : kMooreOffsets) {
                const int a = i + o[0], b = j + o[1];
                if (!z.grid().contains(a, b)) continue;
                const double v = z(a, b);
                if (std::isnan(v)) continue;
                const double d = (o[0] != 0 && o[1] != 0) ? diag : h;
                m = std::max(m, std::abs(c - v) / d);
            }
            g(i, j) = m;
        }
    return g;
}

void ClassThresholds::validate() const {
    if (!(low >= 0.0) || !(high > low) || !std::isfinite(high)) {
        std::ostringstream s;
        s << "roughness class thresholds must satisfy 0 <= low < high, got low=" << low
          << " high=" << high;
        throw InputError(s.str());
    }
}

RasterU8 classify_gradient(const RasterD& g, const ClassThresholds& t) {
    t.validate();
    RasterU8 c(g.grid(), 0);
    for (std::int64_t k = 0; k < g.size(); ++k) {
        const double v = g.data()[k];
        RoughnessClass cl = std::isnan(v) ? RoughnessClass::nodata
                            : v <= t.low  ? RoughnessClass::low
                            : v <= t.high ? RoughnessClass::semi
                                          : RoughnessClass::high;
        c.data()[k] = static_cast<std::uint8_t>(cl);
    }
    return c;
}

ClassAreas class_areas(const RasterU8& classes, double border_m) {
    if (!(border_m >= 0.0)) throw InputError("class areas: border must be >= 0 m");
    const int b = static_cast<int>(std::ceil(border_m / classes.cell_size() - 1e-9));
    std::int64_t n[3] = {0, 0, 0};
    for (int j = b; j < classes.ny() - b; ++j)
        for (int i = b; i < classes.nx() - b; ++i) {
            const std::uint8_t v = classes(i, j);
            if (v < 3) ++n[v];
        }
    ClassAreas a;
    a.cells = n[0] + n[1] + n[2];
    if (a.cells == 0)
        throw InputError("class areas: no valid cell remains inside the " +
                         std::to_string(border_m) + " m border");
    const double tot = static_cast<double>(a.cells);
    a.low_pct = 100.0 * n[0] / tot;
    a.semi_pct = 100.0 * n[1] / tot;
    a.high_pct = 100.0 * n[2] / tot;
    return a;
}

RasterU8 close_classes(const RasterU8& classes, double radius_m) {
    if (!(radius_m >= 0.0)) throw InputError("closing: disk radius must be >= 0 m");
    // No-data cells (outside a DEM's valid area, holes) take no part: they neither spread a class
    // nor are filled, and stay no-data, so they count in no class after the closing either.
    constexpr auto nodata = static_cast<std::uint8_t>(RoughnessClass::nodata);
    RasterU8 c = classes;
    for (std::int64_t k = 0; k < c.size(); ++k)
        if (c.data()[k] > 2) c.data()[k] = nodata;
    return close_disk(c, radius_m / classes.cell_size(), nodata);
}

SlopeAspect slope_aspect(const RasterD& z) {
    SlopeAspect s{RasterD(z.grid()), RasterD(z.grid()), RasterD(z.grid())};
#pragma omp parallel for schedule(static)
    for (int j = 0; j < z.ny(); ++j)
        for (int i = 0; i < z.nx(); ++i) {
            if (std::isnan(z(i, j))) {
                s.slope(i, j) = s.slope_deg(i, j) = s.aspect_deg(i, j) = std::nan("");
                continue;
            }
            const auto [gx, gy] = horn_gradient(z, i, j);
            const double m = std::hypot(gx, gy);
            s.slope(i, j) = m;
            s.slope_deg(i, j) = std::atan(m) * kDegPerRad;
            if (m == 0.0) {
                s.aspect_deg(i, j) = std::nan("");
            } else {
                double a = std::atan2(-gx, -gy) * kDegPerRad;
                s.aspect_deg(i, j) = a < 0 ? a + 360.0 : a;
            }
        }
    return s;
}

RasterD hillshade(const RasterD& z, double azimuth_deg, double altitude_deg, double z_factor) {
    RasterD h(z.grid(), 0.0);
    const double az = azimuth_deg / kDegPerRad, alt = altitude_deg / kDegPerRad;
    const double lx = std::cos(alt) * std::sin(az), ly = std::cos(alt) * std::cos(az),
                 lz = std::sin(alt);
#pragma omp parallel for schedule(static)
    for (int j = 0; j < z.ny(); ++j)
        for (int i = 0; i < z.nx(); ++i) {
            if (std::isnan(z(i, j))) {
                h(i, j) = std::nan("");
                continue;
            }
            auto [gx, gy] = horn_gradient(z, i, j);
            gx *= z_factor;
            gy *= z_factor;
            const double norm = std::sqrt(gx * gx + gy * gy + 1.0);
            h(i, j) = std::max(0.0, (-gx * lx - gy * ly + lz) / norm);
        }
    return h;
}

} // namespace ecoterra::terrain
