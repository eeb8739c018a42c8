#pragma once
// Stiffness the device bridge uses between contact updates (F = F0 + K dx). The contact springs
// alone would overstate it (the fabric yields behind them), so it is measured: the secant
// dF/dx along the finger's motion, low-pass filtered, clamped to [0, max].

#include <Eigen/Core>

namespace haptex::contact {

class SecantStiffness {
 public:
  SecantStiffness(double max_N_per_m, double filter_s) : max_(max_N_per_m), filter_s_(filter_s) {}

  /// `force_W_N` is the force on the finger at `x_W_m`. Returns the current estimate [N/m] >= 0.
  double Update(const Eigen::Vector3d& force_W_N, const Eigen::Vector3d& x_W_m, double dt_s);
  void Reset() {
    have_last_ = false;
    k_ = 0.0;
  }
  double value() const { return k_; }

 private:
  double max_, filter_s_;
  bool have_last_ = false;
  Eigen::Vector3d last_force_{Eigen::Vector3d::Zero()};
  Eigen::Vector3d last_x_{Eigen::Vector3d::Zero()};
  double k_ = 0.0;
};

}  // namespace haptex::contact
