#pragma once
// The contact layer of a local fabric patch (paper section 5): classifies the state (I-IX), runs
// the models that state needs, and reports per finger the force, a stiffness for the device
// bridge, the state, and where on the fabric the finger touches. Pure: time comes in as dt.
//
// One tick around a fabric step of the patch:
//   solver.Prepare(thumb, index, dt, &state);   // springs from the contact models into state
//   stepper.Step(&state);                        // libs/textile, springs integrated implicitly
//   const ContactOutput& out = solver.Resolve(state);   // forces, friction, state, touch points
// PatchSimulation (patch_simulation.h) does exactly this.

#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "libs/contact/anchor_accumulator.h"
#include "libs/contact/contact_options.h"
#include "libs/contact/contact_state.h"
#include "libs/contact/finger_fabric_contact.h"
#include "libs/contact/finger_finger_contact.h"
#include "libs/contact/finger_geometry.h"
#include "libs/contact/pinch_contact.h"
#include "libs/contact/secant_stiffness.h"
#include "libs/textile/fabric_model.h"
#include "libs/textile/fabric_state.h"

namespace haptex::contact {

enum FingerSlot : int { kThumb = 0, kIndex = 1 };

struct FingerInput {
  bool present = false;  ///< false: the finger is not simulated (one-finger scenes) or not tracked
  FingerPose pose;       ///< at the end of the coming step
};

/// Everything one finger needs from a tick.
struct FingerContactOutput {
  Eigen::Vector3d force_W_N{Eigen::Vector3d::Zero()};  ///< on the fingertip (clamped)
  /// d force / d finger position, for the bridge's F0 + K dx (negative semi-definite).
  Eigen::Matrix3d stiffness_W_N_per_m{Eigen::Matrix3d::Zero()};
  /// d force / d the other finger's position: where the fingers press on each other (II, III,
  /// and the grip of VIII, IX) the force follows their distance, so each finger's force changes
  /// with the other's motion too. The bridge renders both terms, so that neither finger's motion
  /// reaches the other's force only through a late F0.
  Eigen::Matrix3d cross_stiffness_W_N_per_m{Eigen::Matrix3d::Zero()};
  bool force_clamped = false;       ///< the models asked for more than max_finger_force_N
  bool on_textile = false;          ///< with hysteresis
  int contact_particles = 0;        ///< inverted proxies on this finger
  double normal_force_N = 0.0;      ///< along the contact normal, >= 0
  double tangential_force_N = 0.0;  ///< in the contact plane, >= 0
  /// What the friction law holds the finger's contacts to (paper Fig. 9's F^T/F^N sticks up to
  /// mu_s and slides at mu_d in these): on the fabric, the load Coulomb's law decided on before the
  /// step (FingerFabricResult::law_load); pinched, the grip and half the pinch's friction; on the
  /// other finger, that contact's. normal/tangential_force_N differ by the fabric's response.
  double friction_normal_N = 0.0;
  double friction_tangential_N = 0.0;
  Eigen::Vector3d contact_normal_W{Eigen::Vector3d::UnitZ()};  ///< outward from the finger
  /// The largest tangential_force_N / normal_force_N the finger's contacts hold now: mu_s of each
  /// kind of contact it has (fabric, the other finger), and at least the present ratio (a finger
  /// ploughing through a dent feels the fabric's flanks too). 0 without normal force: no cone. The
  /// bridge keeps the force it extrapolates between two models inside this cone around
  /// -contact_normal_W (libs/device/force_model.h).
  double friction_cone_mu = 0.0;
  /// Touch point in fabric coordinates (u warp, v weft) [m], slip of the finger over the fabric
  /// in fabric coordinates [m/s], and the finger's distal axis angle in the fabric plane [rad].
  bool touching = false;
  Eigen::Vector2d touch_uv_m{Eigen::Vector2d::Zero()};
  Eigen::Vector2d slip_uv_m_per_s{Eigen::Vector2d::Zero()};
  double finger_angle_rad = 0.0;
};

struct ContactOutput {
  ContactState state = ContactState::kI;
  ContactEvidence evidence;
  std::array<FingerContactOutput, 2> finger{};
  FingerFingerResult finger_finger;  ///< II/III, or the grip of VIII/IX
  PinchResult pinch;
  std::int64_t ticks = 0;
};

/// Counters of trouble; they only grow.
struct ContactDiagnostics {
  std::int64_t force_clamps = 0;
  std::int64_t non_finite_inputs = 0;  ///< finger poses with NaN/Inf: that finger is ignored
  std::int64_t non_finite_forces = 0;  ///< a model produced NaN/Inf: zero force that tick
};

class ContactSolver {
 public:
  /// `patch` must outlive the solver. `uv_origin_m` is added to the patch's rest coordinates so
  /// touch points come out in the whole fabric's coordinates.
  /// @throws std::invalid_argument for invalid options.
  ContactSolver(const textile::FabricModel& patch, const ContactOptions& options,
                const Eigen::Vector2d& uv_origin_m = Eigen::Vector2d::Zero());

