#include "libs/contact/coulomb_friction.h"

namespace haptex::contact {

StickSlipResult UpdateStickSlip(const Eigen::Vector3d& held_W, const Eigen::Vector3d& free_W,
                                double stiffness_N_per_m, double normal_N,
                                const FrictionCoefficients& mu, bool was_sliding) {
  StickSlipResult out;
  if (!(normal_N > 0.0) || !(stiffness_N_per_m > 0.0)) {
    out.held_W = free_W;
    out.sliding = was_sliding;
    return out;
  }
  const Eigen::Vector3d stretch = free_W - held_W;
  const double force = stiffness_N_per_m * stretch.norm();
  const double limit = (was_sliding ? mu.mu_dynamic : mu.mu_static) * normal_N;
  // The relative tolerance keeps a contact that slid to exactly mu_d F_N and stopped from
  // counting as sliding forever through rounding.
  if (force <= limit * (1.0 + 1e-9)) {
    out.held_W = held_W;
    out.sliding = false;
    out.tangential_N = force;
    return out;
  }
  const double kinetic = mu.mu_dynamic * normal_N;
  out.held_W = free_W - stretch * (kinetic / force);
  out.sliding = true;
  out.tangential_N = kinetic;
  return out;
}

}  // namespace haptex::contact
