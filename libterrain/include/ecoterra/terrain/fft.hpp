#pragma once
// Thin RAII wrapper over FFTW 3 (Frigo & Johnson 2005) for real 2D transforms of rasters.
// Plans use FFTW_ESTIMATE, so the same input gives the same output on every run.
#include "ecoterra/raster.hpp"

#include <complex>
#include <vector>

namespace ecoterra::terrain {

/// The non-redundant half of the 2D spectrum of an ny x nx real field: (nx/2 + 1) x ny complex
/// values, kx index a in [0, nx/2], ky index b in [0, ny) (b > ny/2 are negative frequencies).
class HalfSpectrum {
public:
    HalfSpectrum(int nx, int ny)
        : m_nx(nx), m_ny(ny), m_data(static_cast<std::size_t>(ny) * (nx / 2 + 1)) {}
    int nx() const { return m_nx; }
    int ny() const { return m_ny; }
    int nxh() const { return m_nx / 2 + 1; }
    std::complex<double>& at(int a, int b) {
        return m_data[static_cast<std::size_t>(b) * nxh() + a];
    }
    const std::complex<double>& at(int a, int b) const {
        return m_data[static_cast<std::size_t>(b) * nxh() + a];
    }
    std::complex<double>* data() { return m_data.data(); }

private:
    int m_nx, m_ny;
    std::vector<std::complex<double>> m_data;
};

/// Unnormalised forward transform of a field with no NaN.
HalfSpectrum forward_real_fft(const RasterD& field);
/// Unnormalised inverse transform into `out` (whose grid fixes nx, ny).
void inverse_real_fft(const HalfSpectrum& spec, RasterD& out);

} // namespace ecoterra::terrain
