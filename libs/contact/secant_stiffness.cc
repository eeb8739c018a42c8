#include "libs/contact/secant_stiffness.h"

#include <algorithm>
#include <cmath>

namespace haptex::contact {

double SecantStiffness::Update(const Eigen::Vector3d& force_W_N, const Eigen::Vector3d& x_W_m, double dt_s) {
  if (have_last_) {
    const Eigen::Vector3d dx = x_W_m - last_x_;
    const double dx2 = dx.squaredNorm();
    // Below a micrometre the secant is quantisation noise: keep the estimate.
    if (dx2 > 1e-12) {
      const double secant = std::clamp(-(force_W_N - last_force_).dot(dx) / dx2, 0.0, max_);
      const double alpha = dt_s / (filter_s_ + dt_s);
      if (std::isfinite(secant)) k_ += alpha * (secant - k_);
    }
  }
  last_force_ = force_W_N;
  last_x_ = x_W_m;
  have_last_ = true;
  return k_;
}

}  // namespace haptex::contact
