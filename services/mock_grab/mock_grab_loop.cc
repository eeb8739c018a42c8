#include "services/mock_grab/mock_grab_loop.h"

#include <cmath>
#include <string>

namespace haptex::mock_grab {

MockGrabLoop::MockGrabLoop(const device::MockControllerConfig& config, device::ScriptParams script, ForceLog* log,
                           std::int64_t log_origin_ns, runtime::HealthReporter* health)
    : controller_(std::make_unique<device::MockGrabController>(config, std::move(script))),
      log_(log),
      log_origin_ns_(log_origin_ns),
      health_(health) {
  ids_.steps = health_->AddCounter("steps");
  ids_.accepted = health_->AddCounter("commands_accepted");
  ids_.rejected = health_->AddCounter("commands_rejected");
  ids_.timeouts = health_->AddCounter("host_timeouts");
  ids_.world_pauses = health_->AddCounter("world_pauses");
  ids_.log_dropped = health_->AddCounter("force_log_dropped");
  ids_.strangers = health_->AddCounter("commands_from_strangers");
  ids_.out_of_order = health_->AddCounter("commands_out_of_order");
  ids_.rejected_by_reason = health_->AddCounterPerReason<device::FrameError, device::kFrameErrorCount>(
      "commands_rejected_", device::FrameErrorName);
}

void MockGrabLoop::ReadHost(std::span<const std::byte> datagram, double t_s, bool from_host) {
  if (!from_host) {
    ++strangers_;
    return;
  }
  controller_->OnCommandDatagram(datagram, t_s);
}

void MockGrabLoop::Update(double t_s, double dt_s) {
  t_s_ = t_s;
  controller_->Step(t_s, dt_s, status_);
}

void MockGrabLoop::Write(services::Outbox& /*out*/) {
  if (log_ != nullptr) {
    device::ForceLogRow row;
    row.time_ns = log_origin_ns_ + std::llround(t_s_ * 1e9);
    for (std::size_t f = 0; f < device::kManipulatorCount; ++f) {
      const device::MockFingerState& finger = controller_->finger(static_cast<device::Manipulator>(f));
      for (int k = 0; k < 3; ++k) {
        // the log keeps what a float carries, as the real controller's sensors do
        row.commanded_D_N[f][static_cast<std::size_t>(k)] = static_cast<float>(finger.commanded_force_D_N(k));
        row.applied_D_N[f][static_cast<std::size_t>(k)] = static_cast<float>(finger.applied_force_D_N(k));
        row.position_D_m[f][static_cast<std::size_t>(k)] = finger.p_D_m(k);
      }
    }
    row.host_timed_out = controller_->host_timed_out();
    row.host_sequence = controller_->host_sequence();
    log_->Push(row);
  }
  health_->SetCounter(ids_.steps, controller_->counters().steps);
  health_->SetCounter(ids_.accepted, controller_->commands_accepted());
  health_->SetCounter(ids_.rejected, controller_->frame_counters().TotalRejected());
  for (std::size_t e = 1; e < device::kFrameErrorCount; ++e) {
    health_->SetCounter(ids_.rejected_by_reason[e],
                        controller_->frame_counters().Get(static_cast<device::FrameError>(e)));
  }
  health_->SetCounter(ids_.out_of_order, controller_->counters().commands_out_of_order);
  health_->SetCounter(ids_.timeouts, controller_->counters().host_timeouts);
  health_->SetCounter(ids_.world_pauses, controller_->counters().world_pauses);
  health_->SetCounter(ids_.strangers, strangers_);
  if (log_ != nullptr) health_->SetCounter(ids_.log_dropped, log_->dropped());
}

}  // namespace haptex::mock_grab
