#pragma once
// Coulomb stick-slip of one spring end (paper 5.2-5.4): a tangential spring of stiffness k runs
// from the held point (where the contact sticks) to the frictionless point (where it would be
// without friction). It sticks while k |free - held| <= mu_s F_N; once sliding, the held point
// trails the frictionless point at the distance where the force is mu_d F_N, until the force
// needed falls to mu_d F_N or less (the motion stopped or turned): then it sticks again.

#include <Eigen/Core>

namespace haptex::contact {

struct FrictionCoefficients {
  double mu_static = 0.4;
  double mu_dynamic = 0.2;
};

struct StickSlipResult {
  Eigen::Vector3d held_W{Eigen::Vector3d::Zero()};  ///< new held point
  bool sliding = false;
  double tangential_N = 0.0;  ///< k |free - held| after the update
};

/// @param was_sliding the previous tick's state. mu_dynamic <= mu_static is assumed (validated
/// by ContactOptions); a non-positive normal force releases the held point (no friction).
StickSlipResult UpdateStickSlip(const Eigen::Vector3d& held_W, const Eigen::Vector3d& free_W, double stiffness_N_per_m,
                                double normal_N, const FrictionCoefficients& mu, bool was_sliding);

// The friction cone of a whole finger (states IV-VII, paper 5.3 and Fig. 9). The finger's force
// F^d = sum_i k_i (x_i - x_i^E) splits into the normal springs, -sum_i F_i^N n_i (n_i the outward
// surface normal where particle i meets the finger), and the friction springs
// sum_i k_i s_i, s_i = (where particle i meets the surface) - (its held point x_i^E). The contact
// normal is the direction of the normal springs' resultant, so:
//   F^N = |sum_i F_i^N n_i| - n.(sum_i k_i s_i),   F^T = |tangential part of sum_i k_i s_i|.

/// F^N and F^T of a finger's force, as above.
struct FingerConeLoad {
  double normal_N = 0.0;
  double tangential_N = 0.0;
};
FingerConeLoad FingerCone(const Eigen::Vector3d& normal_resultant_W_N, const Eigen::Vector3d& friction_W_N);

/// The finger slips as a whole: anchor i keeps the fraction min(1, mu / ratio_i) of its friction
/// spring, where ratio_i = k_i |s_i| / F_i^N is its own F^T/F^N; that is, every anchor follows
/// Coulomb's law with one coefficient mu for the whole finger (low-load anchors at the rim give
/// way first, and in steady sliding each carries mu F_i^N as in the paper's per-particle law).
/// Returns the mu that puts the finger's force on the cone F^T = mu_target F^N, erring to the
/// inside (relative 1e-12). Returns max ratio_i (nothing moves) if the force is inside already,
/// and 0 (every friction spring released) if even that is outside or mu_target is 0.
/// `spring_W_N` (3 x m): k_i s_i; `anchor_ratio` (m): ratio_i >= 0.
double SharedSlipCoefficient(const Eigen::Vector3d& normal_resultant_W_N,
                             const Eigen::Ref<const Eigen::Matrix3Xd>& spring_W_N,
                             const Eigen::Ref<const Eigen::VectorXd>& anchor_ratio, double mu_target);

}  // namespace haptex::contact
