#pragma once
// Every dial of the contact models: inputs (from the scene), never constants of the code.

#include "libs/contact/coulomb_friction.h"
#include "libs/contact/finger_geometry.h"

namespace haptex::contact {

struct ContactOptions {
  FingerShape thumb;
  FingerShape index;
  /// Half the fabric's thickness: particles are the mid-surface, so fingers touch it this far
  /// out from their skin [m].
  double fabric_half_thickness_m = 0.0003;

  FrictionCoefficients finger_fabric{0.4, 0.2};
  FrictionCoefficients finger_finger{0.8, 0.6};

  /// II/III (and the grip of VIII/IX): normal spring between the fingers, paper 5.2 [N/m].
  double finger_finger_normal_N_per_m = 1250.0;
  /// II/III: the artificial tangential spring of the finger-finger proxy [N/m].
  double finger_finger_tangential_N_per_m = 1250.0;
  /// Stiffness of the finger pad per contact area [N/m per m^2]: the inverted proxy's spring of a
  /// particle (IV-VII) and a pinch sample's spring (VIII/IX) get this times the fabric area they
  /// stand for, so the finger's contact stiffness does not depend on the mesh. The default puts
  /// the paper's 1.25 N/mm over a 1 cm^2 pad.
  double pad_stiffness_N_per_m3 = 1.25e7;
  /// VIII/IX: sample points per triangle edge (n^2 per triangle): more points than particles.
  int pinch_samples_per_edge = 2;
  /// VIII/IX: a sample's spring and share of the grip ramp in over this depth inside the finger
  /// intersection [m], so samples entering or leaving it change the force smoothly.
  double pinch_edge_ramp_m = 0.0005;

  /// Fingers touch (directly or through fabric) at zero gap; they stop touching above this gap [m].
  double touch_release_gap_m = 0.0002;
  /// Slip fraction of a finger's friction load above which the contact is dynamic, and below
  /// which it is static again (hysteresis).
  double dynamic_enter_fraction = 0.6;
  double dynamic_leave_fraction = 0.4;
  /// A finger touches the textile when its normal force exceeds this, and stops below half [N].
  double textile_contact_force_N = 0.01;
  /// Time constant of the filters on the classifier's evidence before the thresholds above [s], in
  /// [0, 1]; 0: none. Each finger's normal load: followed at once when it rises, decaying with
  /// this time constant (a peak hold); the slip fraction: low-passed. A contact whose load or slip
  /// swings across the thresholds every few ticks then keeps one state (contact_state.h).
  double state_filter_s = 0.01;

  /// The largest force one finger may get from the contact models [N] (the bridge clamps again
  /// to the device limits).
  double max_finger_force_N = 40.0;
  /// Cap of the stiffness estimate handed to the device bridge [N/m].
  double max_stiffness_N_per_m = 2000.0;
  /// Time constant of the secant stiffness estimate [s].
  double stiffness_filter_s = 0.005;
};

/// @throws std::invalid_argument naming the option (non-positive radius or stiffness,
/// mu_dynamic > mu_static, negative mu, ...).
void ValidateContactOptions(const ContactOptions& options);

}  // namespace haptex::contact
