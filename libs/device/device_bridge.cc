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
  passivity.Validate();
  if (!(device_lost_after_s > 0.0) || !std::isfinite(device_lost_after_s)) {
    throw std::invalid_argument("DeviceBridgeConfig: device_lost_after_s must be > 0 s, got " +
                                std::to_string(device_lost_after_s));
  }
  if (!(max_model_age_s > 0.0) || !(max_model_age_s < static_cast<double>(kFrameHistory) / kControllerRate_Hz)) {
    throw std::invalid_argument("DeviceBridgeConfig: max_model_age_s must be in (0, " +
                                std::to_string(static_cast<double>(kFrameHistory) / kControllerRate_Hz) + ") s, got " +
                                std::to_string(max_model_age_s));
  }
  if (!(foreign_echo_hold_s >= 0.0) || !std::isfinite(foreign_echo_hold_s)) {
    throw std::invalid_argument("DeviceBridgeConfig: foreign_echo_hold_s must be a finite number >= 0 s");
  }
  if (!(recover_fraction > 0.0) || !(recover_fraction <= 1.0) || !(recover_after_s >= 0.0) ||
      !std::isfinite(recover_after_s)) {
    throw std::invalid_argument("DeviceBridgeConfig: recover_fraction must be in (0, 1] and recover_after_s >= 0");
  }
  if (!(round_trip_filter_s > 0.0) || !std::isfinite(round_trip_filter_s)) {
    throw std::invalid_argument("DeviceBridgeConfig: round_trip_filter_s must be > 0 s, got " +
                                std::to_string(round_trip_filter_s));
  }
  if (!(disarm_after_tick_gap_s > 0.0) || !std::isfinite(disarm_after_tick_gap_s)) {
    throw std::invalid_argument("DeviceBridgeConfig: disarm_after_tick_gap_s must be > 0 s, got " +
                                std::to_string(disarm_after_tick_gap_s));
  }
  if (!(gap_confirm_window_s > 0.0) || !std::isfinite(gap_confirm_window_s)) {
    throw std::invalid_argument("DeviceBridgeConfig: gap_confirm_window_s must be > 0 s, got " +
                                std::to_string(gap_confirm_window_s));
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
  // sequence 0 is never sent (it means "none" in echoes): not a frame to act on
  if (frame.sequence == 0 || (!resync && !SequenceNewer(frame.sequence, last_status_sequence_))) {
    ++counters_.status_out_of_order;
    return error;
  }

  // an echo newer than our newest command: another host's command was accepted
  if (frame.echo_host_sequence != 0 && command_sequence_ != 0 &&
      SequenceNewer(frame.echo_host_sequence, command_sequence_)) {
    ++counters_.foreign_echoes;
    if (!foreign_commander_) ++counters_.foreign_echo_events;
    foreign_commander_ = true;
    last_foreign_echo_s_ = t_rx_s;
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
    if (resync) {  // a restarted controller: its positions do not continue the old ones
      finger.estimator.Reset();
      finger.passivity.Reset();
      finger.observed = false;
    }
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
  frame_arrivals_[frame.sequence % kFrameHistory] = FrameArrival{frame.sequence, t_rx_s};
  has_status_ = true;
  controller_flags_ = frame.controller_flags;
  last_status_sequence_ = frame.sequence;
  last_status_time_ns_ = frame.controller_time_ns;
  last_status_echo_ = frame.echo_host_sequence;
  if (gap_pending_ && (frame.controller_flags & controller_flags::kHostTimeout)) gap_timeout_seen_ = true;
  last_status_rx_s_ = t_rx_s;
  return error;
}

double DeviceBridge::FrameArrivalS(std::uint64_t sequence) const {
  const FrameArrival& a = frame_arrivals_[sequence % kFrameHistory];
  return sequence != 0 && a.sequence == sequence ? a.arrival_s : -std::numeric_limits<double>::infinity();
}

void DeviceBridge::SetForceModel(Manipulator finger, const ForceModel& model, double t_rx_s,
                                 std::uint64_t based_on_controller_sequence) {
  Finger& f = fingers_[Index(finger)];
  if (f.has_model) f.resume.OnModelArrival(t_rx_s - f.model_rx_s);
  f.model = model;
  f.has_model = true;
  f.model_rx_s = t_rx_s;
  f.model_basis_s = FrameArrivalS(based_on_controller_sequence);
  ++counters_.force_models;
  if (!std::isfinite(f.model_basis_s)) {
    ++counters_.models_unknown_basis;
    return;
  }
  // the round trip, once per controller frame answered
  if (based_on_controller_sequence != round_trip_basis_) {
    round_trip_basis_ = based_on_controller_sequence;
    const double sample_s = t_rx_s - f.model_basis_s;
    haptic_round_trip_.Record(sample_s);
    if (haptic_round_trip_.count() == 1) {
      round_trip_estimate_s_ = sample_s;
    } else {
      const double gap_s = std::max(0.0, t_rx_s - last_round_trip_sample_s_);
      round_trip_estimate_s_ +=
          (1.0 - std::exp(-gap_s / config_.round_trip_filter_s)) * (sample_s - round_trip_estimate_s_);
    }
    last_round_trip_sample_s_ = t_rx_s;
  }
}

void DeviceBridge::UpdateLinkAge(double t_s) {
  bool any_too_old = false, all_young = true;
  for (const Finger& finger : fingers_) {
    if (!finger.has_model || !std::isfinite(finger.model_basis_s)) continue;
    // the age it arrived with: how slow the link is (an outage is the model lifetime's business)
    const double age_s = finger.model_rx_s - finger.model_basis_s;
    any_too_old = any_too_old || age_s > config_.max_model_age_s;
    all_young = all_young && age_s <= config_.recover_fraction * config_.max_model_age_s;
  }
  if (!link_too_slow_) {
    if (!any_too_old) return;
    link_too_slow_ = true;
    young_since_s_ = -1.0;
    ++counters_.slow_link_events;
    return;
  }
  if (!all_young) {
    young_since_s_ = -1.0;
    return;
  }
  if (young_since_s_ < 0.0) young_since_s_ = t_s;
  if (t_s - young_since_s_ >= config_.recover_after_s) link_too_slow_ = false;
}

bool DeviceBridge::TickGapDisarms(double t_s, double dt_s, bool lost, bool controller_timed_out) {
  if (dt_s >= config_.disarm_after_tick_gap_s && !lost) {
    if (controller_timed_out) {
      ++counters_.tick_gap_disarms;
      gap_pending_ = false;
      return true;
    }
    if (!gap_pending_) {  // ask: the answer to the next command tells whether it held
      gap_pending_ = true;
      gap_pending_since_s_ = t_s;
      gap_first_command_ = NextSequence(command_sequence_);
      gap_timeout_seen_ = false;
    }
    return false;
  }
  if (!gap_pending_) return false;
  const bool answered = last_status_echo_ == gap_first_command_ || SequenceNewer(last_status_echo_, gap_first_command_);
  const bool too_late = !answered && t_s - gap_pending_since_s_ >= config_.gap_confirm_window_s - 1e-9;
  if (gap_timeout_seen_ || lost || too_late) {
    ++counters_.tick_gap_disarms;
    gap_pending_ = false;
    return true;
  }
  if (answered) {
    ++counters_.tick_gaps_held;
    gap_pending_ = false;
  }
  return false;
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
  const bool tick_gap = TickGapDisarms(t_s, dt_s, lost, controller_timed_out);

  UpdateLinkAge(t_s);
  if (link_too_slow_) ++counters_.slow_link_ticks;
  if (foreign_commander_ && t_s - last_foreign_echo_s_ >= config_.foreign_echo_hold_s) foreign_commander_ = false;

  if (controller_timed_out && !host_timed_out_before_) ++counters_.host_timeout_cuts;
  host_timed_out_before_ = controller_timed_out;
  // a stall of our own loop: the controller may have cut the force before we could know
  const bool own_stall = dt_s >= config_.disarm_after_tick_gap_s;

  CommandFrame command;
  command.host_flags = shutdown_ ? host_flags::kShutdown : 0;
  bool stale_cut = false;
  std::array<SafetyInput, kManipulatorCount> inputs;
  std::array<ResumeProxy::Phase, kManipulatorCount> phase_before{};
  std::array<bool, kManipulatorCount> began{};
  for (std::size_t i = 0; i < kManipulatorCount; ++i) {
    Finger& finger = fingers_[i];
    SafetyInput& input = inputs[i];
    const bool held_off = shutdown_ || zero_force_hold_ || estop || foreign_commander_ || !finger.state.valid;
    const bool blocked = held_off || lost;
    // a controller silent for a while (its process, or the whole host, paused) is a hiccup of the
    // link like the others: the force resumes over the short ramp if it comes back soon enough
    const bool link_hiccup = controller_timed_out || tick_gap || lost;
    input.output_allowed = !blocked && !link_hiccup;
    // off only for the link's sake: force resumes over the short ramp once commands get through
    input.link_interruption = !held_off && link_hiccup;
    const bool refused = link_too_slow_ || !std::isfinite(finger.model_basis_s);
    if (finger.has_model) {
      input.model_ttl_s = finger.model.ttl_s;
      // fresh while models keep arriving, and only while they answer recent enough motion
      input.model_age_s = refused ? std::numeric_limits<double>::infinity() : std::max(0.0, t_s - finger.model_rx_s);
    } else {
      input.model_age_s = std::numeric_limits<double>::infinity();
    }
    const bool stale = finger.safety.WatchdogGain(input) < 1.0;
    phase_before[i] = finger.resume.phase();
    began[i] = finger.resume.BeginTick(own_stall || !input.output_allowed || stale, dt_s);
    if (began[i]) {
      finger.cut_cause = own_stall              ? CutCause::kBridgeStall
                         : controller_timed_out ? CutCause::kHostTimeout
                         : lost                 ? CutCause::kDeviceLost
                         : held_off             ? CutCause::kHeldOff
                         : refused              ? CutCause::kRefusedModels
                                                : CutCause::kStaleModels;
      finger.cut_at_s = t_s;
      ++counters_.held_cuts_by_cause[static_cast<std::size_t>(finger.cut_cause)];
      // energy booked before the cut says nothing of the contact after it
      finger.passivity.Reset();
    }
  }
  for (std::size_t i = 0; i < kManipulatorCount; ++i) {
    Finger& finger = fingers_[i];
    SafetyInput& input = inputs[i];
    const bool constrained = finger.resume.constraining();
    // the contact is rendered at the proxies: a finger that passed the surface during the cut
    // meets the surface it left, not the cloth (or the other finger) beyond it
    input.p_W_m = finger.resume.Constrain(finger.state.p_W_m);
    const Eigen::Vector3d& v_W = finger.state.v_W_m_per_s;
    if (finger.has_model) {
      const Finger& other = fingers_[1 - i];
      const bool predicted = config_.evaluate_at_predicted_pose;
      const Eigen::Vector3d at_proxy_W_N =
          EvaluateForceModel(finger.model, finger.resume.Constrain(ModelPose(finger, predicted)),
                             other.resume.Constrain(ModelPose(other, predicted)));
      input.requested_W_N = finger.resume.Shape(at_proxy_W_N, finger.state.p_W_m, v_W);
      input.requested_W_N = finger.resume.CapLateModel(input.requested_W_N, input.model_age_s, dt_s);
    }
    // energy the rendering would create is damped out (a deficit left at a contact's end is
    // still paid off: re-engaging a late model is where delay pumps energy in); a resume's return
    // to the surface is bounded by the resume's own limit instead, and damped by the proxy's spring
    if (constrained && !finger.resume.constraining()) finger.passivity.Reset();  // back on the surface
    if (!constrained) input.requested_W_N = finger.passivity.Adjust(input.requested_W_N, v_W, dt_s);
    input.requested_W_N = finger.resume.ClampToBound(input.requested_W_N);
    const std::uint64_t watchdog_zeros = finger.safety.counters().watchdog_zero_steps;
    const SafetyOutput result = finger.safety.Step(input, dt_s);
    stale_cut |= finger.has_model && input.output_allowed && !link_too_slow_ &&
                 finger.safety.counters().watchdog_zero_steps > watchdog_zeros;
    finger.resume.EndTick(result.force_W_N, finger.state.p_W_m, input.output_allowed && !result.ramping, dt_s);
    // the force held since the last tick moved the finger by what it was measured to move
    if (finger.state.valid && finger.observed && !constrained) {
      finger.passivity.Observe(finger.last_command_W_N, finger.state.p_W_m - finger.observed_p_W_m);
    }
    finger.observed = finger.state.valid;
    finger.observed_p_W_m = finger.state.p_W_m;
    finger.last_command_W_N = result.force_W_N;
    if ((began[i] || phase_before[i] != ResumeProxy::Phase::kFollowing) &&
        finger.resume.phase() == ResumeProxy::Phase::kFollowing) {
      finger.passivity.Reset();
      FinishResume(finger, i, finger.resume.contacts_ended() != finger.contacts_ended_seen);
      finger.contacts_ended_seen = finger.resume.contacts_ended();
    }
    finger.model_state = finger.state;
    if (finger.resume.phase() != ResumeProxy::Phase::kFollowing) {
      // the proxy rests on the surface; and a finger back on it is still moving with the return,
      // which, extrapolated a link's round trip ahead, would take it out of the pinch it rejoins
      const Eigen::Vector3d on_surface_W_m = finger.resume.Constrain(finger.state.p_W_m);
      finger.model_state.p_W_m = on_surface_W_m;
      finger.model_state.p_pred_W_m = on_surface_W_m;
      finger.model_state.p_link_pred_W_m = on_surface_W_m;
      finger.model_state.v_W_m_per_s.setZero();
    }

    ManipulatorCommand& m = command.manipulators[i];
    m.force_D_N = (R_DW_ * result.force_W_N).cast<float>();
    // RAMPING only beside FORCE_ENABLE: a cut is FORCE_ENABLE clear (zero at once, no ramp), and
    // the ramp that follows starts from zero
    m.flags = static_cast<std::uint16_t>((input.output_allowed ? command_flags::kForceEnable : 0) |
                                         (input.output_allowed && result.ramping ? command_flags::kRamping : 0) |
                                         (result.limited ? command_flags::kLimited : 0));
  }

  if (stale_cut && !stale_cut_) ++counters_.stale_model_cuts;
  stale_cut_ = stale_cut;

  // what the user feels: the first command from a model answering each newer controller frame
  for (const Finger& finger : fingers_) {
    if (!finger.has_model || !(finger.model_basis_s > end_to_end_basis_s_)) continue;
    end_to_end_basis_s_ = finger.model_basis_s;
    motion_to_force_end_to_end_.Record(t_s - finger.model_basis_s);
  }

  // motion-to-force latency: the first force computed from each new controller frame
  if (!lost && (!reflected_any_ || last_status_sequence_ != last_reflected_sequence_)) {
    motion_to_force_.Record(t_s - last_status_rx_s_);
    last_reflected_sequence_ = last_status_sequence_;
    reflected_any_ = true;
  }

  command_sequence_ = NextSequence(command_sequence_);
  command.sequence = command_sequence_;
  command.echo_controller_sequence = last_status_sequence_;
  command.echo_controller_time_ns = last_status_time_ns_;
  sent_[command_sequence_ % kSendHistory] = SentCommand{command_sequence_, t_s};
  EncodeCommandFrame(command, out);
}

const char* CutCauseName(CutCause cause) {
  switch (cause) {
    case CutCause::kBridgeStall:
      return "bridge_stall";
    case CutCause::kHostTimeout:
      return "host_timeout";
    case CutCause::kStaleModels:
      return "stale_models";
    case CutCause::kRefusedModels:
      return "refused_models";
    case CutCause::kDeviceLost:
      return "device_lost";
    case CutCause::kHeldOff:
      return "held_off";
  }
  return "unknown";
}

const Eigen::Vector3d& DeviceBridge::ModelPose(const Finger& finger, bool predicted) {
  // no prediction from the return's motion while a resume is under way (see model_state)
  const bool resuming = finger.resume.phase() != ResumeProxy::Phase::kFollowing;
  return predicted && !resuming ? finger.state.p_pred_W_m : finger.state.p_W_m;
}

void DeviceBridge::FinishResume(Finger& finger, std::size_t index, bool ended) {
  const ResumeProxy& r = finger.resume;
  ResumeRecord& record = resumes_[resume_count_ % kResumeHistory];
  record.number = ++resume_count_;
  record.cause = finger.cut_cause;
  record.finger = static_cast<Manipulator>(index);
  record.cut_at_s = finger.cut_at_s;
  record.held_N = r.held_N();
  record.asked_N = r.asked_since_cut_N();
  record.peak_N = r.peak_since_cut_N();
  record.limited = r.limited_since_cut() && !ended;
  record.ended = ended;
  if (record.limited) ++counters_.resumes_limited;
  if (ended) ++counters_.contacts_ended;
}

}  // namespace haptex::device
