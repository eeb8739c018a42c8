#pragma once
// Monotone cubic Hermite interpolation (Fritsch-Carlson) of a non-decreasing curve y(x).

#include <vector>

namespace haptex::textile {

/// A monotone piecewise-cubic curve through knots (x_k, y_k), extended linearly beyond the first
/// and last knot with the end tangents. Evaluation never allocates.
class MonotoneSpline {
 public:
  MonotoneSpline() = default;

  /// Builds the spline. @throws std::invalid_argument unless there are >= 2 knots, x strictly
  /// increasing, y non-decreasing, and every value finite.
  MonotoneSpline(std::vector<double> x, std::vector<double> y);

  /// Value and slope dy/dx at x. The segment comes from a table over uniform cells (a lookup
  /// and at most a step or two, instead of a binary search); same result as a binary search.
  void Evaluate(double x, double* y, double* dy_dx) const;
  double Value(double x) const;
  double Slope(double x) const;

  const std::vector<double>& knots_x() const { return x_; }
  const std::vector<double>& knots_y() const { return y_; }
  /// Hermite tangents at the knots after the Fritsch-Carlson limiter.
  const std::vector<double>& tangents() const { return m_; }
  bool empty() const { return x_.empty(); }

 private:
  std::vector<double> x_, y_, m_;
  /// cell_segment_[c]: the segment holding the start of uniform cell c of [x_0, x_{n-1}].
  std::vector<int> cell_segment_;
  double cells_per_x_ = 0.0;
};

}  // namespace haptex::textile
