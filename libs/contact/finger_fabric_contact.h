#pragma once
// States IV-VII (paper 5.3): one finger on the fabric. Every particle that enters the finger gets
// an inverted proxy: a spring to a held point on the finger's surface that moves with the finger.
// The force on the finger is F^d = sum_i k_i (x_i - x_i^E).
//
// Friction is decided for the finger as a whole (the god-object proxy of 5.3 sticks or slides;
// Table 1 makes static/dynamic a state of the finger; Fig. 9 plots F^T/F^N of F^d): the paper's
// stick condition F^T < mu_s F^N is checked on F^d (FingerCone in coulomb_friction.h). While it
// holds, every held point stays where it is on the finger. When it fails, the held points slip
// together, each between its old and its desired point on the curved surface as in the paper's
// Fig. 5, with one Coulomb coefficient for all (SharedSlipCoefficient): in the break-away tick
// to F^T = mu_s F^N, then to mu_d F^N while the finger slides, until sliding needs no more than
// mu_d F^N (the finger stopped or turned) and the contact sticks again.
//
// Why not per particle (the paper's text): pressing the finger in stretches the fabric over the
// pad, so the held points carry radial loads before the rub, and the rim's particles carry little
// normal force; per-particle stick-slip lets them slip one after another, and the finger's F^T/F^N
// never got above 0.23-0.26 for mu_s = 0.4 instead of the figure's 0.4.

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "libs/contact/anchor_accumulator.h"
#include "libs/contact/contact_options.h"
#include "libs/contact/coulomb_friction.h"
#include "libs/contact/finger_geometry.h"
#include "libs/textile/fabric_state.h"

namespace haptex::contact {

/// What one finger's inverted proxies did over a step.
struct FingerFabricResult {
  Eigen::Vector3d force_W_N{Eigen::Vector3d::Zero()};  ///< on the finger
  Eigen::Vector3d normal_W{Eigen::Vector3d::UnitZ()};  ///< mean outward contact normal
  double normal_sum_N = 0.0;                           ///< sum of per-particle normal forces
  double sliding_normal_N = 0.0;                       ///< part of normal_sum_N whose particles slide
  /// Sum of the per-particle friction springs on the finger (their tangential part).
  Eigen::Vector3d friction_W_N{Eigen::Vector3d::Zero()};
  /// The load Coulomb's law held the finger to before the step (FingerCone of the normal forces
  /// and the friction springs as the law left them): on the cone of mu_s where it broke away, of
  /// mu_d while it slides. The step's response (the fabric under the finger gives) makes the force
  /// the device gets differ from it.
  FingerConeLoad law_load;
  int particles = 0;                                          ///< particles in contact after the step
  int strongest_particle = -1;                                ///< particle with the largest normal force
  Eigen::Vector2d touch_uv_m{Eigen::Vector2d::Zero()};        ///< normal-force weighted, patch rest uv
  Eigen::Vector3d touch_velocity_W{Eigen::Vector3d::Zero()};  ///< fabric velocity there
};

class FingerFabricContact {
 public:
  /// `particle_area_m2` (size n): the fabric area each particle stands for.
  FingerFabricContact(const Eigen::VectorXd& particle_area_m2, const FingerShape& shape, const ContactOptions& options);

  /// Before the fabric step, with the finger's pose at the end of the step: starts contacts for
  /// particles inside the finger, drops those now outside, applies Coulomb's law to the finger
  /// (the held points moved with it; with the particles where the last step left them, the finger
  /// sticks or its held points slide along the curved surface) and adds a spring per contact
  /// particle to `springs`. Particles with `excluded[p] & excluded_bits` (the pinch owns them, or
  /// they are certainly out of the finger's reach) and prescribed particles have no contact. The
  /// finger slides if any of its contacts is marked sliding (all are marked alike, so a patch
  /// hand-off that copies ParticleContact keeps the finger's state).
  void Prepare(const FingerPose& pose, const textile::FabricState& state, const std::vector<std::uint8_t>& excluded,
               const FrictionCoefficients& mu, AnchorAccumulator* springs, std::uint8_t excluded_bits = 0xff);

  /// After the step: the force on the finger from the springs as the step applied them, the
  /// per-particle normal forces for the next step's friction, and where the finger touches.
  void Resolve(const FingerPose& pose, const textile::FabricState& state, const Eigen::MatrixX2d& rest_uv_m,
               FingerFabricResult* result);

  void Reset();
  int num_active() const;
  bool active(int p) const { return particles_[static_cast<std::size_t>(p)].active; }

  /// Held point of particle p in the finger frame, and whether it slides (for patch hand-off).
  struct ParticleContact {
    bool active = false;
    bool sliding = false;  ///< the finger's friction state (the same for all its contacts)
    Eigen::Vector3d held_F{Eigen::Vector3d::Zero()};
    Eigen::Vector3d anchor_W{Eigen::Vector3d::Zero()};  ///< spring end during the last step
    Eigen::Vector3d normal_W{Eigen::Vector3d::UnitZ()};
    double normal_N = 0.0;  ///< after the last step
  };
  const ParticleContact& particle(int p) const { return particles_[static_cast<std::size_t>(p)]; }
  void SetParticle(int p, const ParticleContact& contact) {
    particles_[static_cast<std::size_t>(p)] = contact;
    dirty_ = true;
    slots_current_ = false;
  }

 private:
  FingerShape shape_;
  double radius_eff_m_;
  Eigen::VectorXd k_N_per_m_;  ///< per particle
  std::vector<ParticleContact> particles_;
  bool dirty_ = false;  ///< particles_ may differ from the default (Reset has work to do)
  // Scratch of Prepare, one column/entry per contact (sized once: no allocation per tick).
  std::vector<int> slot_particle_;
  Eigen::Matrix3Xd slot_free_W_;      ///< where the particle meets the surface
  Eigen::Matrix3Xd slot_spring_W_N_;  ///< k_i s_i: friction spring, held point carried along
  Eigen::VectorXd slot_ratio_;        ///< k_i |s_i| / F_i^N
  FingerConeLoad law_load_;           ///< of the last Prepare
  /// Whether the active particles are still exactly slot_particle_[0, num_slots_) (in order)
  /// and all slide iff slots_sliding_, as the last Prepare left them: then Resolve and the next
  /// Prepare visit those instead of scanning every particle.
  bool slots_current_ = false;
  int num_slots_ = 0;
  bool slots_sliding_ = false;
};

}  // namespace haptex::contact
