#pragma once
// The dual layer in one process, exactly as the two services do it but without sockets: a global
// fabric stepped at the global rate that cuts patches (services/global_sim/patch_cutter) and
// merges results, and a local patch ticked at the local rate that is rebuilt from every cut and
// handed off (services/local_contact/local_patch_runtime). Tests compare it with a single layer.

#include <array>
#include <memory>
#include <vector>

#include "libs/contact/contact_options.h"
#include "libs/textile/fabric_model.h"
#include "libs/textile/fabric_state.h"
#include "libs/textile/fabric_stepper.h"
#include "services/common/refined_grid.h"
#include "services/global_sim/patch_cutter.h"
#include "services/global_sim/patch_merge.h"
#include "services/local_contact/local_patch_runtime.h"

namespace haptex::local_contact::testing {

/// The scenario the consistency test and the sweep share: a 3 x 8 cm strip hanging from a clamp
/// at z = 0 (warp down, weft along x), `spacing_m` apart, pinched 6 cm below the clamp.
struct Strip {
  textile::FabricModel model;
  textile::FabricState state;
};
Strip PinchStretchStrip(const textile::FabricMaterial& material, double spacing_m);
/// The fingers at time t: approach and squeeze (0.3 s), hold, pull down 3 mm (0.5-2.0 s), hold.
std::array<contact::FingerInput, 2> PinchStretchFingers(double t_s, const contact::ContactOptions& o);

class DualLayerHarness {
 public:
  DualLayerHarness(const textile::FabricMaterial& material, textile::FabricModel global_model,
                   textile::FabricState global_state, double global_dt_s, double local_dt_s,
                   const contact::ContactOptions& contact, double patch_margin_m,
                   int refinement_levels = 0);

  /// One local tick with the fingers' poses at its end; every global_dt a global step, a new cut
  /// and a hand-off. Returns the contact output of the tick (state I with no patch yet).
  const contact::ContactOutput& Tick(const contact::FingerInput& thumb, const contact::FingerInput& index);

  int handoffs() const { return handoffs_; }
  /// false: new patches start from global_sim's state alone (a control for the hand-off test).
  void set_carry_over(bool carry) { carry_over_ = carry; }
  global_sim::PatchRect rect() const { return rect_; }
  const textile::FabricState& global_state() const { return global_state_; }

 private:
  void GlobalStep(const contact::FingerInput& thumb, const contact::FingerInput& index);

  textile::FabricMaterial material_;
  textile::FabricModel global_model_;
  textile::FabricState global_state_;
  textile::FabricStepper global_stepper_;
  double global_dt_s_, local_dt_s_;
  contact::ContactOptions contact_;
  double margin_m_;
  services::RefinedGrid refined_;
  int ticks_per_global_;
  int tick_ = 0;
  int handoffs_ = 0;
  bool carry_over_ = true;
  std::uint64_t patch_id_ = 0;
  global_sim::PatchRect rect_;
  std::unique_ptr<PatchRuntime> patch_;
  std::vector<int> merged_;
  global_sim::TwoStepVelocity cut_velocity_;
  v1::LocalPatch patch_message_;
  v1::PatchResult result_message_;
  contact::ContactOutput idle_;
};

}  // namespace haptex::local_contact::testing
