#include "libs/device/device_bridge.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace haptex::device {

void DeviceBridgeConfig::Validate() const {
  estimator.Validate();
  safety.Validate();
  if (!(device_lost_after_s > 0.0) || !std::isfinite(device_lost_after_s)) {
    throw std::invalid_argument("DeviceBridgeConfig: device_lost_after_s must be > 0 s, got " +
                                std::to_string(device_lost_after_s));
  }
  if (!(disarm_after_tick_gap_s > 0.0) || !std::isfinite(disarm_after_tick_gap_s)) {
    throw std::invalid_argument("DeviceBridgeConfig: disarm_after_tick_gap_s must be > 0 s, got " +
                                std::to_string(disarm_after_tick_gap_s));
  }
  const Eigen::Matrix3d R = X_WD.linear();
  if (!X_WD.matrix().allFinite() || !(R.transpose() * R).isIdentity(1e-9) || std::abs(R.determinant() - 1.0) > 1e-9) {
    throw std::invalid_argument(
        "DeviceBridgeConfig: X_WD must be a rigid transform (orthonormal "
        "rotation with determinant 1, finite translation)");
  }
  if (!(value_limits.workspace_half_extent_m.array() > 0.0f).all() || !(value_limits.workspace_margin_m >= 0.0f) ||
      !(value_limits.quaternion_norm_tolerance > 0.0f) || !(value_limits.max_measured_force_N > 0.0f) ||
      !(value_limits.max_command_force_N > 0.0f)) {
    throw std::invalid_argument(
        "DeviceBridgeConfig: value_limits must be positive (workspace, "
        "margin >= 0, quaternion tolerance, force limits)");
  }
}

namespace {
const DeviceBridgeConfig& Validated(const DeviceBridgeConfig& config) {
  config.Validate();
  return config;
}
}  // namespace

DeviceBridge::DeviceBridge(const DeviceBridgeConfig& config)
    : config_(Validated(config)),
      R_DW_(config_.X_WD.linear().transpose()),
      fingers_{Finger(config_), Finger(config_)} {}

FrameError DeviceBridge::OnStatusDatagram(std::span<const std::byte> datagram, double t_rx_s) {
  StatusFrame frame;
  const FrameError error = DecodeStatusFrame(datagram, config_.value_limits, &frame);
  frame_counters_.Add(error);
  if (error != FrameError::kNone) return error;

  // after a silence (or a controller restart) any sequence is accepted: resynchronise
  const bool resync = !has_status_ || t_rx_s - last_status_rx_s_ > config_.device_lost_after_s;
  if (!resync && !SequenceNewer(frame.sequence, last_status_sequence_)) {
    ++counters_.status_out_of_order;
    return error;
  }

  // link round trip: first status echoing a command we sent
  if (frame.echo_host_sequence != 0) {
    SentCommand& sent = sent_[frame.echo_host_sequence % kSendHistory];
    if (sent.sequence == frame.echo_host_sequence) {
      round_trip_.Record(t_rx_s - sent.sent_s);
      sent.sequence = 0;
    }
  }

  const Eigen::Matrix3d R_WD = config_.X_WD.linear();
  const Eigen::Quaterniond q_WD(R_WD);
  for (std::size_t i = 0; i < kManipulatorCount; ++i) {
    const ManipulatorStatus& m = frame.manipulators[i];
    Finger& finger = fingers_[i];
    if (resync) finger.estimator.Reset();
    FingerState& state = finger.state;
    state.controller_sequence = frame.sequence;
    state.controller_time_ns = frame.controller_time_ns;
    state.received_s = t_rx_s;
    state.device_flags = m.flags;
    state.force_measured_W_N = R_WD * m.force_D_N.cast<double>();
    if (m.flags & manipulator_flags::kCalibrated) {
      finger.estimator.Update(config_.X_WD * m.p_D_m.cast<double>(), q_WD * m.q_DF.cast<double>(),
                              frame.controller_time_ns, &state);
    } else {
      // an uncalibrated pose is meaningless: no force for this finger
      state.valid = false;
      finger.estimator.Reset();
    }
  }
  has_status_ = true;
  controller_flags_ = frame.controller_flags;
  last_status_sequence_ = frame.sequence;
  last_status_time_ns_ = frame.controller_time_ns;
  last_status_rx_s_ = t_rx_s;
  return error;
}

