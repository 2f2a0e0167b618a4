#pragma once
// Spectral synthesis of fractional Brownian surfaces (Saupe 1988, "Algorithms for random fractals",
// in The Science of Fractal Images, ch. 2; Voss 1985).
//
// Fourier coefficients c(k) = g(k) |k|^{-(H + 1)} with g complex standard normal, k = 0 removed,
// and an inverse FFT: the 2D power spectrum goes as |k|^{-2(H+1)} = |k|^{-(8 - 2D)}, the variogram
// as r^{2H}, and the surface has fractal dimension D = 3 - H. The result is periodic (it tiles)
// and is rescaled to the requested RMS height.
#include "ecoterra/raster.hpp"

#include <cstdint>

namespace ecoterra::terrain {

struct FbmParams {
    double hurst = 0.7; ///< Hurst exponent H in (0, 1); D = 3 - H
    double rms_m = 1.0; ///< RMS height of the result about its mean, m
    static FbmParams from_dimension(double D, double rms_m = 1.0);
};

void validate(const FbmParams& p);

RasterD fbm_surface(const GridSpec& grid, const FbmParams& p, std::uint64_t seed);

} // namespace ecoterra::terrain
