#pragma once
// States VIII/IX (paper 5.4): the fabric squeezed between thumb and index. A shared contact frame
// C (origin on the contact plane midway between the finger surfaces, z_C from thumb to index)
// carries sample points: equally spaced points of the fabric (more than its particles) that lie
// in the intersection of the two fingers. Each sample keeps its ideal position in C, a spring
// pulls its fabric point there, and Coulomb friction moves the ideal position when the spring
// exceeds the sample's share of the grip. Particles inside the intersection belong to this model
// alone; the others keep the one-finger model without friction, so the fabric can fold over one
// finger while pinched.

#include <algorithm>
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
    maybe_active_ = maybe_active_ || state.active;
    if (state.active) triangle_held_[static_cast<std::size_t>(i / per_triangle_)] = 1;
  }

 private:
  struct Sample {
    Eigen::Vector2d ideal_C{Eigen::Vector2d::Zero()};  ///< ideal position on the contact plane
    double k_N_per_m = 0.0;  ///< spring during the last step: ramps in near the edge
    bool active = false;
    bool sliding = false;
  };
  /// A capsule axis in the contact frame C, for squared distances without a square root.
  struct AxisC {
    Eigen::Vector3d a{Eigen::Vector3d::Zero()};
    Eigen::Vector3d ab{Eigen::Vector3d::Zero()};
    double inv_len2 = 0.0;  ///< 0 for a sphere
    [[gnu::always_inline]] double Distance2(const Eigen::Vector3d& q) const {
      const Eigen::Vector3d aq = q - a;
      const double t = std::clamp(aq.dot(ab) * inv_len2, 0.0, 1.0);
      return (aq - t * ab).squaredNorm();
    }
  };
  /// How deep q lies inside both fingers [m]: min over the two of (radius - distance to axis);
  /// negative outside the intersection. The exact test of a particle that the squared distances
  /// in C leave too close to call.
  double DepthInBoth(const Eigen::Vector3d& q) const;
  bool InsideBoth(const Eigen::Vector3d& q) const { return DepthInBoth(q) > 0.0; }

  const textile::FabricModel& patch_;
  ContactOptions options_;
  double radius_thumb_m_, radius_index_m_;  ///< reach of the pinch: radius + 2 half thicknesses
  double k_N_per_m_;  ///< per sample (uniform mesh: triangle area / samples)
  int per_triangle_ = 1;  ///< samples per triangle
  std::vector<std::array<int, 3>> triangle_p_;  ///< particles of each triangle (compact copy)
  std::vector<std::array<double, 3>> sample_w_;  ///< barycentric weights of sample j of any triangle
  std::vector<Sample> samples_;  ///< every candidate point, fixed at construction; triangle-major
  std::vector<std::uint8_t> triangle_held_;  ///< per triangle: 0 if none of its samples is active
  bool maybe_active_ = false;  ///< some sample may be active (Reset has work to do)

  // Per tick (sized at construction, so no allocation per tick).
  std::vector<std::uint8_t> near_;  ///< per particle
  std::vector<double> d2_thumb_, d2_index_;  ///< per particle: squared distance to each axis
  std::vector<double> dist_thumb_, dist_index_;  ///< per particle: distance to each axis
  Eigen::Matrix3Xd x_C_;  ///< per particle: position in C (at Prepare)
  std::vector<int> active_triangles_;  ///< triangles with an active sample, ascending
  /// Per entry of active_triangles_: 1 if all its samples are active at the full spring.
  std::vector<std::uint8_t> active_full_;
  // Such a triangle's sums over its samples that depend only on the weights (the same
  // additions in the same order as the general loop, so the same bits).
  std::vector<std::array<double, 3>> full_wk_;  ///< per sample j: w_j k_full
  std::array<double, 3> full_kw_{}, full_ww_{};  ///< per corner: sum_j w_j k_full, sum_j w_j
  // What Resolve needs, per particle touched by an active sample: sum of w k and of w over the
  // samples on it (the samples' springs and touch points are linear in the particles).
  std::vector<int> touched_;
  std::vector<std::uint32_t> touch_stamp_;  ///< == stamp_: touched this tick (no clearing)
  std::uint32_t stamp_ = 0;
  std::vector<double> touch_k_, touch_w_;
  Eigen::Matrix3Xd touch_kd_C_;  ///< sum of w k (anchor - sample point), in C
  Eigen::Vector2d k_ideal_C_{Eigen::Vector2d::Zero()};  ///< sum of k ideal_C over active samples
  int num_sliding_ = 0;
  int last_triangle_ = -1;

  bool active_ = false;
  int num_active_ = 0;
  double weight_sum_ = 0.0;  ///< sum of the active samples' springs [N/m]
  double grip_N_ = 0.0;
  Segment seg_thumb_{}, seg_index_{};
  AxisC axis_thumb_C_{}, axis_index_C_{};
  Eigen::Vector3d origin_W_{Eigen::Vector3d::Zero()};
  Eigen::Matrix3d R_WC_{Eigen::Matrix3d::Identity()};
};

}  // namespace haptex::contact
