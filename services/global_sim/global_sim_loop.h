#pragma once
// global_sim's work per global step, apart from sockets. Read: the newest FingerStates (as the
// spheres the fingers may sweep) and PatchResults (merged at once, held through the coming step).
// Update: the scene's loads, one step of the whole fabric, the merged particles released, the
// next patch cut. Write: the LocalPatch to local_contact, a ClothFrame to the viewer when one is
// due, recorded then and also without a viewer when the scene's recording.cloth_frames asks (so
// `haptex view` shows the cloth). Allocates nothing once warmed up.

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "haptex/v1/cloth_frame.pb.h"
#include "haptex/v1/envelope.pb.h"
#include "haptex/v1/local_patch.pb.h"
#include "libs/dual_layer/global_link_delay.h"
#include "libs/dual_layer/patch_cut.h"
#include "libs/dual_layer/patch_data.h"
#include "libs/dual_layer/patch_merge.h"
#include "libs/dual_layer/patch_result.h"
#include "libs/dual_layer/refined_grid.h"
#include "libs/net/messenger.h"
#include "libs/runtime/health_reporter.h"
#include "libs/scene/cloth_setup.h"
#include "libs/textile/fabric_stepper.h"
#include "services/common/outbox.h"

namespace haptex::global_sim {

struct GlobalSimPeers {
  std::optional<services::PeerId> local_contact, viewer;
};

class GlobalSimLoop final {
 public:
  /// The scene's cloth stepped at `rate_hz`. Registers its counters with `health` (which must
  /// outlive the loop). @throws std::invalid_argument for a scene the fabric cannot be made of.
  GlobalSimLoop(const scene::LoadedScene& scene, double rate_hz, const GlobalSimPeers& peers,
                runtime::HealthReporter* health);
  GlobalSimLoop(const GlobalSimLoop&) = delete;
  GlobalSimLoop& operator=(const GlobalSimLoop&) = delete;

  void Read(const v1::Envelope& envelope, double t_s);
  void Update(double t_s, double dt_s);
  void Write(services::Outbox& out);

  const textile::FabricModel& model() const { return cloth_.model; }
  const textile::FabricState& state() const { return cloth_.state; }

  struct Counters {
    std::uint64_t steps = 0, patches_sent = 0, patches_not_sent = 0, results_merged = 0, results_rejected = 0,
                  cloth_frames = 0;
  };
  const Counters& counters() const { return counters_; }

 private:
  void PublishCounters();

  scene::ClothSetup setup_;
  scene::ClothInstance cloth_;
  textile::FabricStepper stepper_;
  scene::SceneLoads loads_;
  GlobalSimPeers peers_;
  runtime::HealthReporter* health_;
  double finger_reach_m_, margin_m_, frame_period_s_;
  bool record_cloth_frames_;
  dual_layer::RefinedGrid refined_;
  dual_layer::MergedInterior merged_;
  dual_layer::TwoStepVelocity cut_velocity_;
  dual_layer::GlobalLinkDelay link_delay_;
  std::array<dual_layer::FingerSphere, 2> spheres_{};
  net::NewestWins newest_states_;
  dual_layer::PatchData patch_;
  bool patch_ready_ = false;
  dual_layer::PatchRect patch_rect_;  ///< of the patch cut this step (empty: none), for the viewer
  std::uint64_t patch_id_ = 0;
  dual_layer::PatchResultData result_;
  double t_s_ = 0.0, next_frame_s_ = 0.0;
  v1::LocalPatch patch_message_;
  v1::ClothFrame frame_;
  Counters counters_;
  struct CounterIds {
    runtime::HealthReporter::CounterId patches, unsent, results, results_bad, held_again, nan, cg, newton, halvings;
  } ids_{};
};

}  // namespace haptex::global_sim
