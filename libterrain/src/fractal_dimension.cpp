#include "ecoterra/terrain/fractal_dimension.hpp"

#include "ecoterra/terrain/fft.hpp"

#include <Eigen/Dense>

#include <cmath>
#include <numbers>
#include <sstream>

namespace ecoterra::terrain {

namespace {
/// Bins starting below this many coefficients are reported but never fitted.
constexpr int kMinCoefficientsPerBin = 4;
/// The default lowest fitted frequency, in cycles per extent.
constexpr double kDefaultFitMinCyclesPerExtent = 10.0;

/// z minus its least-squares plane, NaN cells set to 0 after removal.
RasterD detrend_plane(const RasterD& z) {
    double s1 = 0, sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0, sz = 0, sxz = 0, syz = 0;
    for (int j = 0; j < z.ny(); ++j)
        for (int i = 0; i < z.nx(); ++i) {
            const double v = z(i, j);
            if (std::isnan(v)) continue;
            s1 += 1;
            sx += i;
            sy += j;
            sxx += double(i) * i;
            syy += double(j) * j;
            sxy += double(i) * j;
            sz += v;
            sxz += i * v;
            syz += j * v;
        }
    Eigen::Matrix3d A;
    A << s1, sx, sy, sx, sxx, sxy, sy, sxy, syy;
    const Eigen::Vector3d c = A.ldlt().solve(Eigen::Vector3d(sz, sxz, syz));
    RasterD r(z.grid(), 0.0);
    for (int j = 0; j < z.ny(); ++j)
        for (int i = 0; i < z.nx(); ++i) {
            const double v = z(i, j);
            r(i, j) = std::isnan(v) ? 0.0 : v - (c[0] + c[1] * i + c[2] * j);
        }
    return r;
}
} // namespace

std::array<double, 3> fit_line(const std::vector<double>& x, const std::vector<double>& y) {
    const double n = static_cast<double>(x.size());
    double mx = 0, my = 0;
    for (std::size_t k = 0; k < x.size(); ++k) mx += x[k], my += y[k];
    mx /= n;
    my /= n;
    double sxx = 0, sxy = 0, syy = 0;
    for (std::size_t k = 0; k < x.size(); ++k) {
        sxx += (x[k] - mx) * (x[k] - mx);
        sxy += (x[k] - mx) * (y[k] - my);
        syy += (y[k] - my) * (y[k] - my);
    }
    const double b = sxx > 0 ? sxy / sxx : 0.0;
    const double r2 = (sxx > 0 && syy > 0) ? sxy * sxy / (sxx * syy) : 1.0;
    return {my - b * mx, b, r2};
}

void PsdOptions::validate() const {
    if (!(bin_ratio >= 1.1) || !std::isfinite(bin_ratio))
        throw InputError("PSD: bin ratio must be >= 1.1");
    if (anchor_cpm < 0 || fit_min_cpm < 0 || fit_max_cpm < 0)
        throw InputError("PSD: frequencies must be >= 0 cycles/m");
}

PsdResult radial_psd(const RasterD& z, const PsdOptions& opt) {
    opt.validate();
    require_valid_cells(z, "PSD");
    const int nx = z.nx(), ny = z.ny();
    if (nx < 8 || ny < 8) throw InputError("PSD: the raster needs at least 8x8 cells");
    const double h = z.cell_size();
    RasterD w = detrend_plane(z);
    std::vector<double> hx(nx), hy(ny);
    for (int i = 0; i < nx; ++i) hx[i] = 0.5 - 0.5 * std::cos(2 * std::numbers::pi * i / (nx - 1));
    for (int j = 0; j < ny; ++j) hy[j] = 0.5 - 0.5 * std::cos(2 * std::numbers::pi * j / (ny - 1));
    // No-data cells enter the transform as zeros (detrend_plane): the window's power is summed
    // over the valid cells only, so that holes and a DEM's outer no-data do not lower the level.
    double u = 0;
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            w(i, j) *= hx[i] * hy[j];
            if (!std::isnan(z(i, j))) u += hx[i] * hx[i] * hy[j] * hy[j];
        }
    u /= double(nx) * ny;
    const HalfSpectrum F = forward_real_fft(w);
    const double wx = z.grid().width_m(), wy = z.grid().height_m();
    const double nyquist = 0.5 / h;
    const double anchor = opt.anchor_cpm > 0 ? opt.anchor_cpm : 1.0 / std::max(wx, wy);
    const double norm = h * h / (double(nx) * ny * u);
    const double lr = std::log(opt.bin_ratio);
    // Bin index n has centre anchor * ratio^n and edges at ratio^(n -+ 1/2).
    const int nmin = static_cast<int>(std::floor(std::log(1.0 / std::max(wx, wy) / anchor) / lr));
    const int nmax = static_cast<int>(std::ceil(std::log(nyquist / anchor) / lr));
    const int nb = nmax - nmin + 1;
    std::vector<double> sum(nb, 0.0);
    std::vector<int> cnt(nb, 0);
    for (int b = 0; b < ny; ++b) {
        const double ky = (b <= ny / 2 ? b : b - ny) / wy;
        for (int a = 0; a < F.nxh(); ++a) {
            if (a == 0 && b == 0) continue;
            const double k = std::hypot(a / wx, ky);
            if (k > nyquist) continue;
            const int n = static_cast<int>(std::floor(std::log(k / anchor) / lr + 0.5)) - nmin;
            if (n < 0 || n >= nb) continue;
            sum[n] += std::norm(F.at(a, b)) * norm;
            ++cnt[n];
        }
    }
    PsdResult res;
    res.fit_min_cpm =
        opt.fit_min_cpm > 0 ? opt.fit_min_cpm : kDefaultFitMinCyclesPerExtent / std::min(wx, wy);
    // By default the fit stops at the last annulus that lies wholly below Nyquist: a truncated
    // annulus averages a line spectrum over too few coefficients and biases the slope.
    res.fit_max_cpm = opt.fit_max_cpm > 0 ? opt.fit_max_cpm : nyquist / std::sqrt(opt.bin_ratio);
    std::vector<double> lx, ly;
    for (int n = 0; n < nb; ++n) {
        if (cnt[n] == 0) continue;
        PsdBin bin;
        bin.k_cpm = anchor * std::exp((n + nmin) * lr);
        bin.power = sum[n] / cnt[n];
        bin.count = cnt[n];
        bin.fitted = cnt[n] >= kMinCoefficientsPerBin && bin.power > 0 &&
                     bin.k_cpm >= res.fit_min_cpm * (1 - 1e-9) &&
                     bin.k_cpm <= res.fit_max_cpm * (1 + 1e-9);
        if (bin.fitted) {
            lx.push_back(std::log10(bin.k_cpm));
            ly.push_back(std::log10(bin.power));
        }
        res.bins.push_back(bin);
    }
    if (lx.size() < 2) {
        std::ostringstream s;
        s << "PSD: fewer than two bins between " << res.fit_min_cpm << " and " << res.fit_max_cpm
          << " cycles/m; widen the fit range";
        throw InputError(s.str());
    }
    const auto [a, b, r2] = fit_line(lx, ly);
    (void)a;
    res.slope = b;
    res.r2 = r2;
    res.dimension = (8.0 + b) / 2.0;
    return res;
}

