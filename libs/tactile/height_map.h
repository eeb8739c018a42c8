#pragma once
// A sampled surface height field of a fabric: the input of the periodicity analysis.

#include <Eigen/Core>

namespace haptex::tactile {

/// Heights on a square grid. Sample (ix, iy) sits at fabric position (ix, iy) * pixel_size_m;
/// x is the fabric's u (warp) axis, y its v (weft) axis. Heights are in micrometres.
class HeightMap final {
 public:
  /// @param height_um nx x ny heights [um], index (ix, iy); at least 2 x 2, all finite.
  /// @param pixel_size_m grid spacing [m], > 0.
  /// @throws std::invalid_argument on an empty grid, non-finite heights or a bad pixel size.
  HeightMap(Eigen::ArrayXXd height_um, double pixel_size_m);

  int size_x() const { return static_cast<int>(height_um_.rows()); }
  int size_y() const { return static_cast<int>(height_um_.cols()); }
  double pixel_size_m() const { return pixel_size_m_; }
  /// Distance from the first to the last sample along x [m].
  double extent_x_m() const { return (size_x() - 1) * pixel_size_m_; }
  double extent_y_m() const { return (size_y() - 1) * pixel_size_m_; }
  const Eigen::ArrayXXd& height_um() const { return height_um_; }

  double MeanUm() const { return height_um_.mean(); }
  /// Mean absolute deviation from the mean [um]: the statistic KES SMD reports.
  double MeanAbsoluteDeviationUm() const;
  /// Root-mean-square deviation from the mean [um].
  double RmsDeviationUm() const;

  /// Bilinear height at (x_m, y_m) [um]; positions outside the grid are clamped to its border.
  double SampleUm(double x_m, double y_m) const;

  /// Multiplies the deviation from the mean by `factor` (the mean is kept).
  void ScaleDeviation(double factor);

 private:
  Eigen::ArrayXXd height_um_;
  double pixel_size_m_;
};

}  // namespace haptex::tactile
