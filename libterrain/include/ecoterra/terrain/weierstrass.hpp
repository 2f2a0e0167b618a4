#pragma once
// The 3D Weierstrass-Mandelbrot (W-M) fractal surface and the multifractal combination of three
// W-M DEMs.
//
// Equations (Ausloos & Berman 1985, Proc. R. Soc. A 400, 331; in the form of Dawkins, Bevly &
// Jackson 2012, J. Terramechanics 49, 299, and Majhor & Bos, ASME J. Auton. Veh. 5(2) 021003,
// eqs 1-2):
//
//   z(x, y) = A * sum_{m=1..M} sum_{n=1..n_max} gamma^{(D-3) n}
//               [ cos(phi_mn) - cos( 2 pi gamma^n r / L * cos(theta - pi m / M) + phi_mn ) ]
//   A = L (G / L)^{D-2} (ln(gamma) / M)^{1/2}
//
// with r cos(theta - pi m / M) = x cos(pi m / M) + y sin(pi m / M) (no atan2, no quadrant bug).
// Units: x, y, L, G, A and z in metres; gamma, D, M, n dimensionless; phi in radians.
//
// Fast evaluation (reference terrain.md s1.3): each (m, n) term is a plane wave, and
// cos(a x + b y + phi) = cos(a x + phi) cos(b y) - sin(a x + phi) sin(b y), so the whole grid is
// Z = C - V U^T with U (nx x 2T) and V (ny x 2T) tables of per-term trigonometry: one matrix
// product, no per-pixel trigonometry. Phases are evaluated in double precision.
#include "ecoterra/raster.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

namespace ecoterra::terrain {

struct WMParams {
    int M = 64;         ///< number of ridges (directions), >= 1
    int n_max = 0;      ///< highest frequency index; 0 = the grid's Nyquist cutoff
    double gamma = 1.5; ///< frequency density, > 1
    double D = 2.45;    ///< fractal dimension, in (2, 3)
    double L_m = 100.9; ///< sampling length, m
    double G_m = 1e-8;  ///< elevation scaling coefficient, m
    /// Random phases are uniform in [0, phase_max_rad]: pi as in Majhor & Bos Table 1; 2 pi gives
    /// the fully random-phase ensemble of Ausloos & Berman (see docs/terrain.md on the bias).
    double phase_max_rad = 3.141592653589793;
};

/// Throws InputError naming the parameter if any is outside its valid range.
void validate(const WMParams& p);

/// A = L (G/L)^(D-2) (ln gamma / M)^(1/2), m (eq. 2).
double wm_amplitude(const WMParams& p);

/// The Nyquist cutoff floor(log(L / (2 cell)) / log(gamma)) (terms above it alias on the grid).
int wm_nyquist_nmax(double L_m, double gamma, double cell_size_m);

/// Phases phi_mn, an M x n_max matrix (row m-1, column n-1), uniform in [0, phase_max_rad].
Eigen::MatrixXd wm_random_phases(int M, int n_max, std::uint64_t seed, std::uint64_t stream = 0,
                                 double phase_max_rad = 3.141592653589793);

/// Eq. 1 evaluated directly at one point (for tests and for reproducing published values).
/// phases must be M x n_max with n_max = p.n_max (> 0).
double wm_evaluate_point(const WMParams& p, const Eigen::MatrixXd& phases, double x_m, double y_m);

struct WMResult {
    RasterD z;                         ///< elevation, m
    int n_max = 0;                     ///< the n_max used
    int terms_evaluated = 0;           ///< (m, n) terms summed
    int terms_negligible = 0;          ///< terms skipped: amplitude < 1e-17 of the n=1 term
    std::vector<std::string> warnings; ///< e.g. terms above Nyquist alias
};

/// Evaluates eq. 1 at every cell centre of `grid` with the given phases (M x n_max; its column
/// count fixes n_max). Deterministic on any thread count.
WMResult wm_generate(const GridSpec& grid, const WMParams& p, const Eigen::MatrixXd& phases);

/// As above with phases drawn from the seed (stream lets several layers share one seed).
WMResult wm_generate(const GridSpec& grid, const WMParams& p, std::uint64_t seed,
                     std::uint64_t stream = 0);

/// How each layer is rescaled before the product: to zero mean and a maximum absolute value of 1
/// (the paper's text: "scaled near the same range and with zero mean"), or to [0, 1] (its min to
/// 0, its max to 1: no layer crosses zero, so no flat bands where one does; docs/terrain.md).
enum class LayerScaling { zero_mean, unit_interval };

/// Majhor & Bos multifractal: three W-M DEMs (low, mid, high frequency), each low-pass filtered
/// with a Gaussian, rescaled (`layer_scaling`), multiplied pixel by pixel, and the product scaled
/// to [base_elevation_m, base_elevation_m + relief_m].
struct MultifractalParams {
    WMParams low{16, 0, 1.5, 2.2, 100.9, 1e-6};
    WMParams mid{32, 0, 1.5, 2.45, 100.9, 8e-8};
    WMParams high{64, 0, 1.5, 2.45, 100.9, 1e-8};
    /// Gaussian low-pass standard deviation, m (0 = no filter). The paper gives none; the default
    /// is half a cell of the majhor2023 grid, MATLAB imgaussfilt's default (docs/terrain.md).
    double filter_sigma_m = 0.025;
    /// Total relief (max - min) of the result, m. 19.2 m = 5 x 3.84 m: see docs/terrain.md.
    double relief_m = 19.2;
    double base_elevation_m = 0.0; ///< elevation of the lowest cell, m
    LayerScaling layer_scaling = LayerScaling::zero_mean;
    /// Added to each layer after its rescaling, before the product (dimensionless). 0 keeps the
    /// paper's zero-mean layers; an offset above 1 keeps every zero-mean layer positive, so no
    /// layer's zero crossing flattens the product (docs/terrain.md s1.2).
    double layer_offset = 0.0;
};

void validate(const MultifractalParams& p);

struct MultifractalResult {
    RasterD z;                     ///< elevation, m
    std::array<RasterD, 3> layers; ///< the three rescaled layers (dimensionless: [-1, 1] or [0, 1])
    std::vector<std::string> warnings;
};

MultifractalResult multifractal_generate(const GridSpec& grid, const MultifractalParams& p,
                                         std::uint64_t seed, bool keep_layers = false);

/// The paper's setting: 1009 x 1009 px at 0.05 m, D_high in {2.3, 2.45, 2.6} (Table 1).
MultifractalParams majhor2023_params(double d_high);
GridSpec majhor2023_grid();

} // namespace ecoterra::terrain
