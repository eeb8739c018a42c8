#pragma once
// 2D power spectra of height fields: for checking tiles against their source and for images.

#include <vector>

#include <Eigen/Core>

#include "libs/tactile/height_map.h"

namespace haptex::tactile {

/// One-sided-agnostic 2D power spectrum: power(kx, ky) = |DFT of the Hann-windowed, mean-free
/// heights|^2 / (window energy), so the sum over all bins equals the variance [um^2].
/// Unshifted (DC at (0, 0)); bin (kx, ky) is frequency (kx df_x, ky df_y), kx > n/2 negative.
struct PowerSpectrum {
  Eigen::ArrayXXd power_um2;
  double df_x_per_m = 0.0;  ///< bin width [cycles/m]
  double df_y_per_m = 0.0;
};

/// Spectrum of the map; the grid is zero-padded to powers of two.
PowerSpectrum ComputePowerSpectrum(const HeightMap& map);

/// Frequencies [cycles/m] of the `count` strongest local maxima (DC excluded), strongest first,
/// one of each +/- pair (the one with kx > 0, or ky > 0 when kx == 0).
std::vector<Eigen::Vector2d> DominantFrequencies(const PowerSpectrum& spectrum, int count);

/// log10 power, centred (DC in the middle): ready for GreyImageFromArray.
Eigen::ArrayXXd SpectrumImage(const PowerSpectrum& spectrum);

}  // namespace haptex::tactile
