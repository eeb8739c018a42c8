#pragma once
// The mock GRAB controller's work per controller period (5 kHz), apart from sockets. Read: the
// host's CommandFrames (the newest valid one wins inside the controller). Update: one step of the
// two simulated fingertips (the scripted user pulling, the commanded force pushing) into the
// StatusFrame the caller sends (status()). Write: what the fingers felt to the force log, and the
// counters. Allocates nothing once warmed up.

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>

#include "libs/device/mock_grab_controller.h"
#include "libs/runtime/health_reporter.h"
#include "services/common/outbox.h"
#include "services/mock_grab/force_log.h"

namespace haptex::mock_grab {

class MockGrabLoop final {
 public:
  /// `log` (optional, outliving the loop) gets a row per step, stamped `log_origin_ns` + t on the
  /// steady clock. Registers its counters with `health` (which must outlive the loop).
  MockGrabLoop(const device::MockControllerConfig& config, device::ScriptParams script, ForceLog* log,
               std::int64_t log_origin_ns, runtime::HealthReporter* health);

  /// One datagram from the GRAB socket, read at `t_s`. Only the configured host (`from_host`: it
  /// came from the address status goes to) commands the fingers, as a real controller configured
  /// with its host; anything else is dropped unread and counted (commands_from_strangers).
  void ReadHost(std::span<const std::byte> datagram, double t_s, bool from_host);
  void Read(const v1::Envelope& /*envelope*/, double /*t_s*/) {}  // Control only (the context's)

  void Update(double t_s, double dt_s);
  /// The StatusFrame Update made, for the host.
  std::span<const std::byte> status() const { return status_; }
  void Write(services::Outbox& out);

  const device::MockGrabController& controller() const { return *controller_; }
  std::uint64_t commands_from_strangers() const { return strangers_; }

 private:
  std::unique_ptr<device::MockGrabController> controller_;
  ForceLog* log_;
  std::int64_t log_origin_ns_;
  runtime::HealthReporter* health_;
  double t_s_ = 0.0;
  std::uint64_t strangers_ = 0;
  std::array<std::byte, device::kStatusFrameSize> status_{};
  struct CounterIds {
    runtime::HealthReporter::CounterId steps, accepted, rejected, timeouts, world_pauses, log_dropped, strangers,
        out_of_order;
    /// commands_rejected_<reason>, by FrameError (index 0, accepted, unused)
    std::array<runtime::HealthReporter::CounterId, device::kFrameErrorCount> rejected_by_reason;
  } ids_{};
};

}  // namespace haptex::mock_grab
