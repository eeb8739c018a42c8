#pragma once
// The device bridge's pure core: one Tick per 5 kHz period turns the newest controller status
// and the newest ForceModels into a CommandFrame. services/device_bridge wraps it with a socket
// and a loop; nothing here reads a clock, blocks or allocates after construction.

#include <Eigen/Geometry>
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>

#include "libs/device/finger_state.h"
#include "libs/device/finger_state_estimator.h"
#include "libs/device/force_model.h"
#include "libs/device/force_safety.h"
#include "libs/device/grab_protocol.h"
#include "libs/device/latency_tracker.h"
#include "libs/device/passivity_controller.h"
#include "libs/device/resume_proxy.h"

namespace haptex::device {

/// Controller frames whose arrival the bridge remembers, to age the models answering them: 1.6 s
/// at 5 kHz, longer than any round trip it renders.
inline constexpr std::size_t kFrameHistory = 8192;

/// Everything the bridge core needs. Validate() throws std::invalid_argument with a clear message.
struct DeviceBridgeConfig {
  FingerStateEstimatorConfig estimator;
  ForceSafetyConfig safety;
  PassivityConfig passivity;
  ResumeProxyConfig resume;
  GrabValueLimits value_limits;
  /// No accepted StatusFrame for this long: device lost, force zero, start-up ramp on return.
  double device_lost_after_s = 0.050;
  /// A gap this long between two bridge ticks (the host process stalled) puts the controller's
  /// state in doubt: its host timeout is 5 ms (1 ms is left for link jitter) and may have fired
  /// before its flag could reach us. The bridge then goes on commanding and waits for a status
  /// that echoes a command sent after the gap: without HOST_TIMEOUT on it or on any status before
  /// it, the device held the force all along (cutting it would let the user's fingers fall into
  /// the fabric and come back against more force); with it, or with no such status within
  /// gap_confirm_window_s, the bridge disarms and the force ramps in again. Meanwhile a controller
  /// that did time out moves to the commanded force at its own slew limit (protocol rule).
  double disarm_after_tick_gap_s = 0.004;
  /// How long the bridge waits for a status answering a command sent after a tick gap: about ten
  /// controller periods, the round trip of a device link with room for jitter.
  double gap_confirm_window_s = 0.002;
  /// Evaluate ForceModels at the predicted pose (compensates the link latency) or the measured one.
  bool evaluate_at_predicted_pose = true;
  /// The longest haptic-link round trip rendered: a ForceModel arriving longer than this after the
  /// controller frame it answers is refused (the force ramps to zero and the link is reported
  /// slow) until younger ones come again. Every model is aged on the bridge's own clock, from the
  /// arrival of the controller frame it answers (ForceModel.based_on_controller_sequence).
  double max_model_age_s = 0.15;
  /// A slow link is rendered again once every model has been younger than
  /// recover_fraction x max_model_age_s for recover_after_s: no flapping at the limit.
  double recover_fraction = 0.8;
  double recover_after_s = 0.5;
  /// Time constant of the haptic round-trip estimate that sets the link horizon [s].
  double round_trip_filter_s = 1.0;
  /// A controller echoing a command sequence newer than any this bridge sent is taking commands
  /// from someone else: force off (a fault, counted and reported) until its echoes have been the
  /// bridge's own again for this long; then the start-up ramp.
  double foreign_echo_hold_s = 0.5;
  /// Pose of the device workspace frame D in the world frame W.
  Eigen::Isometry3d X_WD{Eigen::Isometry3d::Identity()};