void DeviceBridge::SetForceModel(Manipulator finger, const ForceModel& model, double t_rx_s) {
  Finger& f = fingers_[Index(finger)];
  f.model = model;
  f.has_model = true;
  f.model_rx_s = t_rx_s;
  ++counters_.force_models;
}

void DeviceBridge::Tick(double t_s, double dt_s, std::span<std::byte, kCommandFrameSize> out) {
  ++counters_.ticks;

  // controller watchdog
  const bool lost = !has_status_ || t_s - last_status_rx_s_ > config_.device_lost_after_s;
  if (lost && !device_lost_) ++counters_.device_lost_events;
  device_lost_ = lost;
  const bool estop = (controller_flags_ & controller_flags::kEmergencyStop) != 0;
  // the controller zeroed force because our commands stopped reaching it: disarm, so the force
  // ramps in again instead of jumping back when commands get through
  const bool controller_timed_out = (controller_flags_ & controller_flags::kHostTimeout) != 0;
  // our own stall: the controller may have timed out before its flag could reach us
  const bool tick_gap = dt_s >= config_.disarm_after_tick_gap_s;
  if (tick_gap) ++counters_.tick_gap_disarms;

  CommandFrame command;
  command.host_flags = shutdown_ ? host_flags::kShutdown : 0;
  for (std::size_t i = 0; i < kManipulatorCount; ++i) {
    Finger& finger = fingers_[i];
    SafetyInput input;
    const bool blocked = lost || shutdown_ || zero_force_hold_ || estop || !finger.state.valid;
    const bool link_hiccup = controller_timed_out || tick_gap;
    input.output_allowed = !blocked && !link_hiccup;
    // off only for the link's sake: force resumes over the short ramp once commands get through
    input.link_interruption = !blocked && link_hiccup;
    if (finger.has_model) {
      const Eigen::Vector3d& p_W = config_.evaluate_at_predicted_pose ? finger.state.p_pred_W_m : finger.state.p_W_m;
      input.requested_W_N = EvaluateForceModel(finger.model, p_W);
      input.model_age_s = std::max(0.0, t_s - finger.model_rx_s);
      input.model_ttl_s = finger.model.ttl_s;
    } else {
      input.model_age_s = std::numeric_limits<double>::infinity();
    }
    const SafetyOutput result = finger.safety.Step(input, dt_s);

    ManipulatorCommand& m = command.manipulators[i];
    m.force_D_N = (R_DW_ * result.force_W_N).cast<float>();
    m.flags = static_cast<std::uint16_t>((input.output_allowed ? command_flags::kForceEnable : 0) |
                                         (result.ramping ? command_flags::kRamping : 0) |
                                         (result.limited ? command_flags::kLimited : 0));
  }

  // motion-to-force latency: the first force computed from each new controller frame
  if (!lost && (!reflected_any_ || last_status_sequence_ != last_reflected_sequence_)) {
    motion_to_force_.Record(t_s - last_status_rx_s_);
    last_reflected_sequence_ = last_status_sequence_;
    reflected_any_ = true;
  }

  ++command_sequence_;
  if (command_sequence_ == 0) command_sequence_ = 1;  // 0 means "none" in the echo field
  command.sequence = command_sequence_;
  command.echo_controller_sequence = last_status_sequence_;
  command.echo_controller_time_ns = last_status_time_ns_;
  sent_[command_sequence_ % kSendHistory] = SentCommand{command_sequence_, t_s};
  EncodeCommandFrame(command, out);
}

}  // namespace haptex::device
