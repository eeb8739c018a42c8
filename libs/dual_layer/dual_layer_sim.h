#pragma once
// The dual layer in one process, as the two services run it but without sockets or threads: a
// global fabric stepped at the global rate that cuts patches and merges results, and a local
// patch ticked at the local rate that is rebuilt from every cut and handed off. The tests compare
// it with a single layer; the sweep measures its speed/accuracy trade.

#include <array>
#include <deque>
#include <memory>
#include <vector>

#include "libs/contact/contact_options.h"
#include "libs/dual_layer/global_link_delay.h"
#include "libs/dual_layer/local_patch.h"
#include "libs/dual_layer/patch_cut.h"
#include "libs/dual_layer/patch_merge.h"
#include "libs/dual_layer/refined_grid.h"
#include "libs/textile/fabric_model.h"
#include "libs/textile/fabric_state.h"
#include "libs/textile/fabric_stepper.h"

namespace haptex::dual_layer {

class DualLayerSim {
 public:
  DualLayerSim(const textile::FabricMaterial& material, textile::FabricModel global_model,
               textile::FabricState global_state, double global_dt_s, double local_dt_s,
               const contact::ContactOptions& contact, double patch_margin_m, int refinement_levels = 0);

  /// One local tick with the fingers' poses at its end; every global_dt a global step, a new cut
  /// and a hand-off. Returns the contact output of the tick (state I with no patch yet).
  const contact::ContactOutput& Tick(const contact::FingerInput& thumb, const contact::FingerInput& index);

  int handoffs() const { return handoffs_; }
  /// false: new patches start from the global layer's state alone (a control for the hand-off test).
  void set_carry_over(bool carry) { carry_over_ = carry; }
  /// Each way of the link between the layers takes `steps` global steps: a patch is handed off
  /// and a result merged that many steps after they were made (placement with global_sim across a
  /// network).
  void set_link_delay_steps(int steps) { link_delay_steps_ = steps; }
  /// true: patches tell the local layer the link is immediate, whatever it is (a control for the
  /// delay test: the border then moves with global_sim's whole velocity).
  void set_extrapolate_border_in_full(bool in_full) { extrapolate_border_in_full_ = in_full; }
  /// The global link's round trip as global_sim measures it (global_link_delay.h).
  std::uint32_t link_round_trip_steps() const { return link_delay_.round_trip_steps(); }
  PatchRect rect() const { return rect_; }
  /// The patch the local layer ticks now (null before the first cut): where the fabric under the
  /// fingers is between global steps.
  const LocalPatch* patch() const { return patch_.get(); }
  const textile::FabricState& global_state() const { return global_state_; }

 private:
  void GlobalStep(const contact::FingerInput& thumb, const contact::FingerInput& index);
  void HandOffArrived();

  textile::FabricMaterial material_;
  textile::FabricModel global_model_;
  textile::FabricState global_state_;
  textile::FabricStepper global_stepper_;
  double global_dt_s_, local_dt_s_;
  contact::ContactOptions contact_;
  double margin_m_;
  RefinedGrid refined_;
  int ticks_per_global_;
  int tick_ = 0;
  int handoffs_ = 0;
  bool carry_over_ = true;
  int link_delay_steps_ = 0;
  bool extrapolate_border_in_full_ = false;
  std::uint64_t steps_ = 0;       ///< global steps taken
  std::uint64_t patch_step_ = 0;  ///< the step the current patch was cut at
  GlobalLinkDelay link_delay_;
  std::deque<std::unique_ptr<LocalPatch>> patches_in_flight_;
  std::deque<PatchResultData> results_in_flight_;
  std::uint64_t patch_id_ = 0;
  PatchRect rect_;
  std::unique_ptr<LocalPatch> patch_;
  MergedInterior merged_{0, 0};  ///< sized in the constructor
  TwoStepVelocity cut_velocity_;
  PatchData patch_data_;
  contact::ContactOutput idle_;
};

}  // namespace haptex::dual_layer
