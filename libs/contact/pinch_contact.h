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
#include "libs/contact/pinch_sample_lanes.h"
#include "libs/textile/fabric_model.h"
#include "libs/textile/fabric_state.h"

namespace haptex::contact {

struct PinchResult {
  bool active = false;
  int samples = 0;
  int sliding_samples = 0;
  double grip_N = 0.0;                                        ///< normal force between the fingers
  Eigen::Vector3d normal_W{Eigen::Vector3d::UnitZ()};         ///< z_C: thumb -> index
  Eigen::Vector3d fabric_force_W_N{Eigen::Vector3d::Zero()};  ///< sum of sample springs on the fabric
  Eigen::Vector3d friction_W_N{Eigen::Vector3d::Zero()};      ///< in-plane part of it, on the fingers
  Eigen::Vector2d touch_uv_m{Eigen::Vector2d::Zero()};        ///< mean rest uv of the samples
  Eigen::Vector3d touch_velocity_W{Eigen::Vector3d::Zero()};
  int touch_triangle = -1;  ///< a triangle under the samples (tangent frame)
};

/// PinchContact::Prepare's marks of a particle (bits): in both fingers (the pinch's alone), and
/// certainly farther than the pinch's reach (radius + 2 half thicknesses, more than a finger's
/// own contact reaches) from the thumb's or the index's axis.
constexpr std::uint8_t kPinchOwnedBit = 1, kPinchBeyondThumbBit = 2, kPinchBeyondIndexBit = 4;

class PinchContact {
 public:
  PinchContact(const textile::FabricModel& patch, const ContactOptions& options);

  /// Before the fabric step, with the fingers' poses at its end and the grip normal force:
  /// (re)builds the contact frame, starts samples that entered the intersection (sticking where
  /// they are), drops those that left, applies Coulomb's law to each sample's ideal position
  /// (both faces grip: the limit is 2 mu times the sample's share of the grip), marks the
  /// particles in `owned` (kPinchOwnedBit and the others), and adds the samples' springs (lumped onto their triangle's
  /// particles) to `springs`. Returns false when no fabric lies in the intersection.
  bool Prepare(const FingerPose& thumb, const FingerPose& index, double grip_N, const FrictionCoefficients& mu,
               const textile::FabricState& state, std::vector<std::uint8_t>* owned, AnchorAccumulator* springs);
  /// After the step: the forces as applied and where the fabric is touched.
  void Resolve(const textile::FabricState& state, const Eigen::MatrixX2d& rest_uv_m, PinchResult* result);
  void Reset();
  bool active() const { return active_; }

  /// Sample points for a patch hand-off: sample i belongs to triangle i / samples_per_triangle()
  /// at a fixed barycentric position; its state is carried to the same point of a new patch.
  struct SampleState {
    bool active = false;
    bool sliding = false;
    Eigen::Vector2d ideal_C{Eigen::Vector2d::Zero()};
  };
  int samples_per_triangle() const { return per_triangle_; }
  int num_samples() const { return static_cast<int>(triangle_p_.size()) * per_triangle_; }
  SampleState sample(int i) const {
    const std::size_t l = Lane(i);
    return {k_[l] > 0.0, sliding_[l] != 0, Eigen::Vector2d(ideal_x_[l], ideal_y_[l])};
  }
  void SetSample(int i, const SampleState& state) {
    const std::size_t l = Lane(i);
    // Any spring marks it active until the next Prepare sets the sample's own.
    k_[l] = state.active ? k_N_per_m_ : 0.0;
    sliding_[l] = state.sliding ? -1 : 0;
    ideal_x_[l] = state.ideal_C.x();
    ideal_y_[l] = state.ideal_C.y();
    maybe_active_ = maybe_active_ || state.active;
    // Held, and no longer known to be all at the full spring.
    std::uint8_t& held = triangle_held_[static_cast<std::size_t>(i / per_triangle_)];
    if (state.active || held != 0) held = static_cast<std::uint8_t>(internal::PinchTriangleHold::kSome);
  }

 private:
  /// Lane of sample i (triangle i / per_triangle_, padded to whole chunks of 4).
  std::size_t Lane(int i) const {
    return static_cast<std::size_t>(i / per_triangle_) * static_cast<std::size_t>(lanes_per_triangle_) +
           static_cast<std::size_t>(i % per_triangle_);
  }
  /// How deep q lies inside both fingers [m]: min over the two of (radius - distance to axis);
  /// negative outside the intersection. The exact test of a particle that the squared distances
  /// in C leave too close to call.
  double DepthInBoth(const Eigen::Vector3d& q) const;
  // Prepare's steps, in order.
  /// Each particle's position in C and distances to the axes; marks those in the intersection.
  void LocateParticles(const textile::FabricState& state, std::vector<std::uint8_t>* owned);
  /// Which samples are active and their springs; false when none is.
  bool ClassifySamples();
  /// Coulomb's law for every active sample; their springs summed per particle.
  void ApplyFriction(const FrictionCoefficients& mu);
  /// The per-particle sums as anchor springs.
  void LumpSprings(const textile::FabricState& state, AnchorAccumulator* springs);
  internal::PinchSampleLayout Layout() const;
  internal::PinchTriangleList Triangles(const int* triangles, int num_triangles) const;
  internal::PinchSampleArrays SampleArrays();
  bool InsideBoth(const Eigen::Vector3d& q) const { return DepthInBoth(q) > 0.0; }

