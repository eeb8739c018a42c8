#pragma once
// Collects the springs the contact models put on patch particles (several models may act on one
// particle) and writes their sum into the fabric state's anchor springs:
// sum_i k_i (a_i - x) = K (A - x) with K = sum k_i, A = sum k_i a_i / K.

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "libs/textile/fabric_state.h"

namespace haptex::contact {

class AnchorAccumulator {
 public:
  explicit AnchorAccumulator(int num_particles)
      : k_(Eigen::VectorXd::Zero(num_particles)),
        ka_(Eigen::VectorXd::Zero(3 * num_particles)),
        is_touched_(static_cast<std::size_t>(num_particles), 0),
        touched_(static_cast<std::size_t>(num_particles), 0) {}

  /// Only the particles given springs since the last Clear are zeroed (a few of the patch).
  void Clear() {
    for (int i = 0; i < num_touched_; ++i) {
      const int p = touched_[static_cast<std::size_t>(i)];
      k_[p] = 0.0;
      ka_.segment<3>(3 * p).setZero();
      is_touched_[static_cast<std::size_t>(p)] = 0;
    }
    num_touched_ = 0;
  }
  void Add(int p, double k_N_per_m, const Eigen::Vector3d& anchor_W) {
    Touch(p);
    k_[p] += k_N_per_m;
    ka_.segment<3>(3 * p) += k_N_per_m * anchor_W;
  }
  /// The same as Add(p, k, anchor) for a spring given by its stiffness and k times its anchor
  /// (several springs on one particle summed by the caller).
  void AddMoment(int p, double k_N_per_m, const Eigen::Vector3d& k_anchor_W) {
    Touch(p);
    k_[p] += k_N_per_m;
    ka_.segment<3>(3 * p) += k_anchor_W;
  }
  /// Writes the springs into `state` (resizing its anchor arrays only if they were never sized).
  void WriteTo(textile::FabricState* state) const;

  /// The particles given springs since the last Clear (in the order of their first spring);
  /// every other particle has none.
  int num_touched() const { return num_touched_; }
  int touched(int i) const { return touched_[static_cast<std::size_t>(i)]; }

 private:
  void Touch(int p) {
    if (is_touched_[static_cast<std::size_t>(p)] != 0) return;
    is_touched_[static_cast<std::size_t>(p)] = 1;
    touched_[static_cast<std::size_t>(num_touched_++)] = p;
  }

  Eigen::VectorXd k_;
  Eigen::VectorXd ka_;
  std::vector<std::uint8_t> is_touched_;
  std::vector<int> touched_;  ///< [0, num_touched_)
  int num_touched_ = 0;
};

}  // namespace haptex::contact
