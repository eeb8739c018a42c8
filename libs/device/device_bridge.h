#pragma once
// The device bridge's pure core: one Tick per 5 kHz period turns the newest controller status
// and the newest ForceModels into a CommandFrame. services/device_bridge wraps it with a socket
// and a loop; nothing here reads a clock, blocks or allocates after construction.

#include <Eigen/Geometry>
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "libs/device/finger_state.h"
#include "libs/device/finger_state_estimator.h"
#include "libs/device/force_model.h"
#include "libs/device/force_safety.h"
#include "libs/device/grab_protocol.h"
#include "libs/device/latency_tracker.h"

namespace haptex::device {

/// Everything the bridge core needs. Validate() throws std::invalid_argument with a clear message.
struct DeviceBridgeConfig {
  FingerStateEstimatorConfig estimator;
  ForceSafetyConfig safety;
  GrabValueLimits value_limits;
  /// No accepted StatusFrame for this long: device lost, force zero, start-up ramp on return.
  double device_lost_after_s = 0.050;
  /// A gap this long between two bridge ticks (the host process stalled) disarms, and force ramps
  /// in again: the controller may have zeroed force for lack of commands (its host timeout is
  /// 5 ms; 1 ms is left for link jitter), and the next command must not jump back to the old
  /// force before the controller's timeout flag reaches us.
  double disarm_after_tick_gap_s = 0.004;
  /// Evaluate ForceModels at the predicted pose (compensates the link latency) or the measured one.
  bool evaluate_at_predicted_pose = true;
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
  std::uint64_t tick_gap_disarms = 0;     ///< ticks after a gap >= disarm_after_tick_gap_s
};

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

  /// Installs the newest ForceModel for one finger, received at host time `t_rx_s`.
  void SetForceModel(Manipulator finger, const ForceModel& model, double t_rx_s);

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

  const FingerState& finger_state(Manipulator finger) const { return fingers_[Index(finger)].state; }
  const ForceSafety& safety(Manipulator finger) const { return fingers_[Index(finger)].safety; }
  /// Force commanded in the last Tick, world frame.
  const Eigen::Vector3d& last_force_W_N(Manipulator finger) const {
    return fingers_[Index(finger)].safety.last_force_W_N();
  }
  /// Flags of the latest accepted StatusFrame.
  std::uint16_t controller_flags() const { return controller_flags_; }
  bool device_lost() const { return device_lost_; }
  const FrameCounters& frame_counters() const { return frame_counters_; }
  const BridgeCounters& counters() const { return counters_; }
  /// Host time from a controller packet's arrival to the send of the first force computed from
  /// it (both on the host clock).
  const LatencyTracker& motion_to_force_latency() const { return motion_to_force_; }
  /// Host time from a command's send to the first StatusFrame echoing it.
  const LatencyTracker& link_round_trip() const { return round_trip_; }
  const DeviceBridgeConfig& config() const { return config_; }

 private:
  static std::size_t Index(Manipulator m) { return static_cast<std::size_t>(m); }

  struct Finger {
    explicit Finger(const DeviceBridgeConfig& c) : estimator(c.estimator), safety(c.safety) {}
    FingerStateEstimator estimator;
    ForceSafety safety;
    FingerState state;
    ForceModel model;
    bool has_model = false;
    double model_rx_s = 0.0;
  };

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
  std::array<SentCommand, kSendHistory> sent_{};

  bool has_status_ = false;
  bool device_lost_ = true;
  bool shutdown_ = false;
  bool zero_force_hold_ = false;
  std::uint16_t controller_flags_ = 0;
  std::uint32_t last_status_sequence_ = 0;
  std::uint64_t last_status_time_ns_ = 0;
  double last_status_rx_s_ = 0.0;
  std::uint32_t last_reflected_sequence_ = 0;
  bool reflected_any_ = false;
  std::uint32_t command_sequence_ = 0;
};

}  // namespace haptex::device
