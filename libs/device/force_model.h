#pragma once
// The local force model local_contact sends at 1 kHz and the bridge evaluates at 5 kHz:
// F(x) = F0 + K (x - x0), a linearisation of the contact force around the anchor x0.

#include <algorithm>

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
  /// The friction cone the contact holds: the normal force's direction on the finger and the
  /// largest tangential/normal ratio about it (at least F0's own). 0 or a bad axis: no cone.
  Eigen::Vector3d friction_cone_axis_W{Eigen::Vector3d::Zero()};
  double friction_cone_mu = 0.0;
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

/// Keeps `force` inside the cone about the unit `axis`: its part across the axis at most `mu`
/// times its part along it (none where that is not positive). Only ever shortens the force.
inline Eigen::Vector3d KeepInFrictionCone(const Eigen::Vector3d& force, const Eigen::Vector3d& axis, double mu) {
  const double normal_N = force.dot(axis);
  const Eigen::Vector3d tangential = force - normal_N * axis;
  const double tangential_N = tangential.norm();
  const double allowed_N = normal_N > 0.0 ? mu * normal_N : 0.0;  // (mu may be infinite)
  if (tangential_N <= allowed_N) return force;
  return force - (1.0 - allowed_N / tangential_N) * tangential;
}

/// F0 + K (p - x0) + K_cross (p_other - x0_other), the extrapolation capped at |F0| +
/// kExtrapolationAllowance_N, inside the model's friction cone (a stuck contact's tangential
/// stiffness, extrapolated over a link's latency, would otherwise hold the finger far harder than
/// friction can), and never pulling against F0:
/// contact pushes, and a linearisation taken where the finger will be (deeper in) must not turn into
/// a pull while it is still short of there, so the part of the force opposite F0 is dropped. May
/// return NaN/Inf if the model holds them: the safety stage handles that.
inline Eigen::Vector3d EvaluateForceModel(const ForceModel& model, const Eigen::Vector3d& p_W_m,
                                          const Eigen::Vector3d& p_other_W_m) {
  Eigen::Vector3d extrapolation = model.stiffness_W_N_per_m * (p_W_m - model.x0_W_m) +
                                  model.cross_stiffness_W_N_per_m * (p_other_W_m - model.other_x0_W_m);
  const double f0_N = model.force0_W_N.norm();
  const double allowed_N = f0_N + kExtrapolationAllowance_N;
  const double extrapolation_N = extrapolation.norm();
  if (extrapolation_N > allowed_N) extrapolation *= allowed_N / extrapolation_N;
  Eigen::Vector3d force = model.force0_W_N + extrapolation;
  const double axis_norm = model.friction_cone_axis_W.norm();
  if (model.friction_cone_mu > 0.0 && axis_norm > 0.5 && axis_norm < 2.0)  // else: no cone (none sent, or garbled)
    force = KeepInFrictionCone(force, model.friction_cone_axis_W / axis_norm, model.friction_cone_mu);
  const double along = force.dot(model.force0_W_N);
  if (along < 0.0 && f0_N > 0.0) force -= (along / (f0_N * f0_N)) * model.force0_W_N;
  return force;
}

}  // namespace haptex::device
