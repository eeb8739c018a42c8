#include "libs/tactile/height_map.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

namespace haptex::tactile {

HeightMap::HeightMap(Eigen::ArrayXXd height_um, double pixel_size_m)
    : height_um_(std::move(height_um)), pixel_size_m_(pixel_size_m) {
  if (height_um_.rows() < 2 || height_um_.cols() < 2) {
    throw std::invalid_argument("HeightMap: need at least 2 x 2 samples");
  }
  if (!std::isfinite(pixel_size_m_) || pixel_size_m_ <= 0.0) {
    throw std::invalid_argument("HeightMap: pixel_size_m must be finite and > 0");
  }
  if (!height_um_.allFinite()) {
    throw std::invalid_argument("HeightMap: heights must be finite");
  }
}

double HeightMap::MeanAbsoluteDeviationUm() const { return (height_um_ - height_um_.mean()).abs().mean(); }

double HeightMap::RmsDeviationUm() const { return std::sqrt((height_um_ - height_um_.mean()).square().mean()); }

double HeightMap::SampleUm(double x_m, double y_m) const {
  const double fx = std::clamp(x_m / pixel_size_m_, 0.0, static_cast<double>(size_x() - 1));
  const double fy = std::clamp(y_m / pixel_size_m_, 0.0, static_cast<double>(size_y() - 1));
  const int ix = std::min(static_cast<int>(fx), size_x() - 2);
  const int iy = std::min(static_cast<int>(fy), size_y() - 2);
  const double tx = fx - ix;
  const double ty = fy - iy;
  const auto& h = height_um_;
  return (1.0 - tx) * (1.0 - ty) * h(ix, iy) + tx * (1.0 - ty) * h(ix + 1, iy) + (1.0 - tx) * ty * h(ix, iy + 1) +
         tx * ty * h(ix + 1, iy + 1);
}

void HeightMap::ScaleDeviation(double factor) {
  const double mean = height_um_.mean();
  height_um_ = mean + (height_um_ - mean) * factor;
}

}  // namespace haptex::tactile
