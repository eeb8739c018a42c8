#include "libs/textile/monotone_spline.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>

#include "libs/base/demand.h"

namespace haptex::textile {

MonotoneSpline::MonotoneSpline(std::vector<double> x, std::vector<double> y) : x_(std::move(x)), y_(std::move(y)) {
  const std::size_t n = x_.size();
  if (n < 2 || y_.size() != n) {
    throw std::invalid_argument("MonotoneSpline: needs at least 2 knots and as many y as x values");
  }
  for (std::size_t k = 0; k < n; ++k) {
    if (!std::isfinite(x_[k]) || !std::isfinite(y_[k])) {
      throw std::invalid_argument("MonotoneSpline: knot " + std::to_string(k) + " is not finite");
    }
    if (k > 0 && !(x_[k] > x_[k - 1])) {
      throw std::invalid_argument("MonotoneSpline: x must be strictly increasing (knot " + std::to_string(k) + ")");
    }
    if (k > 0 && y_[k] < y_[k - 1]) {
      throw std::invalid_argument("MonotoneSpline: y must be non-decreasing (knot " + std::to_string(k) + ")");
    }
  }
  // Secant slopes, then three-point tangents.
  std::vector<double> delta(n - 1);
  for (std::size_t k = 0; k + 1 < n; ++k) delta[k] = (y_[k + 1] - y_[k]) / (x_[k + 1] - x_[k]);
  m_.assign(n, 0.0);
  m_[0] = delta[0];
  m_[n - 1] = delta[n - 2];
  for (std::size_t k = 1; k + 1 < n; ++k) {
    m_[k] = (delta[k - 1] * delta[k] <= 0.0) ? 0.0 : 0.5 * (delta[k - 1] + delta[k]);
  }
  // Fritsch-Carlson limiter: keep (alpha, beta) inside the circle of radius 3.
  for (std::size_t k = 0; k + 1 < n; ++k) {
    if (delta[k] == 0.0) {
      m_[k] = 0.0;
      m_[k + 1] = 0.0;
      continue;
    }
    const double alpha = m_[k] / delta[k];
    const double beta = m_[k + 1] / delta[k];
    const double r2 = alpha * alpha + beta * beta;
    if (r2 > 9.0) {
      const double tau = 3.0 / std::sqrt(r2);
      m_[k] = tau * alpha * delta[k];
      m_[k + 1] = tau * beta * delta[k];
    }
  }
  // Segment lookup: about four cells per segment, so the walk from a cell's segment is short.
  const std::size_t cells = 4 * (n - 1);
  const double span = x_[n - 1] - x_[0];
  cells_per_x_ = static_cast<double>(cells) / span;
  if (!std::isfinite(cells_per_x_)) cells_per_x_ = 0.0;  // absurd span: walk from segment 0
  cell_segment_.resize(cells);
  for (std::size_t c = 0; c < cells; ++c) {
    const double start = x_[0] + static_cast<double>(c) / cells_per_x_;
    const auto it = std::upper_bound(x_.begin(), x_.end(), start);
    const auto k = static_cast<std::size_t>(std::max<std::ptrdiff_t>(it - x_.begin() - 1, 0));
    cell_segment_[c] = static_cast<int>(std::min(k, n - 2));
  }
}

void MonotoneSpline::Evaluate(double x, double* y, double* dy_dx) const {
  HAPTEX_DEMAND(x_.size() >= 2);
  const std::size_t n = x_.size();
  if (x <= x_[0]) {
    *y = y_[0] + m_[0] * (x - x_[0]);
    *dy_dx = m_[0];
    return;
  }
  if (x >= x_[n - 1]) {
    *y = y_[n - 1] + m_[n - 1] * (x - x_[n - 1]);
    *dy_dx = m_[n - 1];
    return;
  }
  // k with x_k <= x < x_{k+1} (x_0 < x < x_{n-1} here): a cell's segment, then a short walk
  // (which also absorbs any rounding in the cell index).
  const double cell = (x - x_[0]) * cells_per_x_;
  const std::size_t last_cell = cell_segment_.size() - 1;
  const std::size_t c = cell < static_cast<double>(last_cell) ? static_cast<std::size_t>(cell) : last_cell;
  std::size_t k = static_cast<std::size_t>(cell_segment_[c]);
  while (x_[k + 1] <= x) ++k;
  while (x < x_[k]) --k;
  const double h = x_[k + 1] - x_[k];
  const double t = (x - x_[k]) / h;
  const double t2 = t * t;
  const double t3 = t2 * t;
  const double h00 = 2 * t3 - 3 * t2 + 1, h10 = t3 - 2 * t2 + t, h01 = -2 * t3 + 3 * t2, h11 = t3 - t2;
  *y = h00 * y_[k] + h10 * h * m_[k] + h01 * y_[k + 1] + h11 * h * m_[k + 1];
  const double d00 = 6 * t2 - 6 * t, d10 = 3 * t2 - 4 * t + 1, d01 = -6 * t2 + 6 * t, d11 = 3 * t2 - 2 * t;
  *dy_dx = (d00 * y_[k] + d01 * y_[k + 1]) / h + d10 * m_[k] + d11 * m_[k + 1];
}

double MonotoneSpline::Value(double x) const {
  double y = 0, d = 0;
  Evaluate(x, &y, &d);
  return y;
}

double MonotoneSpline::Slope(double x) const {
  double y = 0, d = 0;
  Evaluate(x, &y, &d);
  return d;
}

}  // namespace haptex::textile