  void Prepare(const FingerInput& thumb, const FingerInput& index, double dt_s, textile::FabricState* state);
  const ContactOutput& Resolve(const textile::FabricState& state);

  /// Forgets every contact (the next tick starts from state I).
  void Reset();

  const ContactOutput& output() const { return output_; }
  const ContactDiagnostics& diagnostics() const { return diagnostics_; }
  /// Contact force on each patch particle during the last step [N], 3n (for PatchResult).
  const Eigen::VectorXd& particle_force_W_N() const { return particle_force_W_N_; }
  const ContactOptions& options() const { return options_; }
  FingerFabricContact& finger_contact(int slot) { return finger_fabric_[static_cast<std::size_t>(slot)]; }
  const FingerFabricContact& finger_contact(int slot) const { return finger_fabric_[static_cast<std::size_t>(slot)]; }
  PinchContact& pinch() { return pinch_; }
  const PinchContact& pinch() const { return pinch_; }
  /// Takes over the classifier's hysteresis, the stiffness estimates and the previous finger
  /// poses of `other` (a patch hand-off: the fingers did not change, only the fabric patch did).
  void ContinueFrom(const ContactSolver& other);

 private:
  void FinishFinger(int slot, const FingerFabricResult& one, const textile::FabricState& state);
  void TouchFrame(int triangle, const textile::FabricState& state, const FingerPose& pose,
                  const Eigen::Vector3d& relative_velocity_W, FingerContactOutput* out) const;

  const textile::FabricModel& patch_;
  ContactOptions options_;
  Eigen::MatrixX2d rest_uv_m_;          ///< per particle, with the origin added
  std::vector<int> particle_triangle_;  ///< one triangle per particle (tangent frame)
  AnchorAccumulator springs_;
  std::vector<std::uint8_t> pinch_owned_;
  std::array<FingerFabricContact, 2> finger_fabric_;
  FingerFingerContact finger_finger_;
  PinchContact pinch_;
  std::array<SecantStiffness, 2> stiffness_;
  std::array<FilteredHysteresis, 2> on_textile_;
  FilteredHysteresis dynamic_;
  Hysteresis touching_;

  std::array<FingerInput, 2> input_{};
  std::array<FingerPose, 2> previous_pose_{};
  std::array<bool, 2> have_previous_{};
  double dt_s_ = 0.0;
  bool pinching_ = false;
  Eigen::VectorXd particle_force_W_N_;
  /// The particles whose particle_force_W_N_ Resolve last set: [0, num_force_particles_).
  std::vector<int> force_particles_;
  int num_force_particles_ = 0;
  ContactOutput output_;
  ContactDiagnostics diagnostics_;
};

}  // namespace haptex::contact
