#pragma once
// The local force model local_contact sends at 1 kHz and the bridge evaluates at 5 kHz:
// F(x) = F0 + K (x - x0), a linearisation of the contact force around the anchor x0.

#include <Eigen/Core>

namespace haptex::device {

/// Force on one fingertip as an affine function of its position. World frame W.
struct ForceModel {
  Eigen::Vector3d force0_W_N{Eigen::Vector3d::Zero()};           ///< F0: force at the anchor
  Eigen::Matrix3d stiffness_W_N_per_m{Eigen::Matrix3d::Zero()};  ///< K = dF/dx (negative for a wall)
  Eigen::Vector3d x0_W_m{Eigen::Vector3d::Zero()};               ///< anchor position
  /// How long after its arrival the model may be used; the bridge also caps this by its own
  /// staleness limit (ForceSafetyConfig::stale_after_s).
  double ttl_s = 0.010;
};

/// F0 + K (p - x0). May return NaN/Inf if the model holds them: the safety stage handles that.
inline Eigen::Vector3d EvaluateForceModel(const ForceModel& model, const Eigen::Vector3d& p_W_m) {
  return model.force0_W_N + model.stiffness_W_N_per_m * (p_W_m - model.x0_W_m);
}

}  // namespace haptex::device
