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
  /// d F / d x of the other finger, and that finger's anchor: where the fingers press on each
  /// other, their distance sets the force, so the other finger's motion must reach this force at
  /// the bridge's rate too, not a link round trip late through F0.
  Eigen::Matrix3d cross_stiffness_W_N_per_m{Eigen::Matrix3d::Zero()};
  Eigen::Vector3d other_x0_W_m{Eigen::Vector3d::Zero()};
  /// How long after its arrival the model may be used; the bridge also caps this by its own
  /// staleness limit (ForceSafetyConfig::stale_after_s).
  double ttl_s = 0.010;
};

/// The linear model's extrapolation K (p - x0) + K_cross (p_other - x0_other) is trusted up to
/// |F0| plus this [N]: the model is a linearisation where local_contact last saw the fingers, and
/// over a slow link the fingers get millimetres away from there. A soft fabric's measured secant
/// stiffness can be high while its force is small (it yields), and extrapolated over millimetres it
/// would push far harder than the fabric does.
inline constexpr double kExtrapolationAllowance_N = 0.05;

/// F0 + K (p - x0) + K_cross (p_other - x0_other), the extrapolation capped at |F0| +
/// kExtrapolationAllowance_N, and never pulling against F0: contact pushes, and a linearisation taken
/// where the finger will be (deeper in) must not turn into a pull while it is still short of there,
/// so the part of the force opposite F0 is dropped. May return NaN/Inf if the model holds them: the
/// safety stage handles that.
inline Eigen::Vector3d EvaluateForceModel(const ForceModel& model, const Eigen::Vector3d& p_W_m,
                                          const Eigen::Vector3d& p_other_W_m) {
  Eigen::Vector3d extrapolation = model.stiffness_W_N_per_m * (p_W_m - model.x0_W_m) +
                                  model.cross_stiffness_W_N_per_m * (p_other_W_m - model.other_x0_W_m);
  const double f0_N = model.force0_W_N.norm();
  const double allowed_N = f0_N + kExtrapolationAllowance_N;
  const double extrapolation_N = extrapolation.norm();
  if (extrapolation_N > allowed_N) extrapolation *= allowed_N / extrapolation_N;
  Eigen::Vector3d force = model.force0_W_N + extrapolation;
  const double along = force.dot(model.force0_W_N);
  if (along < 0.0 && f0_N > 0.0) force -= (along / (f0_N * f0_N)) * model.force0_W_N;
  return force;
}

}  // namespace haptex::device
