#pragma once
// Collects the springs the contact models put on patch particles (several models may act on one
// particle) and writes their sum into the fabric state's anchor springs:
// sum_i k_i (a_i - x) = K (A - x) with K = sum k_i, A = sum k_i a_i / K.

#include <Eigen/Core>

#include "libs/textile/fabric_state.h"

namespace haptex::contact {

class AnchorAccumulator {
 public:
  explicit AnchorAccumulator(int num_particles)
      : k_(Eigen::VectorXd::Zero(num_particles)), ka_(Eigen::VectorXd::Zero(3 * num_particles)) {}

  void Clear() {
    k_.setZero();
    ka_.setZero();
  }
  void Add(int p, double k_N_per_m, const Eigen::Vector3d& anchor_W) {
    k_[p] += k_N_per_m;
    ka_.segment<3>(3 * p) += k_N_per_m * anchor_W;
  }
  /// The same as Add(p, k, anchor) for a spring given by its stiffness and k times its anchor
  /// (several springs on one particle summed by the caller).
  void AddMoment(int p, double k_N_per_m, const Eigen::Vector3d& k_anchor_W) {
    k_[p] += k_N_per_m;
    ka_.segment<3>(3 * p) += k_anchor_W;
  }
  /// Writes the springs into `state` (resizing its anchor arrays only if they were never sized).
  void WriteTo(textile::FabricState* state) const;

 private:
  Eigen::VectorXd k_;
  Eigen::VectorXd ka_;
};

}  // namespace haptex::contact