  const textile::FabricModel& patch_;
  ContactOptions options_;
  double radius_thumb_m_, radius_index_m_;  ///< reach of the pinch: radius + 2 half thicknesses
  double k_N_per_m_;                        ///< per sample (uniform mesh: triangle area / samples)
  double edge_ramp_m_ = 0.0;                ///< the springs ramp in over this depth (options, at least 0)
  /// Squared distances in C [m^2], margins for rounding included (kMargin): near the
  /// intersection within reach2 of the origin; certainly inside a finger below in_*2, certainly
  /// outside above out_*2, certainly deeper than the ramp below full_*2 (-1: never).
  struct Thresholds {
    double reach2_m2 = 0.0;
    double in_thumb2 = 0.0, in_index2 = 0.0, out_thumb2 = 0.0, out_index2 = 0.0;
    double full_thumb2 = -1.0, full_index2 = -1.0;
    /// A triangle of diameter d [m] holds no sample if its farthest corner's squared distance
    /// exceeds far_*_r2 + far_*_diam d^2 (a bound of (radius + d)^2, margin included).
    double far_thumb_r2 = 0.0, far_thumb_diam = 0.0, far_index_r2 = 0.0, far_index_diam = 0.0;
  } thresholds_;
  int per_triangle_ = 1;                        ///< samples per triangle
  int lanes_per_triangle_ = 4;                  ///< per_triangle_ rounded up to whole 4-lane chunks
  bool avx2_ = false;                           ///< the friction kernel's AVX2 build (same results)
  std::vector<std::array<int, 3>> triangle_p_;  ///< particles of each triangle (compact copy)
  // Every candidate point, fixed at construction: per lane (pinch_sample_lanes.h), triangle-major.
  std::vector<double> ideal_x_, ideal_y_;  ///< ideal position on the contact plane, in C
  std::vector<double> k_;                  ///< spring during the last step (ramps in near the edge); 0: inactive
  std::vector<long long> sliding_;         ///< -1 sliding, 0 sticking
  std::vector<double> lane_w_, lane_k_full_, w_sum_full_, lane_wk_full_;  ///< internal::PinchSampleLayout's
  /// Per triangle, a PinchTriangleHold: kNone if none of its samples is active, kAllFull if the
  /// last classification left every sample at the full spring (and nothing changed them since).
  std::vector<std::uint8_t> triangle_held_;
  bool maybe_active_ = false;  ///< some sample may be active (Reset has work to do)

  // Per tick (sized at construction, so no allocation per tick).
  // Per particle, padded to whole 4-particle lanes (internal::PinchParticleArrays).
  std::vector<std::uint8_t> near_, deep_;
  std::vector<internal::PinchOwned> particle_owned_;
  std::vector<std::uint8_t> beyond_;
  std::vector<double> d2_thumb_, d2_index_;  ///< squared distance to each axis
  std::vector<double> x_C_;                  ///< position in C (at Prepare), 4 doubles per particle
  // Per triangle (the first entries in use), sized at construction.
  std::vector<int> candidates_;  ///< triangles that may hold a sample, ascending
  /// Per candidate: deep and all at the full spring last tick, so left as it is.
  std::vector<std::uint8_t> candidate_unchanged_;
  std::vector<int> classify_;                      ///< the candidates not unchanged, ascending
  std::vector<std::uint8_t> classify_deep_;        ///< per entry of classify_: kPinchDeep or kPinchNotDeep
  std::vector<internal::PinchTriangleHold> hold_;  ///< per entry of classify_
  std::vector<int> active_triangles_;              ///< triangles with an active sample, ascending
  std::vector<std::uint8_t> active_full_;          ///< per entry: all its samples active at the full spring
  int num_active_triangles_ = 0;
  // What Resolve needs, per particle touched by an active sample: sums of w k (ideal - q) and of
  // w k, and of w, over the samples on it (the samples' springs and touch points are linear in
  // the particles).
  std::vector<int> touched_;
  std::vector<internal::PinchParticleSums> touch_sums_;
  std::vector<double> touch_w_;
  Eigen::Vector2d k_ideal_C_{Eigen::Vector2d::Zero()};  ///< sum of k ideal_C over active samples
  int num_sliding_ = 0;
  int last_triangle_ = -1;

  bool active_ = false;
  int num_active_ = 0;
  double weight_sum_ = 0.0;  ///< sum of the active samples' springs [N/m]
  double grip_N_ = 0.0;
  Segment seg_thumb_{}, seg_index_{};
  internal::PinchAxis axis_thumb_C_{}, axis_index_C_{};
  Eigen::Vector3d origin_W_{Eigen::Vector3d::Zero()};
  Eigen::Matrix3d R_WC_{Eigen::Matrix3d::Identity()};
};

}  // namespace haptex::contact
