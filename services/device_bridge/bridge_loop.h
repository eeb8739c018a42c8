#pragma once
// The device bridge's work per controller period (5 kHz), apart from sockets. Read: the
// controller's StatusFrames (only from the configured controller), ForceModels (newest per
// finger) and Control (zero-force hold). Update: the prediction horizon from the measured
// latencies, then device::DeviceBridge::Tick (evaluate F = F0 + K (x - x0), clamp, watchdogs)
// into the CommandFrame. Write: the CommandFrame goes to the controller (the caller sends
// command()), FingerStates to local_contact and global_sim at their rates, and to the viewer at
// its frame rate. Allocates nothing once warmed up.

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>

#include "haptex/v1/envelope.pb.h"
#include "haptex/v1/finger_states.pb.h"
#include "libs/device/device_bridge.h"
#include "libs/runtime/health_reporter.h"
#include "services/common/outbox.h"

namespace haptex::device_bridge {

struct BridgeLoopConfig {
  device::DeviceBridgeConfig bridge;
  double rate_hz = device::kControllerRate_Hz;
  double finger_states_to_local_hz = 1000.0;
  double finger_states_to_global_hz = 100.0;
  double finger_states_to_viewer_hz = 30.0;
  /// Predict finger poses one link latency ahead, measured as the bridge runs (else the
  /// estimator's fixed horizon).
  bool measured_prediction_horizon = true;
};

struct BridgePeers {
  std::optional<services::PeerId> local_contact, global_sim, viewer;
};

class BridgeLoop final {
 public:
  /// Registers its counters and latencies with `health` (which must outlive the loop).
  /// @throws std::invalid_argument for an invalid configuration.
  BridgeLoop(const BridgeLoopConfig& config, const BridgePeers& peers, runtime::HealthReporter* health);

  /// One datagram from the GRAB socket, which arrived at `arrival_s` (the kernel's stamp) and was
  /// read in the tick at `t_s`. Only the configured controller (`from_controller`) may move the
  /// fingers; anything else is counted.
  void ReadController(std::span<const std::byte> datagram, double arrival_s, double t_s, bool from_controller);
  void Read(const v1::Envelope& envelope, double t_s);
  void OnControl(v1::Control::Command command);
  /// From now on every command has zero force (the service is stopping).
  void RequestShutdown() { bridge_->RequestShutdown(); }

  void Update(double t_s, double dt_s);
  /// The CommandFrame Update made, for the controller.
  std::span<const std::byte> command() const { return command_; }
  void Write(services::Outbox& out);

  const device::DeviceBridge& bridge() const { return *bridge_; }
  /// Frames, models and latencies so far, for the log line at exit.
  std::string Summary() const;
  std::uint64_t foreign_frames() const { return foreign_frames_; }
  std::uint64_t bad_models() const { return bad_models_; }

 private:
  static constexpr std::size_t kLastErrorCapacity = 200;
  enum class Degradation { kNone, kDeviceLost, kForeignCommander, kLinkTooSlow };
  /// Health's last_error names what changed, once per change, without allocating.
  void ReportDegradation();

  BridgeLoopConfig config_;
  BridgePeers peers_;
  runtime::HealthReporter* health_;
  std::unique_ptr<device::DeviceBridge> bridge_;            // ~80 kB of histograms: on the heap, made once
  std::int64_t local_every_, global_every_, viewer_every_;  // ticks between FingerStates
  std::uint64_t horizon_update_every_;
  std::uint64_t tick_ = 0;
  std::array<std::byte, device::kCommandFrameSize> command_{};
  v1::FingerStates states_;
  std::uint64_t bad_models_ = 0, foreign_frames_ = 0;
  Degradation degradation_ = Degradation::kDeviceLost;  // no controller yet is not an error
  struct CounterIds {
    runtime::HealthReporter::CounterId status_ok, status_bad, foreign, models, models_bad, lost, gap, gap_held,
        stale_cuts, nan, too_old, slow_events, damped, foreign_echoes, foreign_echo_events, out_of_order, peak_limited,
        continuous_limited, slew_limited, host_timeout_cuts, resumes_limited, contacts_ended;
    /// held_cuts_<cause>, by device::CutCause + 1 (index 0 unused)
    std::array<runtime::HealthReporter::CounterId, device::kCutCauseCount + 1> held_cuts;
    /// status_frames_rejected_<reason>, by FrameError (index 0, accepted, unused)
    std::array<runtime::HealthReporter::CounterId, device::kFrameErrorCount> rejected_by_reason;
  } ids_{};
  std::uint64_t resumes_reported_ = 0;
};

}  // namespace haptex::device_bridge
