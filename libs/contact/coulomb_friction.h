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
StickSlipResult UpdateStickSlip(const Eigen::Vector3d& held_W, const Eigen::Vector3d& free_W,
                                double stiffness_N_per_m, double normal_N,
                                const FrictionCoefficients& mu, bool was_sliding);

}  // namespace haptex::contact
