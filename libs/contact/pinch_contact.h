#pragma once
// States VIII/IX (paper 5.4): the fabric squeezed between thumb and index. A shared contact frame
// C (origin on the contact plane midway between the finger surfaces, z_C from thumb to index)
// carries sample points: equally spaced points of the fabric (more than its particles) that lie
// in the intersection of the two fingers. Each sample keeps its ideal position in C, a spring
// pulls its fabric point there, and Coulomb friction moves the ideal position when the spring
// exceeds the sample's share of the grip. Particles inside the intersection belong to this model
// alone; the others keep the one-finger model without friction, so the fabric can fold over one
// finger while pinched.

#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "libs/contact/anchor_accumulator.h"
#include "libs/contact/contact_options.h"
#include "libs/contact/finger_geometry.h"
#include "libs/textile/fabric_model.h"
#include "libs/textile/fabric_state.h"

namespace haptex::contact {

struct PinchResult {
  bool active = false;
  int samples = 0;
  int sliding_samples = 0;
  double grip_N = 0.0;                       ///< normal force between the fingers
  Eigen::Vector3d normal_W{Eigen::Vector3d::UnitZ()};  ///< z_C: thumb -> index
  Eigen::Vector3d fabric_force_W_N{Eigen::Vector3d::Zero()};  ///< sum of sample springs on the fabric
  Eigen::Vector3d friction_W_N{Eigen::Vector3d::Zero()};  ///< in-plane part of it, on the fingers
  Eigen::Vector2d touch_uv_m{Eigen::Vector2d::Zero()};        ///< mean rest uv of the samples
  Eigen::Vector3d touch_velocity_W{Eigen::Vector3d::Zero()};
  int touch_triangle = -1;                   ///< a triangle under the samples (tangent frame)
};

class PinchContact {
 public:
  PinchContact(const textile::FabricModel& patch, const ContactOptions& options);

  /// Before the fabric step, with the fingers' poses at its end and the grip normal force:
  /// (re)builds the contact frame, starts samples that entered the intersection (sticking where
  /// they are), drops those that left, applies Coulomb's law to each sample's ideal position
  /// (both faces grip: the limit is 2 mu times the sample's share of the grip), marks the
  /// particles it owns in `owned`, and adds the samples' springs (lumped onto their triangle's
  /// particles) to `springs`. Returns false when no fabric lies in the intersection.
  bool Prepare(const FingerPose& thumb, const FingerPose& index, double grip_N,
               const FrictionCoefficients& mu, const textile::FabricState& state,
               std::vector<std::uint8_t>* owned, AnchorAccumulator* springs);
  /// After the step: the forces as applied and where the fabric is touched.
  void Resolve(const textile::FabricState& state, const Eigen::MatrixX2d& rest_uv_m,
               PinchResult* result);
  void Reset();
  bool active() const { return active_; }

  /// Sample points for a patch hand-off: sample i belongs to triangle i / samples_per_triangle()
  /// at a fixed barycentric position; its state is carried to the same point of a new patch.
  struct SampleState {
    bool active = false;
    bool sliding = false;
    Eigen::Vector2d ideal_C{Eigen::Vector2d::Zero()};
  };
  int samples_per_triangle() const { return options_.pinch_samples_per_edge * options_.pinch_samples_per_edge; }
  int num_samples() const { return static_cast<int>(samples_.size()); }
  SampleState sample(int i) const {
    const Sample& s = samples_[static_cast<std::size_t>(i)];
    return {s.active, s.sliding, s.ideal_C};
  }
  void SetSample(int i, const SampleState& state) {
    Sample& s = samples_[static_cast<std::size_t>(i)];
    s.active = state.active;
    s.sliding = state.sliding;
    s.ideal_C = state.ideal_C;
  }

 private:
  struct Sample {
    int triangle = 0;
    std::array<double, 3> w{};            ///< barycentric weights of the triangle's particles
    bool active = false;
    bool sliding = false;
    Eigen::Vector2d ideal_C{Eigen::Vector2d::Zero()};  ///< ideal position on the contact plane
    Eigen::Vector3d anchor_W{Eigen::Vector3d::Zero()};  ///< spring end during the last step
    double k_N_per_m = 0.0;  ///< spring during the last step: ramps in near the edge
  };
  /// How deep q lies inside both fingers [m]: min over the two of (radius - distance to axis);
  /// negative outside the intersection.
  double DepthInBoth(const Eigen::Vector3d& q) const;
  bool InsideBoth(const Eigen::Vector3d& q) const { return DepthInBoth(q) > 0.0; }
  Eigen::Vector3d SamplePosition(const Sample& s, const Eigen::VectorXd& x) const;

  const textile::FabricModel& patch_;
  ContactOptions options_;
  double radius_thumb_m_, radius_index_m_;
  double k_N_per_m_;  ///< per sample (uniform mesh: triangle area / samples)
  std::vector<Sample> samples_;  ///< every candidate point, fixed at construction
  std::vector<std::uint8_t> near_;  ///< per particle, scratch
  bool active_ = false;
  int num_active_ = 0;
  double weight_sum_ = 0.0;  ///< sum of the active samples' springs [N/m]
  double grip_N_ = 0.0;
  Segment seg_thumb_{}, seg_index_{};
  Eigen::Vector3d origin_W_{Eigen::Vector3d::Zero()};
  Eigen::Matrix3d R_WC_{Eigen::Matrix3d::Identity()};
};

}  // namespace haptex::contact