  void Validate() const;
};

/// Faults the bridge counted outside the frame decoder and the safety stages.
struct BridgeCounters {
  std::uint64_t ticks = 0;
  std::uint64_t status_out_of_order = 0;  ///< valid frame, sequence not newer: ignored
  std::uint64_t device_lost_events = 0;   ///< transitions present -> lost
  std::uint64_t force_models = 0;         ///< ForceModels received
  std::uint64_t tick_gap_disarms = 0;     ///< gaps >= disarm_after_tick_gap_s that disarmed
  std::uint64_t tick_gaps_held = 0;       ///< such gaps the controller confirmed it held through
  /// Transitions into a watchdog zero of an allowed force: the models fell silent for 20 ms (a
  /// paused host or a stalled local_contact), not refused for a slow link.
  std::uint64_t stale_model_cuts = 0;
  std::uint64_t slow_link_ticks = 0;       ///< ticks in which models were refused for their age
  std::uint64_t models_unknown_basis = 0;  ///< finger models based on no frame the bridge remembers
  std::uint64_t slow_link_events = 0;      ///< transitions into refusing models for age
  std::uint64_t foreign_echoes = 0;        ///< status frames echoing a command this bridge never sent
  std::uint64_t foreign_echo_events = 0;   ///< transitions into the foreign-echo fault
  std::uint64_t host_timeout_cuts = 0;     ///< transitions into the controller's HOST_TIMEOUT
  /// Cuts of a held contact (either finger; ResumeProxy), by what cut it first.
  std::array<std::uint64_t, 6> held_cuts_by_cause{};
  std::uint64_t resumes_limited = 0;  ///< resumes whose force the bound held down
  std::uint64_t contacts_ended = 0;   ///< cuts too long to resume: the contact ended
};

/// What cut the force of a held contact, in the order the bridge looks for it.
enum class CutCause : std::uint8_t { kBridgeStall, kHostTimeout, kStaleModels, kRefusedModels, kDeviceLost, kHeldOff };
inline constexpr std::size_t kCutCauseCount = 6;
const char* CutCauseName(CutCause cause);

/// One resume after a cut of a held contact, finished (the bound's watch over, the contact ended, or
/// the finger let go). Times on the host clock.
struct ResumeRecord {
  std::uint64_t number = 0;  ///< 1, 2, ... over the bridge's life
  CutCause cause = CutCause::kBridgeStall;
  Manipulator finger = Manipulator::kThumb;
  double cut_at_s = 0.0;
  double held_N = 0.0;   ///< mean over the 100 ms before the cut
  double asked_N = 0.0;  ///< largest force the model and the return spring asked for
  double peak_N = 0.0;   ///< largest force commanded
  bool limited = false;  ///< the bound held it down
  bool ended = false;    ///< too long: the contact ended instead
};
inline constexpr std::size_t kResumeHistory = 16;

/// Bridge core for both manipulators. Non-copyable (holds ~80 kB of histograms: create it once,
/// e.g. with std::make_unique, before the loop starts).
class DeviceBridge {
 public:
  /// @throws std::invalid_argument if `config` is invalid.
  explicit DeviceBridge(const DeviceBridgeConfig& config);
  DeviceBridge(const DeviceBridge&) = delete;
  DeviceBridge& operator=(const DeviceBridge&) = delete;

  /// Decodes one controller datagram received at host time `t_rx_s`; counts it under its
  /// FrameError. Accepted frames newer than the last update the finger states.
  FrameError OnStatusDatagram(std::span<const std::byte> datagram, double t_rx_s);

  /// Installs the newest ForceModel for one finger, received at host time `t_rx_s` and computed
  /// from the finger states of controller frame `based_on_controller_sequence`: its age is counted
  /// from that frame's arrival.
  void SetForceModel(Manipulator finger, const ForceModel& model, double t_rx_s,
                     std::uint64_t based_on_controller_sequence);

  /// One bridge period at host time `t_s` (`dt_s` since the previous Tick): evaluates the models,
  /// applies the safety stage and writes the CommandFrame to send now into `out`.
  void Tick(double t_s, double dt_s, std::span<std::byte, kCommandFrameSize> out);

