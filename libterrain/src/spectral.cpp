#include "ecoterra/terrain/spectral.hpp"

#include "ecoterra/progress.hpp"
#include "ecoterra/random.hpp"
#include "ecoterra/terrain/fft.hpp"

#include <cmath>
#include <sstream>

namespace ecoterra::terrain {

FbmParams FbmParams::from_dimension(double D, double rms_m) {
    if (!(D > 2.0 && D < 3.0)) {
        std::ostringstream s;
        s << "fBm: fractal dimension D must be in (2, 3), got " << D;
        throw InputError(s.str());
    }
    return FbmParams{3.0 - D, rms_m};
}

void validate(const FbmParams& p) {
    if (!(p.hurst > 0.0 && p.hurst < 1.0)) {
        std::ostringstream s;
        s << "fBm: Hurst exponent must be in (0, 1), got " << p.hurst;
        throw InputError(s.str());
    }
    if (!(p.rms_m > 0.0) || !std::isfinite(p.rms_m)) {
        std::ostringstream s;
        s << "fBm: RMS height must be > 0 m, got " << p.rms_m;
        throw InputError(s.str());
    }
}

RasterD fbm_surface(const GridSpec& grid, const FbmParams& p, std::uint64_t seed) {
    validate(p);
    grid.validate("fBm grid");
    if (grid.nx < 2 || grid.ny < 2) throw InputError("fBm: the grid needs at least 2x2 cells");
    ensure_fits_in_memory(grid.size(), 8.0 * 3, "fBm grid");
    const int nx = grid.nx, ny = grid.ny, nxh = nx / 2 + 1;
    const double wx = grid.width_m(), wy = grid.height_m();
    const double exponent = -(p.hurst + 1.0);
    HalfSpectrum spec(nx, ny);
    // Draw in a fixed order (row by row) so the surface depends only on the seed.
    Rng rng(seed, "terrain.fbm");
    for (int b = 0; b < ny; ++b) {
        const double ky = (b <= ny / 2 ? b : b - ny) / wy;
        for (int a = 0; a < nxh; ++a) {
            const double kx = a / wx;
            const double re = rng.normal(), im = rng.normal();
            const double k = std::hypot(kx, ky);
            const double amp = (a == 0 && b == 0) ? 0.0 : std::pow(k, exponent);
            spec.at(a, b) = {amp * re, amp * im};
        }
    }
    RasterD z(grid, 0.0);
    report_progress(0.5);
    inverse_real_fft(spec, z);
    const auto s = stats(z);
    z.array() = (z.array() - s.mean) * (s.stddev > 0 ? p.rms_m / s.stddev : 0.0);
    return z;
}

} // namespace ecoterra::terrain
