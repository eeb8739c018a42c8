#pragma once
// Periodicity analysis (after Peinecke, Allerkamp, Wolter 2007; reconstructed in docs/tactile.md
// section 5.3): autocorrelation -> lattice basis -> mean tile + residual noise. Pre-processing only.

#include <cstdint>

#include <Eigen/Core>

#include "libs/tactile/height_map.h"
#include "libs/tactile/periodic_tile.h"

namespace haptex::tactile {

struct PeriodicityOptions {
  /// Autocorrelation peaks below this (R(0) = 1) are never lattice candidates.
  double min_peak_correlation = 0.3;
  /// Lattice candidates: peaks at least this fraction of the strongest non-origin peak.
  double relative_peak_threshold = 0.8;
  /// Lags searched, as a fraction of the map size (<= 0.5 keeps at least a quarter overlap).
  double max_lag_fraction = 0.5;
  /// The peak lattice may be finer than the true one (a plain weave looks almost periodic with one
  /// thread pitch). Sub-lattices up to this index are tried; the smallest cell whose periodicity
  /// index is within sublattice_tolerance of the best wins.
  int max_sublattice_index = 6;
  double sublattice_tolerance = 0.01;
  /// Tile samples per map pixel along each basis vector.
  double tile_oversampling = 1.0;
  /// Side of the residual-noise patch [pixels], a power of two; 0 disables the noise.
  int noise_size = 0;
  std::uint64_t seed = 1;
};

/// Lattice found in a height map.
struct LatticeEstimate {
  Eigen::Matrix2d basis_m;       ///< columns a, b [m], Lagrange-Gauss reduced, det > 0
  int peaks_used = 0;            ///< autocorrelation peaks in the least-squares refinement
  double peak_correlation = 0;   ///< strongest non-origin autocorrelation peak (R(0) = 1)
  int sublattice_index = 1;      ///< cell area / area of the peak lattice's cell
  double periodicity_index = 0;  ///< of the mean tile on this lattice
};

/// Autocorrelation of the mean-plane-detrended map, normalised by the overlap count and by its
/// value at zero lag; index (dx + max_lag_x, dy + max_lag_y) for lag (dx, dy) pixels.
Eigen::ArrayXXd NormalisedAutocorrelation(const HeightMap& map, int max_lag_x, int max_lag_y);

/// Lattice basis from the autocorrelation peaks (sub-pixel, least-squares over all peaks), then
/// the sub-lattice that best explains the map (see PeriodicityOptions::max_sublattice_index).
/// @throws std::runtime_error if no two independent peaks exist (map not periodic or too small).
LatticeEstimate EstimateLattice(const HeightMap& map, const PeriodicityOptions& options = {});

/// Mean tile over all complete and partial cells of `basis_m` in the map, residual statistics,
/// optional residual noise. @throws std::runtime_error if the map does not cover the cell.
PeriodicTile ExtractPeriodicTile(const HeightMap& map, const Eigen::Matrix2d& basis_m,
                                 const PeriodicityOptions& options = {});

/// EstimateLattice followed by ExtractPeriodicTile.
PeriodicTile AnalysePeriodicity(const HeightMap& map, const PeriodicityOptions& options = {});

/// Lagrange-Gauss reduction of a 2D lattice basis (columns): |a| <= |b|, |a.b| <= |a|^2 / 2.
Eigen::Matrix2d ReduceBasis(const Eigen::Matrix2d& basis);

/// Largest distance [m] between the vectors of `candidate` and the nearest points of the
/// lattice `reference`, or +inf if the two bases do not span the same lattice (unimodular map).
double LatticeMismatch(const Eigen::Matrix2d& reference, const Eigen::Matrix2d& candidate);

}  // namespace haptex::tactile