  /// From now on every command has zero force, force-enable clear and the shutdown flag set.
  void RequestShutdown() { shutdown_ = true; }
  /// Holds every force at zero while `hold` is true (reversible; forces ramp in after release).
  void SetZeroForceHold(bool hold) { zero_force_hold_ = hold; }
  bool zero_force_hold() const { return zero_force_hold_; }
  /// Predict finger poses this far ahead from now on (both fingers; see FingerStateEstimator).
  void SetPredictionHorizon(double horizon_s) {
    for (Finger& f : fingers_) f.estimator.SetPredictionHorizon(horizon_s);
  }
  /// Predict the poses sent to the contact models this much further ahead (both fingers).
  void SetLinkHorizon(double horizon_s) {
    for (Finger& f : fingers_) f.estimator.SetLinkHorizon(horizon_s);
  }

  const FingerState& finger_state(Manipulator finger) const { return fingers_[Index(finger)].state; }
  /// The newest ForceModel installed for `finger` (zero force before any).
  const ForceModel& force_model(Manipulator finger) const { return fingers_[Index(finger)].model; }
  const ForceSafety& safety(Manipulator finger) const { return fingers_[Index(finger)].safety; }
  const PassivityController& passivity(Manipulator finger) const { return fingers_[Index(finger)].passivity; }
  const ResumeProxy& resume(Manipulator finger) const { return fingers_[Index(finger)].resume; }
  /// The state the contact models get: the finger's, with its positions on its proxy while a
  /// held contact resumes after a cut (ResumeProxy).
  const FingerState& model_finger_state(Manipulator finger) const { return fingers_[Index(finger)].model_state; }
  /// The newest finished resumes, by number modulo kResumeHistory (number 0: empty slot).
  const std::array<ResumeRecord, kResumeHistory>& resumes() const { return resumes_; }
  std::uint64_t resumes_finished() const { return resume_count_; }
  /// Force commanded in the last Tick, world frame.
  const Eigen::Vector3d& last_force_W_N(Manipulator finger) const {
    return fingers_[Index(finger)].safety.last_force_W_N();
  }
  /// Flags of the latest accepted StatusFrame.
  std::uint16_t controller_flags() const { return controller_flags_; }
  bool device_lost() const { return device_lost_; }
  const FrameCounters& frame_counters() const { return frame_counters_; }
  /// Valid StatusFrames newer than the one before: the ones that moved the finger states.
  std::uint64_t status_frames_accepted() const { return frame_counters_.accepted() - counters_.status_out_of_order; }
  const BridgeCounters& counters() const { return counters_; }
  /// Host time from a controller packet's arrival to the send of the first force computed from
  /// it (both on the host clock).
  const LatencyTracker& motion_to_force_latency() const { return motion_to_force_; }
  /// Host time from a command's send to the first StatusFrame echoing it.
  const LatencyTracker& link_round_trip() const { return round_trip_; }
  /// The haptic link's round trip: from a controller frame's arrival to the arrival of the first
  /// ForceModel based on it (both on the host clock; across any network in between).
  const LatencyTracker& haptic_round_trip() const { return haptic_round_trip_; }
  /// The haptic round trip now: a low-pass of its samples (round_trip_filter_s); 0 before any.
  double haptic_round_trip_estimate_s() const { return round_trip_estimate_s_; }
  /// What the user feels: from a controller frame's arrival to the first command computed from a
  /// ForceModel based on it.
  const LatencyTracker& motion_to_force_end_to_end() const { return motion_to_force_end_to_end_; }
  /// True while models are refused for their age (the link is slower than max_model_age_s).
  bool link_too_slow() const { return link_too_slow_; }
  /// True while the controller is (or recently was) echoing commands this bridge never sent.
  bool foreign_commander() const { return foreign_commander_; }
  const DeviceBridgeConfig& config() const { return config_; }

 private:
  static std::size_t Index(Manipulator m) { return static_cast<std::size_t>(m); }

