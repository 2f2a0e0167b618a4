#include "ecoterra/terrain/filters.hpp"

#include <cmath>
#include <numbers>
#include <vector>

namespace ecoterra::terrain {

namespace {

/// Truncation of the Gaussian kernel, in standard deviations.
constexpr double kGaussianTruncation = 4.0;

std::vector<double> gaussian_kernel(double sigma_px) {
    const int radius = std::max(1, static_cast<int>(std::ceil(kGaussianTruncation * sigma_px)));
    std::vector<double> k(2 * radius + 1);
    for (int d = -radius; d <= radius; ++d)
        k[d + radius] = std::exp(-0.5 * (d / sigma_px) * (d / sigma_px));
    return k;
}

/// Separable normalised convolution of values (NaN = missing) with a symmetric kernel.
RasterD separable_normalised(const RasterD& r, const std::vector<double>& kx,
                             const std::vector<double>& ky) {
    const int nx = r.nx(), ny = r.ny();
    const int rx = static_cast<int>(kx.size() / 2), ry = static_cast<int>(ky.size() / 2);
    RasterD num(r.grid(), 0.0), den(r.grid(), 0.0);
#pragma omp parallel for schedule(static)
    for (int j = 0; j < ny; ++j) {
        const double* in = r.row(j);
        double* on = num.row(j);
        double* od = den.row(j);
        for (int i = 0; i < nx; ++i) {
            double s = 0.0, w = 0.0;
            const int a = std::max(0, i - rx), b = std::min(nx - 1, i + rx);
            for (int q = a; q <= b; ++q) {
                const double v = in[q];
                if (std::isnan(v)) continue;
                const double kw = kx[q - i + rx];
                s += kw * v;
                w += kw;
            }
            on[i] = s;
            od[i] = w;
        }
    }
    RasterD out(r.grid(), 0.0);
#pragma omp parallel for schedule(static)
    for (int j = 0; j < ny; ++j) {
        const int a = std::max(0, j - ry), b = std::min(ny - 1, j + ry);
        std::vector<double> s(nx, 0.0), w(nx, 0.0);
        for (int q = a; q <= b; ++q) {
            const double kw = ky[q - j + ry];
            const double* pn = num.row(q);
            const double* pd = den.row(q);
            for (int i = 0; i < nx; ++i) {
                s[i] += kw * pn[i];
                w[i] += kw * pd[i];
            }
        }
        double* o = out.row(j);
        const double* in = r.row(j);
        for (int i = 0; i < nx; ++i)
            o[i] = (std::isnan(in[i]) || w[i] <= 0.0) ? std::nan("") : s[i] / w[i];
    }
    return out;
}

/// Dilation (max) or erosion (min) over a disk; cells holding `nodata` (if 0..255) neither take
/// part as neighbours nor change: they stay `nodata`, as cells outside the grid would.
template <bool Dilate>
RasterU8 morph(const RasterU8& r, double radius_px, int nodata) {
    const auto offsets = disk_offsets(radius_px);
    RasterU8 out(r.grid(), 0);
    const int nx = r.nx(), ny = r.ny();
#pragma omp parallel for schedule(static)
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            std::uint8_t v = r(i, j);
            if (v == nodata) {
                out(i, j) = v;
                continue;
            }
            for (const auto& o : offsets) {
                const int a = i + o[0], b = j + o[1];
                if (a < 0 || b < 0 || a >= nx || b >= ny || r(a, b) == nodata) continue;
                v = Dilate ? std::max(v, r(a, b)) : std::min(v, r(a, b));
            }
            out(i, j) = v;
        }
    return out;
}

} // namespace

RasterD gaussian_filter(const RasterD& r, double sigma_m) {
    if (!(sigma_m > 0.0)) return r;
    const auto k = gaussian_kernel(sigma_m / r.cell_size());
    return separable_normalised(r, k, k);
}

double gaussian_kernel_radius_m(double sigma_m) {
    return kGaussianTruncation * sigma_m;
}

RasterD box_mean(const RasterD& r, double window_m) {
    int w = static_cast<int>(std::lround(window_m / r.cell_size()));
    if (w % 2 == 0) ++w;
    w = std::max(w, 1);
    const std::vector<double> k(static_cast<std::size_t>(w), 1.0);
    return separable_normalised(r, k, k);
}

double gaussian_sigma_for_cutoff(double cutoff_m) {
    return cutoff_m * std::sqrt(std::numbers::ln2 / 2.0) / std::numbers::pi;
}

std::vector<std::array<int, 2>> disk_offsets(double radius_px) {
    std::vector<std::array<int, 2>> o;
    const int r = static_cast<int>(std::floor(radius_px));
    for (int dj = -r; dj <= r; ++dj)
        for (int di = -r; di <= r; ++di)
            if (di * di + dj * dj <= radius_px * radius_px) o.push_back({di, dj});
    return o;
}

RasterU8 dilate_disk(const RasterU8& r, double radius_px, int nodata) {
    return morph<true>(r, radius_px, nodata);
}
RasterU8 erode_disk(const RasterU8& r, double radius_px, int nodata) {
    return morph<false>(r, radius_px, nodata);
}
RasterU8 close_disk(const RasterU8& r, double radius_px, int nodata) {
    return erode_disk(dilate_disk(r, radius_px, nodata), radius_px, nodata);
}

} // namespace ecoterra::terrain
