#include "services/device_bridge/bridge_loop.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string_view>

#include "services/device_bridge/device_bridge_codec.h"

namespace haptex::device_bridge {
namespace {

runtime::LatencySummary LatencyOf(const device::LatencyTracker& t) {
  return {t.count(), t.p50_s() * 1e6, t.p99_s() * 1e6, t.max_s() * 1e6};
}

}  // namespace

BridgeLoop::BridgeLoop(const BridgeLoopConfig& config, const BridgePeers& peers, runtime::HealthReporter* health)
    : config_(config),
      peers_(peers),
      health_(health),
      bridge_(std::make_unique<device::DeviceBridge>(config.bridge)),
      local_every_(std::max<std::int64_t>(1, std::llround(config.rate_hz / config.finger_states_to_local_hz))),
      global_every_(std::max<std::int64_t>(1, std::llround(config.rate_hz / config.finger_states_to_global_hz))),
      viewer_every_(std::max<std::int64_t>(1, std::llround(config.rate_hz / config.finger_states_to_viewer_hz))),
      horizon_update_every_(static_cast<std::uint64_t>(std::max(1.0, config.rate_hz / 2))) {
  const device::DeviceBridge* bridge = bridge_.get();
  health_->AddLatency("motion_to_force", [bridge] { return LatencyOf(bridge->motion_to_force_latency()); });
  health_->AddLatency("controller_round_trip", [bridge] { return LatencyOf(bridge->link_round_trip()); });
  health_->AddLatency("haptic_round_trip", [bridge] { return LatencyOf(bridge->haptic_round_trip()); });
  health_->AddLatency("motion_to_force_end_to_end",
                      [bridge] { return LatencyOf(bridge->motion_to_force_end_to_end()); });
  ids_.status_ok = health_->AddCounter("status_frames_accepted");
  ids_.status_bad = health_->AddCounter("status_frames_rejected");
  ids_.foreign = health_->AddCounter("status_frames_from_strangers");
  ids_.models = health_->AddCounter("force_models");
  ids_.models_bad = health_->AddCounter("force_models_rejected");
  ids_.lost = health_->AddCounter("device_lost_events");
  ids_.gap = health_->AddCounter("tick_gap_disarms");
  ids_.gap_held = health_->AddCounter("tick_gaps_held");
  ids_.stale_cuts = health_->AddCounter("stale_model_cuts");
  ids_.nan = health_->AddCounter("non_finite_forces");
  ids_.too_old = health_->AddCounter("slow_link_ticks");
  ids_.slow_events = health_->AddCounter("slow_link_events");
  ids_.damped = health_->AddCounter("passivity_damped_ticks");
  ids_.foreign_echoes = health_->AddCounter("foreign_echoes");
  ids_.foreign_echo_events = health_->AddCounter("foreign_echo_events");
  ids_.out_of_order = health_->AddCounter("status_frames_out_of_order");
  // ticks (summed over the fingers) in which the safety stage held a force below what the models
  // asked: a scene that asks the device for more than it gives shows here
  ids_.peak_limited = health_->AddCounter("peak_limited_ticks");
  ids_.continuous_limited = health_->AddCounter("continuous_limited_ticks");
  ids_.slew_limited = health_->AddCounter("slew_limited_ticks");
  // docs/grab-protocol.md section 6: every rejection counted under its reason
  ids_.rejected_by_reason = health_->AddCounterPerReason<device::FrameError, device::kFrameErrorCount>(
      "status_frames_rejected_", device::FrameErrorName);
  ids_.host_timeout_cuts = health_->AddCounter("host_timeout_cuts");
  // cuts of a held contact by cause, and how their resumes went (docs/grab-protocol.md)
  ids_.held_cuts = health_->AddCounterPerReason<device::CutCause, device::kCutCauseCount + 1>(
      "held_cuts_",
      [](device::CutCause c) { return device::CutCauseName(static_cast<device::CutCause>(static_cast<int>(c) - 1)); });
  ids_.resumes_limited = health_->AddCounter("resumes_limited");
  ids_.contacts_ended = health_->AddCounter("contacts_ended");
  for (std::size_t i = 0; i < device::kResumeHistory; ++i) health_->mutable_resumes()->Add();
  FillFingerStates(*bridge_, &states_);  // sized once, before the loop
  health_->ReserveLastError(kLastErrorCapacity);
}

void BridgeLoop::ReadController(std::span<const std::byte> datagram, double arrival_s, double t_s,
                                bool from_controller) {
  if (!from_controller) {
    ++foreign_frames_;
    return;
  }
  // the kernel's stamp, so that motion-to-force latency includes the wait in our socket
  bridge_->OnStatusDatagram(datagram, std::min(arrival_s, t_s));
}

void BridgeLoop::Read(const v1::Envelope& envelope, double t_s) {
  if (envelope.body_case() != v1::Envelope::kForceModel) return;
  const auto& fingers = envelope.force_model().fingers();
  for (const v1::FingerForceModel& m : fingers) {
    device::Manipulator manipulator;
    if (!ToManipulator(m.finger(), &manipulator) || !IsWellFormed(m)) {
      ++bad_models_;
      continue;
    }
    const v1::FingerForceModel* other = nullptr;
    for (const v1::FingerForceModel& o : fingers) {
      device::Manipulator o_manipulator;
      if (&o != &m && ToManipulator(o.finger(), &o_manipulator) && o_manipulator != manipulator) other = &o;
    }
    bridge_->SetForceModel(manipulator, ToForceModel(m, other), t_s,
                           envelope.force_model().based_on_controller_sequence());
  }
}

void BridgeLoop::OnControl(v1::Control::Command command) {
  // SHUTDOWN is the service's: it stops through RequestShutdown (zero force first)
  if (command == v1::Control::COMMAND_ZERO_FORCE) bridge_->SetZeroForceHold(true);
  if (command == v1::Control::COMMAND_ENABLE_FORCE) bridge_->SetZeroForceHold(false);
}

void BridgeLoop::Update(double t_s, double dt_s) {
  // Predict one link latency ahead: from a pose's measurement to its force acting on the finger =
  // the wait in our socket (motion-to-force) + the way up and the way back down (about one
  // controller round trip).
  if (config_.measured_prediction_horizon && tick_ % horizon_update_every_ == 0 &&
      bridge_->link_round_trip().count() > 100 && bridge_->motion_to_force_latency().count() > 100) {
    bridge_->SetPredictionHorizon(bridge_->motion_to_force_latency().p50_s() + bridge_->link_round_trip().p50_s());
  }
  // The contact models get the pose the finger will have when their answer comes back: one haptic
  // round trip (the network's, whatever it is) beyond the controller link's horizon.
  if (config_.measured_prediction_horizon && tick_ % horizon_update_every_ == 0) {
    bridge_->SetLinkHorizon(bridge_->haptic_round_trip_estimate_s());
  }
  bridge_->Tick(t_s, dt_s, command_);
}

void BridgeLoop::Write(services::Outbox& out) {
  const auto k = static_cast<std::int64_t>(tick_);
  const bool to_local = peers_.local_contact && k % local_every_ == 0;
  const bool to_global = peers_.global_sim && k % global_every_ == 0;
  const bool to_viewer = peers_.viewer && k % viewer_every_ == 0;
  if (to_local || to_global || to_viewer) {
    FillFingerStates(*bridge_, &states_);
    if (to_local) out.Send(*peers_.local_contact, states_);
    if (to_global) out.Send(*peers_.global_sim, states_);
    if (to_viewer) out.Send(*peers_.viewer, states_);
  }
  ++tick_;
  std::uint64_t non_finite = 0, peak_limited = 0, continuous_limited = 0, slew_limited = 0;
  for (std::size_t i = 0; i < device::kManipulatorCount; ++i) {
    const device::SafetyCounters& c = bridge_->safety(static_cast<device::Manipulator>(i)).counters();
    non_finite += c.non_finite;
    peak_limited += c.peak_limited;
    continuous_limited += c.continuous_limited;
    slew_limited += c.slew_limited;
  }
  health_->SetCounter(ids_.peak_limited, peak_limited);
  health_->SetCounter(ids_.continuous_limited, continuous_limited);
  health_->SetCounter(ids_.slew_limited, slew_limited);
  health_->SetCounter(ids_.status_ok, bridge_->status_frames_accepted());
  health_->SetCounter(ids_.status_bad, bridge_->frame_counters().TotalRejected());
  for (std::size_t e = 1; e < device::kFrameErrorCount; ++e) {
    health_->SetCounter(ids_.rejected_by_reason[e], bridge_->frame_counters().Get(static_cast<device::FrameError>(e)));
  }
  health_->SetCounter(ids_.out_of_order, bridge_->counters().status_out_of_order);
  health_->SetCounter(ids_.foreign, foreign_frames_);
  health_->SetCounter(ids_.models, bridge_->counters().force_models);
  health_->SetCounter(ids_.models_bad, bad_models_);
  health_->SetCounter(ids_.lost, bridge_->counters().device_lost_events);
  health_->SetCounter(ids_.gap, bridge_->counters().tick_gap_disarms);
  health_->SetCounter(ids_.gap_held, bridge_->counters().tick_gaps_held);
  health_->SetCounter(ids_.stale_cuts, bridge_->counters().stale_model_cuts);
  health_->SetCounter(ids_.nan, non_finite);
  health_->SetCounter(ids_.too_old, bridge_->counters().slow_link_ticks);
  health_->SetCounter(ids_.slow_events, bridge_->counters().slow_link_events);
  std::uint64_t damped = 0;
  for (std::size_t i = 0; i < device::kManipulatorCount; ++i) {
    damped += bridge_->passivity(static_cast<device::Manipulator>(i)).counters().damped_steps;
  }
  health_->SetCounter(ids_.damped, damped);
  health_->SetCounter(ids_.foreign_echoes, bridge_->counters().foreign_echoes);
  health_->SetCounter(ids_.foreign_echo_events, bridge_->counters().foreign_echo_events);
  const device::BridgeCounters& c = bridge_->counters();
  health_->SetCounter(ids_.host_timeout_cuts, c.host_timeout_cuts);
  for (std::size_t cause = 0; cause < device::kCutCauseCount; ++cause) {
    health_->SetCounter(ids_.held_cuts[cause + 1], c.held_cuts_by_cause[cause]);
  }
  health_->SetCounter(ids_.resumes_limited, c.resumes_limited);
  health_->SetCounter(ids_.contacts_ended, c.contacts_ended);
  if (bridge_->resumes_finished() != resumes_reported_) {
    resumes_reported_ = bridge_->resumes_finished();
    auto* resumes = health_->mutable_resumes();
    for (std::size_t slot = 0; slot < device::kResumeHistory; ++slot) {
      const device::ResumeRecord& r = bridge_->resumes()[slot];
      v1::ForceResume* m = resumes->Mutable(static_cast<int>(slot));
      m->set_number(r.number);
      m->set_cause(static_cast<v1::ForceResume::Cause>(static_cast<int>(r.cause) + 1));
      m->set_finger_slot(static_cast<std::uint32_t>(r.finger));
      m->set_cut_at_s(r.cut_at_s);
      m->set_held_n(r.held_N);
      m->set_asked_n(r.asked_N);
      m->set_peak_n(r.peak_N);
      m->set_limited(r.limited);
      m->set_ended(r.ended);
    }
  }
  health_->SetState(bridge_->device_lost() || bridge_->foreign_commander() || bridge_->link_too_slow()
                        ? v1::Health::STATE_DEGRADED
                        : v1::Health::STATE_READY);
  ReportDegradation();
}

void BridgeLoop::ReportDegradation() {
  const Degradation now = bridge_->device_lost()         ? Degradation::kDeviceLost
                          : bridge_->foreign_commander() ? Degradation::kForeignCommander
                          : bridge_->link_too_slow()     ? Degradation::kLinkTooSlow
                                                         : Degradation::kNone;
  if (now == degradation_) return;
  degradation_ = now;
  // the text stays after recovery: it is the last error, and the state says it is over
  std::array<char, kLastErrorCapacity> text{};
  int length = 0;
  const auto& c = bridge_->config();
  if (now == Degradation::kDeviceLost) {
    length = std::snprintf(text.data(), text.size(), "device lost: no controller frame for %.0f ms, force off",
                           c.device_lost_after_s * 1e3);
  } else if (now == Degradation::kForeignCommander) {
    length = std::snprintf(text.data(), text.size(),
                           "controller accepted commands this bridge never sent (another host commands it): force "
                           "off until its echoes are ours for %.1f s",
                           c.foreign_echo_hold_s);
  } else if (now == Degradation::kLinkTooSlow) {
    length = std::snprintf(text.data(), text.size(),
                           "haptic link too slow: round trip %.0f ms, force models older than %.0f ms refused, "
                           "force off until it stays below %.0f ms for %.1f s",
                           bridge_->haptic_round_trip_estimate_s() * 1e3, c.max_model_age_s * 1e3,
                           c.recover_fraction * c.max_model_age_s * 1e3, c.recover_after_s);
  }
  if (length > 0) {
    health_->SetLastError(std::string_view(text.data(), std::min<std::size_t>(length, text.size() - 1)));
  }
}

std::string BridgeLoop::Summary() const {
  const auto& m2f = bridge_->motion_to_force_latency();
  const auto& rtt = bridge_->link_round_trip();
  char text[400];
  std::snprintf(text, sizeof text,
                "status frames %llu accepted, %llu rejected, %llu from strangers; %llu force models (%llu rejected); "
                "motion-to-force p50 %.1f us p99 %.1f us max %.1f us; controller round trip p50 %.1f us p99 %.1f us "
                "max %.1f us",
                static_cast<unsigned long long>(bridge_->status_frames_accepted()),
                static_cast<unsigned long long>(bridge_->frame_counters().TotalRejected()),
                static_cast<unsigned long long>(foreign_frames_),
                static_cast<unsigned long long>(bridge_->counters().force_models),
                static_cast<unsigned long long>(bad_models_), m2f.p50_s() * 1e6, m2f.p99_s() * 1e6, m2f.max_s() * 1e6,
                rtt.p50_s() * 1e6, rtt.p99_s() * 1e6, rtt.max_s() * 1e6);
  return text;
}

}  // namespace haptex::device_bridge