void FractalDimensionOptions::validate() const {
    if (!(max_lag_fraction > 0 && max_lag_fraction <= 0.5))
        throw InputError("fractal dimension: max lag fraction must be in (0, 0.5]");
    if (!(lag_ratio > 1.0)) throw InputError("fractal dimension: lag ratio must be > 1");
    if (!(tolerance > 0)) throw InputError("fractal dimension: tolerance must be > 0");
    if (min_points < 3) throw InputError("fractal dimension: min points must be >= 3");
}

namespace {

/// Lags in cells, growing by the lag ratio up to the longest allowed.
std::vector<int> dimension_lags(const RasterD& z, const FractalDimensionOptions& opt) {
    const int max_lag = static_cast<int>(opt.max_lag_fraction * std::min(z.nx(), z.ny()));
    std::vector<int> lags;
    for (double l = 1.0; l <= max_lag; l *= opt.lag_ratio) {
        const int li = static_cast<int>(std::lround(l));
        if (lags.empty() || li > lags.back()) lags.push_back(li);
    }
    if (static_cast<int>(lags.size()) < opt.min_points)
        throw InputError("fractal dimension: the raster is too small for " +
                         std::to_string(opt.min_points) + " lags (longest lag " +
                         std::to_string(max_lag) + " cells)");
    return lags;
}

/// The structure function at each lag over the x and y pairs: the root mean square difference
/// (variogram) or the mean absolute difference (madogram).
std::vector<double> structure_function(const RasterD& z, const std::vector<int>& lags,
                                       bool absolute) {
    const int nl = static_cast<int>(lags.size());
    std::vector<double> E(nl, 0.0);
#pragma omp parallel for schedule(dynamic, 1)
    for (int q = 0; q < nl; ++q) {
        const int L = lags[q];
        double s = 0;
        std::int64_t n = 0;
        for (int j = 0; j < z.ny(); ++j) {
            const double* r = z.row(j);
            for (int i = 0; i + L < z.nx(); ++i) {
                const double d = r[i + L] - r[i];
                if (!std::isnan(d)) s += absolute ? std::abs(d) : d * d, ++n;
            }
            if (j + L < z.ny()) {
                const double* r2 = z.row(j + L);
                for (int i = 0; i < z.nx(); ++i) {
                    const double d = r2[i] - r[i];
                    if (!std::isnan(d)) s += absolute ? std::abs(d) : d * d, ++n;
                }
            }
        }
        const double mean = n ? s / static_cast<double>(n) : std::nan("");
        E[q] = absolute ? mean : std::sqrt(mean);
    }
    return E;
}

/// The longest run (in log distance) of consecutive lags within tolerance of its own least-
/// squares line; without one, the fit over the shortest lags (flagged by its r2).
void fit_scaling_range(const std::vector<double>& lx, const std::vector<double>& ly,
                       const FractalDimensionOptions& opt, FractalDimensionResult& res) {
    const int nl = static_cast<int>(lx.size());
    double best_span = -1;
    for (int a = 0; a + opt.min_points <= nl; ++a)
        for (int b = a + opt.min_points - 1; b < nl; ++b) {
            std::vector<double> x(lx.begin() + a, lx.begin() + b + 1);
            std::vector<double> y(ly.begin() + a, ly.begin() + b + 1);
            const auto [c0, c1, r2] = fit_line(x, y);
            double worst = 0;
            for (std::size_t k = 0; k < x.size(); ++k)
                worst = std::max(worst, std::abs(y[k] - (c0 + c1 * x[k])));
            if (worst > opt.tolerance) continue;
            const double span = lx[b] - lx[a];
            if (span > best_span + 1e-12) {
                best_span = span;
                res.first = a;
                res.last = b;
                res.hurst = c1;
                res.r2 = r2;
            }
        }
    if (best_span >= 0) return;
    res.first = 0;
    res.last = opt.min_points - 1;
    std::vector<double> x(lx.begin(), lx.begin() + opt.min_points);
    std::vector<double> y(ly.begin(), ly.begin() + opt.min_points);
    const auto [c0, c1, r2] = fit_line(x, y);
    (void)c0;
    res.hurst = c1;
    res.r2 = r2;
}

} // namespace

FractalDimensionResult fractal_dimension(const RasterD& z, const FractalDimensionOptions& opt) {
    opt.validate();
    require_valid_cells(z, "fractal dimension");
    const std::vector<int> lags = dimension_lags(z, opt);
    const std::vector<double> E =
        structure_function(z, lags, opt.estimator == DimensionEstimator::madogram);
    FractalDimensionResult res;
    std::vector<double> lx, ly;
    for (std::size_t q = 0; q < lags.size(); ++q) {
        res.lag_m.push_back(lags[q] * z.cell_size());
        res.structure_m.push_back(E[q]);
        if (!(E[q] > 0))
            throw InputError("fractal dimension: the surface is flat at lag " +
                             std::to_string(lags[q]) + " cells");
        lx.push_back(std::log10(res.lag_m.back()));
        ly.push_back(std::log10(E[q]));
    }
    fit_scaling_range(lx, ly, opt, res);
    res.range_min_m = res.lag_m[res.first];
    res.range_max_m = res.lag_m[res.last];
    res.dimension = 3.0 - res.hurst;
    return res;
}

} // namespace ecoterra::terrain
