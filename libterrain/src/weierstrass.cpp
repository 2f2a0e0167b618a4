#include "ecoterra/terrain/weierstrass.hpp"

#include "ecoterra/progress.hpp"

#include "ecoterra/random.hpp"
#include "ecoterra/terrain/filters.hpp"

#include <Eigen/Dense>

#include <atomic>
#include <cmath>
#include <numbers>
#include <sstream>

namespace ecoterra::terrain {

namespace {

constexpr double kPi = std::numbers::pi;
/// Terms whose amplitude is below this fraction of the n = 1 term cannot change a double sum.
constexpr double kNegligibleAmplitude = 1e-17;
/// Rows of the output computed by one task; fixed so results do not depend on the thread count.
constexpr int kRowBlock = 32;

int resolve_nmax(const GridSpec& grid, const WMParams& p, std::vector<std::string>& warnings) {
    const int nyq = wm_nyquist_nmax(p.L_m, p.gamma, grid.cell_size_m);
    if (p.n_max <= 0) {
        if (nyq < 1)
            throw InputError("W-M: the cell size " + format_number(grid.cell_size_m) +
                             " m is too coarse for L = " + format_number(p.L_m) +
                             " m: even the n = 1 term is above the Nyquist frequency");
        return nyq;
    }
    if (p.n_max > nyq)
        warnings.push_back("W-M: n_max = " + std::to_string(p.n_max) +
                           " is above the Nyquist cutoff " + std::to_string(nyq) + " for cell " +
                           format_number(grid.cell_size_m) + " m; terms n > " +
                           std::to_string(nyq) + " alias into pseudo-noise on the grid");
    return p.n_max;
}

} // namespace

void validate(const WMParams& p) {
    if (p.M < 1) throw InputError("W-M: M (ridges) must be >= 1, got " + std::to_string(p.M));
    if (p.n_max < 0)
        throw InputError("W-M: n_max must be >= 1 (or 0 for the Nyquist cutoff), got " +
                         std::to_string(p.n_max));
    if (!(p.gamma > 1.0) || !std::isfinite(p.gamma))
        throw InputError("W-M: gamma must be > 1, got " + format_number(p.gamma));
    if (!(p.D > 2.0 && p.D < 3.0))
        throw InputError("W-M: fractal dimension D must be in (2, 3), got " + format_number(p.D));
    if (!(p.L_m > 0.0) || !std::isfinite(p.L_m))
        throw InputError("W-M: L must be > 0 m, got " + format_number(p.L_m));
    if (!(p.G_m > 0.0) || !std::isfinite(p.G_m))
        throw InputError("W-M: G must be > 0 m, got " + format_number(p.G_m));
    if (!(p.phase_max_rad > 0.0 && p.phase_max_rad <= 2.0 * kPi))
        throw InputError("W-M: the phase interval must be in (0, 2 pi] rad, got " +
                         format_number(p.phase_max_rad));
}

double wm_amplitude(const WMParams& p) {
    return p.L_m * std::pow(p.G_m / p.L_m, p.D - 2.0) * std::sqrt(std::log(p.gamma) / p.M);
}

int wm_nyquist_nmax(double L_m, double gamma, double cell_size_m) {
    return static_cast<int>(std::floor(std::log(L_m / (2.0 * cell_size_m)) / std::log(gamma)));
}

Eigen::MatrixXd wm_random_phases(int M, int n_max, std::uint64_t seed, std::uint64_t stream,
                                 double phase_max_rad) {
    Rng rng(seed, "terrain.wm.phases", stream);
    Eigen::MatrixXd phi(M, n_max);
    for (int m = 0; m < M; ++m)
        for (int n = 0; n < n_max; ++n) phi(m, n) = rng.uniform(0.0, phase_max_rad);
    return phi;
}

double wm_evaluate_point(const WMParams& p, const Eigen::MatrixXd& phases, double x, double y) {
    validate(p);
    if (phases.rows() != p.M || phases.cols() < 1)
        throw InputError("W-M: phase matrix must be M x n_max");
    const int n_max = static_cast<int>(phases.cols());
    const double A = wm_amplitude(p);
    double z = 0.0;
    for (int m = 1; m <= p.M; ++m) {
        const double th = kPi * m / p.M;
        const double proj = x * std::cos(th) + y * std::sin(th);
        for (int n = 1; n <= n_max; ++n) {
            const double phi = phases(m - 1, n - 1);
            const double k = 2.0 * kPi * std::pow(p.gamma, n) / p.L_m;
            z += std::pow(p.gamma, (p.D - 3.0) * n) * (std::cos(phi) - std::cos(k * proj + phi));
        }
    }
    return A * z;
}

WMResult wm_generate(const GridSpec& grid, const WMParams& p, const Eigen::MatrixXd& phases) {
    validate(p);
    grid.validate("W-M grid");
    if (phases.rows() != p.M)
        throw InputError("W-M: phase matrix has " + std::to_string(phases.rows()) +
                         " rows, expected M = " + std::to_string(p.M));
    WMResult res;
    WMParams q = p;
    q.n_max = static_cast<int>(phases.cols());
    const int n_max = resolve_nmax(grid, q, res.warnings);
    res.n_max = n_max;

    // Terms that survive: amplitude gamma^{(D-3)n} relative to n = 1.
    int n_used = n_max;
    for (int n = 1; n <= n_max; ++n)
        if (std::pow(p.gamma, (p.D - 3.0) * (n - 1)) < kNegligibleAmplitude) {
            n_used = n - 1;
            break;
        }
    res.terms_negligible = p.M * (n_max - n_used);
    if (res.terms_negligible > 0)
        res.warnings.push_back("W-M: " + std::to_string(res.terms_negligible) + " terms with n > " +
                               std::to_string(n_used) +
                               " are below 1e-17 of the n = 1 amplitude and were skipped");
    const int T = p.M * n_used;
    res.terms_evaluated = T;

    const int nx = grid.nx, ny = grid.ny;
    ensure_fits_in_memory(grid.size() + 2 * static_cast<std::int64_t>(T) * (nx + ny), 8.0,
                          "W-M grid " + std::to_string(nx) + "x" + std::to_string(ny));
    const double A = wm_amplitude(p);

    // U: per-column (x) tables, V: per-row (y) tables. Z = C - V U^T.
    Eigen::MatrixXd U(nx, 2 * T), V(ny, 2 * T);
    double C = 0.0;
    std::vector<double> amp(T), kx(T), ky(T), ph(T);
    for (int m = 1; m <= p.M; ++m) {
        const double th = kPi * m / p.M;
        for (int n = 1; n <= n_used; ++n) {
            const int t = (m - 1) * n_used + (n - 1);
            const double k = 2.0 * kPi * std::pow(p.gamma, n) / p.L_m;
            amp[t] = A * std::pow(p.gamma, (p.D - 3.0) * n);
            kx[t] = k * std::cos(th);
            ky[t] = k * std::sin(th);
            ph[t] = phases(m - 1, n - 1);
            C += amp[t] * std::cos(ph[t]);
        }
    }
#pragma omp parallel for schedule(static)
    for (int t = 0; t < T; ++t) {
        for (int i = 0; i < nx; ++i) {
            const double a = std::fmod(kx[t] * grid.x_of(i), 2.0 * kPi) + ph[t];
            U(i, 2 * t) = amp[t] * std::cos(a);
            U(i, 2 * t + 1) = -amp[t] * std::sin(a);
        }
        for (int j = 0; j < ny; ++j) {
            const double b = std::fmod(ky[t] * grid.y_of(j), 2.0 * kPi);
            V(j, 2 * t) = std::cos(b);
            V(j, 2 * t + 1) = std::sin(b);
        }
    }

    res.z = RasterD(grid, 0.0);
    const Eigen::MatrixXd Ut = U.transpose();
    const int blocks = (ny + kRowBlock - 1) / kRowBlock;
    std::atomic<int> done{0};
#pragma omp parallel for schedule(dynamic, 1)
    for (int b = 0; b < blocks; ++b) {
        const int j0 = b * kRowBlock;
        const int h = std::min(kRowBlock, ny - j0);
        Eigen::MatrixXd block = V.middleRows(j0, h) * Ut; // h x nx
        for (int j = 0; j < h; ++j) {
            double* row = res.z.row(j0 + j);
            for (int i = 0; i < nx; ++i) row[i] = C - block(j, i);
        }
        // Only the thread that asked for progress reports it (the others' calls do nothing).
        report_progress(static_cast<double>(++done) / blocks);
    }
    return res;
}

WMResult wm_generate(const GridSpec& grid, const WMParams& p, std::uint64_t seed,
                     std::uint64_t stream) {
    validate(p);
    grid.validate("W-M grid");
    std::vector<std::string> warnings;
    const int n_max = resolve_nmax(grid, p, warnings);
    return wm_generate(grid, p, wm_random_phases(p.M, n_max, seed, stream, p.phase_max_rad));
}

void validate(const MultifractalParams& p) {
    validate(p.low);
    validate(p.mid);
    validate(p.high);
    if (!(p.filter_sigma_m >= 0.0) || !std::isfinite(p.filter_sigma_m))
        throw InputError("multifractal: filter sigma must be >= 0 m, got " +
                         format_number(p.filter_sigma_m));
    if (!(p.relief_m > 0.0) || !std::isfinite(p.relief_m))
        throw InputError("multifractal: relief must be > 0 m, got " + format_number(p.relief_m));
    if (!std::isfinite(p.base_elevation_m))
        throw InputError("multifractal: base elevation must be finite");
    if (!std::isfinite(p.layer_offset))
        throw InputError("multifractal: layer offset must be finite, got " +
                         format_number(p.layer_offset));
}

MultifractalResult multifractal_generate(const GridSpec& grid, const MultifractalParams& p,
                                         std::uint64_t seed, bool keep_layers) {
    validate(p);
    grid.validate("multifractal grid");
    ensure_fits_in_memory(grid.size(), 8.0 * 4, "multifractal grid");
    MultifractalResult res;
    const WMParams* layers[3] = {&p.low, &p.mid, &p.high};
    RasterD product(grid, 1.0);
    for (int k = 0; k < 3; ++k) {
        const ProgressStage stage(k / 3.0, (k + 1) / 3.0);
        WMResult w = wm_generate(grid, *layers[k], seed, static_cast<std::uint64_t>(k));
        for (auto& s : w.warnings) res.warnings.push_back("layer " + std::to_string(k) + ": " + s);
        RasterD f = gaussian_filter(w.z, p.filter_sigma_m);
        if (p.layer_scaling == LayerScaling::unit_interval) {
            const double lo = f.array().minCoeff(), hi = f.array().maxCoeff();
            if (hi > lo)
                f.array() = (f.array() - lo) / (hi - lo);
            else
                f.array() = 1.0; // a flat layer leaves the product alone
        } else {
            const double mean = f.array().mean();
            f.array() -= mean;
            const double peak = f.array().abs().maxCoeff();
            if (peak > 0.0) f.array() /= peak;
        }
        f.array() += p.layer_offset;
        product.array() *= f.array();
        if (keep_layers) res.layers[static_cast<std::size_t>(k)] = std::move(f);
    }
    const double lo = product.array().minCoeff();
    const double hi = product.array().maxCoeff();
    const double span = hi > lo ? hi - lo : 1.0;
    product.array() = (product.array() - lo) * (p.relief_m / span) + p.base_elevation_m;
    res.z = std::move(product);
    return res;
}

MultifractalParams majhor2023_params(double d_high) {
    MultifractalParams p;
    p.high.D = d_high;
    return p;
}

GridSpec majhor2023_grid() {
    return GridSpec{1009, 1009, 0.05, 0.0, 0.0};
}

} // namespace ecoterra::terrain