  struct Finger {
    explicit Finger(const DeviceBridgeConfig& c)
        : estimator(c.estimator),
          safety(c.safety),
          passivity(c.passivity),
          resume(c.resume, c.safety.resume_within_s) {}
    FingerStateEstimator estimator;
    ForceSafety safety;
    PassivityController passivity;
    ResumeProxy resume;
    FingerState state;
    FingerState model_state;
    CutCause cut_cause = CutCause::kBridgeStall;
    double cut_at_s = 0.0;
    std::uint64_t contacts_ended_seen = 0;
    ForceModel model;
    bool has_model = false;
    double model_rx_s = 0.0;
    double model_basis_s = 0.0;  ///< arrival of the controller frame the model answers (-inf: unknown)
    bool observed = false;       ///< observed_p_W_m holds a measured pose
    Eigen::Vector3d observed_p_W_m{Eigen::Vector3d::Zero()};  ///< where the passivity observer saw the finger
    Eigen::Vector3d last_command_W_N{Eigen::Vector3d::Zero()};
  };
  struct FrameArrival {
    std::uint64_t sequence = 0;
    double arrival_s = 0.0;
  };
  /// Refuses models for their age from the tick a model's basis is older than max_model_age_s,
  /// until every model has been young enough for recover_after_s.
  void UpdateLinkAge(double t_s);
  // Whether this tick disarms for a stall of ours (DeviceBridgeConfig::disarm_after_tick_gap_s).
  bool TickGapDisarms(double t_s, double dt_s, bool lost, bool controller_timed_out);
  /// When the frame `sequence` arrived, or -inf when the bridge does not remember it.
  double FrameArrivalS(std::uint64_t sequence) const;

  static constexpr std::size_t kSendHistory = 64;
  struct SentCommand {
    std::uint32_t sequence = 0;
    double sent_s = 0.0;
  };

  DeviceBridgeConfig config_;
  Eigen::Matrix3d R_DW_;
  std::array<Finger, kManipulatorCount> fingers_;
  FrameCounters frame_counters_;
  BridgeCounters counters_;
  LatencyTracker motion_to_force_;
  LatencyTracker round_trip_;
  LatencyTracker haptic_round_trip_{1e-4};  // 0.1 ms bins: up to 1 s
  LatencyTracker motion_to_force_end_to_end_{1e-4};
  std::array<FrameArrival, kFrameHistory> frame_arrivals_{};
  double round_trip_estimate_s_ = 0.0;
  double last_round_trip_sample_s_ = 0.0;
  std::uint64_t round_trip_basis_ = 0;                                    // newest basis sampled for the round trip
  double end_to_end_basis_s_ = -std::numeric_limits<double>::infinity();  // arrival of the newest basis commanded
  bool link_too_slow_ = false;
  bool foreign_commander_ = false;
  double last_foreign_echo_s_ = -std::numeric_limits<double>::infinity();
  double young_since_s_ = -1.0;  // since when every model has been young enough to recover (-1: not)
  std::array<SentCommand, kSendHistory> sent_{};
  std::array<ResumeRecord, kResumeHistory> resumes_{};
  std::uint64_t resume_count_ = 0;
  bool host_timed_out_before_ = false;
  /// Where a finger's force model is evaluated: its predicted pose, or, while a resume is under
  /// way or without prediction, its measured one (before the proxy's constraint).
  static const Eigen::Vector3d& ModelPose(const Finger& finger, bool predicted);
  void FinishResume(Finger& finger, std::size_t index, bool ended);

  bool has_status_ = false;
  bool stale_cut_ = false;  // a finger's force is at the watchdog's zero for stale models
  bool device_lost_ = true;
  bool shutdown_ = false;
  bool zero_force_hold_ = false;
  std::uint16_t controller_flags_ = 0;
  std::uint32_t last_status_sequence_ = 0;
  std::uint64_t last_status_time_ns_ = 0;
  std::uint32_t last_status_echo_ = 0;  // echo_host_sequence of the newest status
  // a tick gap waiting for the controller's answer: since when, the first command sent after it,
  // and whether a status since then reported HOST_TIMEOUT
  bool gap_pending_ = false;
  double gap_pending_since_s_ = 0.0;
  std::uint32_t gap_first_command_ = 0;
  bool gap_timeout_seen_ = false;
  double last_status_rx_s_ = 0.0;
  std::uint32_t last_reflected_sequence_ = 0;
  bool reflected_any_ = false;
  std::uint32_t command_sequence_ = 0;
};

}  // namespace haptex::device
