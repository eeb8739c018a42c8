#pragma once
// Discrete Fourier transforms for the pre-processing side (periodicity analysis, tile smoothing,
// spectra). Radix-2 for power-of-two sizes, a direct DFT otherwise (only small tiles use that).
// Not for the real-time path.

#include <complex>
#include <cstddef>

#include <Eigen/Core>

namespace haptex::tactile {

/// Complex 2D array, index (x, y).
using ComplexGrid = Eigen::Array<std::complex<double>, Eigen::Dynamic, Eigen::Dynamic>;

/// Smallest power of two >= n (n >= 1).
std::size_t NextPowerOfTwo(std::size_t n);

/// In-place 1D DFT of n values spaced by stride. Forward: X_k = sum x_n e^{-2 pi i k n / N};
/// inverse: the conjugate kernel scaled by 1/N, so Inverse(Forward(x)) == x.
void Dft1d(std::complex<double>* data, std::size_t n, std::size_t stride, bool inverse);

/// In-place 2D DFT (rows then columns) with the same conventions as Dft1d.
void Dft2d(ComplexGrid* grid, bool inverse);

}  // namespace haptex::tactile
