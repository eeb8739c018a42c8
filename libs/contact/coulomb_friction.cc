#include "libs/contact/coulomb_friction.h"

#include <algorithm>
#include <cmath>

namespace haptex::contact {

StickSlipResult UpdateStickSlip(const Eigen::Vector3d& held_W, const Eigen::Vector3d& free_W, double stiffness_N_per_m,
                                double normal_N, const FrictionCoefficients& mu, bool was_sliding) {
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

FingerConeLoad FingerCone(const Eigen::Vector3d& normal_resultant_W_N, const Eigen::Vector3d& friction_W_N) {
  FingerConeLoad out;
  const double push_N = normal_resultant_W_N.norm();
  if (!(push_N > 0.0)) {
    out.tangential_N = friction_W_N.norm();
    return out;
  }
  const Eigen::Vector3d n = normal_resultant_W_N / push_N;
  const double along_n = n.dot(friction_W_N);
  out.normal_N = push_N - along_n;
  out.tangential_N = (friction_W_N - along_n * n).norm();
  return out;
}

namespace {

// Distance of the finger's force outside the cone of mu_target when every anchor keeps the
// fraction min(1, mu / ratio_i) of its friction spring (negative inside).
double ConeExcess(const Eigen::Vector3d& normal_resultant_W_N, const Eigen::Ref<const Eigen::Matrix3Xd>& spring_W_N,
                  const Eigen::Ref<const Eigen::VectorXd>& anchor_ratio, double mu, double mu_target) {
  Eigen::Vector3d friction = Eigen::Vector3d::Zero();
  for (Eigen::Index i = 0; i < spring_W_N.cols(); ++i) {
    const double r = anchor_ratio[i];
    friction += (r > mu ? mu / r : 1.0) * spring_W_N.col(i);
  }
  const FingerConeLoad load = FingerCone(normal_resultant_W_N, friction);
  return load.tangential_N - mu_target * load.normal_N;
}

}  // namespace

double SharedSlipCoefficient(const Eigen::Vector3d& normal_resultant_W_N,
                             const Eigen::Ref<const Eigen::Matrix3Xd>& spring_W_N,
                             const Eigen::Ref<const Eigen::VectorXd>& anchor_ratio, double mu_target) {
  const double top = anchor_ratio.size() > 0 ? anchor_ratio.maxCoeff() : 0.0;
  if (!(mu_target > 0.0)) return 0.0;
  double lo = 0.0;
  double h_lo = ConeExcess(normal_resultant_W_N, spring_W_N, anchor_ratio, lo, mu_target);
  if (!(h_lo < 0.0)) return 0.0;
  double hi = top;
  double h_hi = ConeExcess(normal_resultant_W_N, spring_W_N, anchor_ratio, hi, mu_target);
  if (!(h_hi > 0.0)) return top;
  // Illinois regula falsi on the bracket [lo, hi] (h(lo) <= 0 < h(hi)); the excess is piecewise
  // smooth in mu, so this converges in a handful of evaluations.
  const double tolerance_N = 1e-12 * mu_target * normal_resultant_W_N.norm();
  double excess_lo = h_lo;  // h_lo and h_hi are the Illinois-weighted values
  int side = 0;
  for (int iteration = 0; iteration < 100; ++iteration) {
    if (-excess_lo <= tolerance_N || hi - lo <= 1e-12 * top) break;
    double mu = hi - h_hi * (hi - lo) / (h_hi - h_lo);
    if (!(mu > lo && mu < hi)) mu = 0.5 * (lo + hi);
    const double h = ConeExcess(normal_resultant_W_N, spring_W_N, anchor_ratio, mu, mu_target);
    if (h <= 0.0) {
      lo = mu;
      h_lo = excess_lo = h;
      if (side == -1) h_hi *= 0.5;
      side = -1;
    } else {
      hi = mu;
      h_hi = h;
      if (side == 1) h_lo *= 0.5;
      side = 1;
    }
  }
  return lo;
}

}  // namespace haptex::contact
