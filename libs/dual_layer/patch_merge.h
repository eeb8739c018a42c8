#pragma once
// The coupling of the global fabric with the local layer's patch: merging a PatchResult (the local
// layer's newer, finer shape of the patch interior) before a global step, releasing it after, and
// the velocity sent with the next patch.

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "libs/dual_layer/patch_result.h"
#include "libs/textile/fabric_state.h"

namespace haptex::dual_layer {

/// Takes the result's particles (ids below the fabric's count, free in `state`; refined ids are the
/// local layer's own detail) into the coming global step: each is put where the local layer reported
/// it and held there through the step (its contact forces are too stiff to apply as loads over a
/// whole global step), the rest of the fabric relaxes against it. A newer result replaces the
/// last: the particles in `merged` are released first, then `merged` lists the taken ones (release
/// them after the step with ReleaseMerged). Returns the number of particles rejected (id outside
/// `id_space`, non-finite position); -1 when the result's arrays do not match its ids (nothing
/// merged, nothing released).
int MergePatchResult(const PatchResultData& result, int id_space, textile::FabricState* state,
                     std::vector<int>* merged);

/// Frees the particles MergePatchResult took and clears `merged`.
void ReleaseMerged(textile::FabricState* state, std::vector<int>* merged);

/// The longest the global fabric holds the patch interior where the last result put it when no
/// newer result has come: as long as a held contact waits for its force to resume
/// (device::ForceSafetyConfig::resume_within_s), after which the local layer is taken as gone.
inline constexpr double kLastResultHoldMax_s = 0.100;

/// The patch interior taken from the local layer's results, one global step at a time. A result's
/// particles are held through the step after it (Merge, step, Release). A step that no newer
/// result reached (a late or lost result, a paused local layer) holds them again where the last
/// result put them, up to `max_held_steps` steps after it: relaxed instead, the pressed interior
/// sprang back toward the unpressed global shape, the next patch's border with it, and a held
/// fold felt twice its force after a 2 ms pause of local_contact.
class MergedInterior {
 public:
  /// For a fabric of `num_particles` (room for all of them is kept: merging allocates nothing).
  MergedInterior(int max_held_steps, int num_particles);

  /// MergePatchResult into `state`; the result's particles are held from now.
  int Merge(const PatchResultData& result, int id_space, textile::FabricState* state);
  /// Before a global step: without a result since the last step, holds the last result's particles
  /// again (those still free) at their positions, unless that result is too old.
  void HoldBeforeStep(textile::FabricState* state);
  /// After a global step: frees every held particle.
  void ReleaseAfterStep(textile::FabricState* state);

  /// Steps run without a newer result since the last one that was held again.
  std::uint64_t steps_held_again() const { return steps_held_again_; }

 private:
  std::vector<int> held_, last_result_;
  int max_held_steps_;
  int steps_since_result_ = 0;
  bool result_since_step_ = false;
  std::uint64_t steps_held_again_ = 0;
};

/// The velocity sent with a patch, which the local layer moves the patch border with over the next
/// global step: each particle's mean over the last two global steps ((x_s - x_(s-2)) / 2 dt for
/// the border, free in the global fabric), not its last step's. The merge exchanges shape with the
/// local layer once a step, so the border ring's last-step velocity carries the ring's catch-up
/// with the merged interior, at the step's own period; extrapolated over the next step it comes
/// back in the next result three times over (x_s + (x_s - x_(s-1)) for x alternating by one step),
/// a loop that fed a 50 Hz force oscillation with a resting finger. The two-step mean has no
/// component at that period and keeps the cloth's own motion (exact for constant velocity).
class TwoStepVelocity {
 public:
  /// Call once after every global step with the state's velocities; returns the mean with the
  /// previous call's (the velocities themselves on the first call).
  const Eigen::VectorXd& Update(const Eigen::VectorXd& v_W_m_per_s);

 private:
  Eigen::VectorXd last_, mean_;
};

}  // namespace haptex::dual_layer
