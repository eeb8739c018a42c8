#pragma once
// local_contact's work per haptic tick, apart from sockets and threads. Read: the newest
// FingerStates (newest wins) and LocalPatches (handed to the patch builder). Update: swap in a
// built patch (hand-off by particle id), run the contact models and one step of the patch's
// dynamics. Write: the ForceModel to the bridge, a TouchTrace to tactile (recorded, not sent, when
// there is no tactile service), and once per global step
// the PatchResult to global_sim. Allocates nothing once warmed up; never waits for a patch: with
// none yet it sends zero force, and with global_sim late it renders from the patch it has.

#include <array>
#include <cstdint>
#include <memory>
#include <optional>

#include "haptex/v1/envelope.pb.h"
#include "libs/contact/contact_solver.h"
#include "libs/dual_layer/local_patch.h"
#include "libs/dual_layer/patch_result.h"
#include "libs/net/messenger.h"
#include "libs/runtime/health_reporter.h"
#include "services/common/outbox.h"
#include "services/local_contact/patch_builder.h"

namespace haptex::local_contact {

struct LocalContactConfig {
  double rate_hz = 1000.0;
  std::array<bool, 2> scene_fingers{true, true};  ///< by slot: which fingers the scene simulates
  /// How long the bridge may apply a ForceModel after receiving it (device::ForceSafetyConfig's
  /// staleness limit caps it on the bridge's side).
  double force_model_ttl_s = 0.010;
  /// No FingerStates for this long: where the fingers are is unknown, and no ForceModel is sent (the
  /// bridge's model lifetime takes the force away) until fresh ones come. A model computed from
  /// old poses would be wrong, and arriving old it would be reported as a slow link.
  double finger_states_stale_s = 0.050;
  /// The viewer's copies of the ForceModel and TouchTrace: a person watches at most this often.
  /// Each finger's copy is the strongest force of the ticks since the last one (a peak hold), so a
  /// spike shorter than the viewer's period still shows.
  double viewer_hz = 30.0;
};

struct LocalContactPeers {
  services::PeerId bridge = 0;
  std::optional<services::PeerId> global_sim, tactile, viewer;
};

class LocalContactLoop final {
 public:
  /// Registers its counters with `health` (which must outlive the loop). `builder` builds the
  /// patches the loop receives and must outlive it.
  LocalContactLoop(const LocalContactConfig& config, const LocalContactPeers& peers, PatchBuilder* builder,
                   runtime::HealthReporter* health);

  void Read(const v1::Envelope& envelope, double t_s);
  void Update(double t_s, double dt_s);
  void Write(services::Outbox& out);
  /// Zero force to the bridge (the loop is stopping; the bridge's watchdog would ramp down anyway).
  void WriteZeroForce(services::Outbox& out);

  /// The patch being rendered (null before the first).
  const dual_layer::LocalPatch* patch() const { return patch_.get(); }
  /// The contact state of the last tick with a patch (I before any).
  contact::ContactState contact_state() const {
    return contact_ != nullptr ? contact_->state : contact::ContactState::kI;
  }

  struct Counters {
    std::uint64_t force_models_sent = 0, patches_received = 0, patches_dropped_busy = 0, patches_rejected = 0,
                  patch_handoffs = 0, patch_results_sent = 0;
    std::uint64_t stale_finger_states_ticks = 0;  ///< ticks without fresh FingerStates: no model sent
    std::array<std::uint64_t, 9> state_ticks{};   ///< ticks in contact state I..IX
  };
  const Counters& counters() const { return counters_; }

 private:
  void PublishCounters();
  void HoldPeakForViewer();

  LocalContactConfig config_;
  LocalContactPeers peers_;
  PatchBuilder* builder_;
  runtime::HealthReporter* health_;
  std::unique_ptr<dual_layer::LocalPatch> patch_;
  net::NewestWins newest_states_;
  std::array<contact::FingerInput, 2> fingers_{};
  std::array<bool, 2> in_contact_{};  ///< by slot: the finger pushes at the bridge's pose
  std::array<bool, 2> ahead_{};       ///< by slot: the finger is met a haptic round trip ahead
  std::array<Eigen::Vector3d, 2> at_bridge_W_m_{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  std::uint64_t controller_sequence_ = 0;
  double finger_states_rx_s_ = -1.0;                 ///< when the newest FingerStates arrived; < 0: never
  bool fingers_known_ = false;                       ///< this tick: FingerStates are fresh
  std::uint64_t global_step_ = 0;                    ///< of the newest patch received
  const contact::ContactOutput* contact_ = nullptr;  ///< this tick's, null without a patch
  bool result_due_ = false;
  std::int64_t viewer_every_ticks_ = 1, ticks_to_viewer_ = 0;
  v1::ForceModel force_model_;
  v1::ForceModel viewer_force_model_;      ///< by finger: the strongest of the ticks since the last copy sent
  std::array<double, 2> viewer_peak_n_{};  ///< by slot: its force's magnitude
  bool viewer_force_held_ = false;         ///< a tick has been held since the last copy sent
  v1::TouchTrace touch_;
  dual_layer::PatchResultData result_;
  v1::PatchResult result_message_;
  Counters counters_;
  struct CounterIds {
    runtime::HealthReporter::CounterId models, patches, busy, rejected, handoffs, results, stale_states;
    std::array<runtime::HealthReporter::CounterId, 9> states;
  } ids_{};
};

}  // namespace haptex::local_contact
