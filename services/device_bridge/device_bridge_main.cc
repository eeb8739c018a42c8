// haptex-device-bridge: owns the GRAB device. At the controller's rate (5 kHz) it reads the
// controller's StatusFrames, estimates and predicts each fingertip, turns the newest ForceModel
// into a force (F = F0 + K (x - x0)), clamps it (peak, continuous, slew; NaN -> zero), ramps it
// to zero when models go stale or the device is lost, and sends the CommandFrame. Nothing else
// talks to the controller.
//
// GRAB socket: receives StatusFrames, sends CommandFrames to --controller.
// haptex socket: receives ForceModel (local_contact), Control; sends FingerStates to
// local_contact and global_sim, Health to the launcher.
// Stopping: forces go to zero first (zero commands for stop_ramp), then the process exits.

#include <spdlog/spdlog.h>

#include <array>
#include <cstddef>
#include <iostream>
#include <memory>

#include "libs/device/device_bridge.h"
#include "libs/net/udp_address.h"
#include "libs/net/udp_endpoint.h"
#include "libs/base/clock.h"
#include "libs/runtime/periodic_loop.h"
#include "services/common/service_context.h"
#include "services/device_bridge/proto_conversion.h"

namespace haptex::device_bridge {
namespace {

struct Options {
  std::string controller_bind = "127.0.0.1:0";
  std::string controller;
  double rate_hz = 5000;
  double stop_zero_force_s = 0.030;  // zero commands sent before exiting
  double prediction_horizon_ms = -1.0;  // < 0: the measured latency, updated as it runs
};

device::DeviceBridgeConfig MakeConfig(const services::ServiceContext& context, const Options& options) {
  device::DeviceBridgeConfig config;
  if (options.prediction_horizon_ms >= 0) config.estimator.prediction_horizon_s = options.prediction_horizon_ms * 1e-3;
  if (context.scene() != nullptr) {
    const v1::DeviceSpec& d = context.scene()->scene.device();
    if (d.peak_force_n() > 0) config.safety.peak_force_N = d.peak_force_n();
    if (d.continuous_force_n() > 0) config.safety.continuous_force_N = d.continuous_force_n();
    if (d.force_model_stale_s() > 0) config.safety.stale_after_s = d.force_model_stale_s();
    if (d.watchdog_ramp_s() > 0) config.safety.stale_ramp_s = d.watchdog_ramp_s();
    if (d.controller_lost_s() > 0) config.device_lost_after_s = d.controller_lost_s();
  }
  config.Validate();
  return config;
}

double RateOr(double value, double fallback) { return value > 0 ? value : fallback; }

int Run(services::ServiceContext& context, const Options& options) {
  const device::DeviceBridgeConfig config = MakeConfig(context, options);
  auto bridge = std::make_unique<device::DeviceBridge>(config);
  net::UdpEndpoint socket(options.controller_bind);
  const auto controller = net::ResolveUdpAddress(options.controller);
  std::cout << "device_bridge controller socket on " << net::FormatUdpAddress(socket.local_endpoint())
            << std::endl;

  // FingerStates rates: the scene's, else the local and global loop rates
  const v1::Rates rates = context.scene() ? context.scene()->scene.rates() : v1::Rates{};
  const double local_hz = RateOr(rates.finger_states_to_local_hz(), RateOr(rates.local_hz(), 1000));
  const double global_hz = RateOr(rates.finger_states_to_global_hz(), RateOr(rates.global_hz(), 100));
  const auto local = context.FindPeer("local_contact");
  const auto global = context.FindPeer("global_sim");
  const auto local_every = std::max<std::int64_t>(1, std::llround(options.rate_hz / local_hz));
  const auto global_every = std::max<std::int64_t>(1, std::llround(options.rate_hz / global_hz));
  const auto horizon_update_every = static_cast<std::uint64_t>(std::max(1.0, options.rate_hz / 2));

  auto& health = context.health();
  runtime::PeriodicLoop loop("device_bridge", options.rate_hz);
  health.AddLoop(&loop.stats());
  health.AddLatency("motion_to_force", [&bridge] {
    const auto& t = bridge->motion_to_force_latency();
    return runtime::LatencySummary{t.count(), t.p50_s() * 1e6, t.p99_s() * 1e6, t.max_s() * 1e6};
  });
  health.AddLatency("controller_round_trip", [&bridge] {
    const auto& t = bridge->link_round_trip();
    return runtime::LatencySummary{t.count(), t.p50_s() * 1e6, t.p99_s() * 1e6, t.max_s() * 1e6};
  });
  const auto c_status_ok = health.AddCounter("status_frames_accepted");
  const auto c_status_bad = health.AddCounter("status_frames_rejected");
  const auto c_foreign = health.AddCounter("status_frames_from_strangers");
  const auto c_models = health.AddCounter("force_models");
  const auto c_models_bad = health.AddCounter("force_models_rejected");
  const auto c_lost = health.AddCounter("device_lost_events");
  const auto c_gap = health.AddCounter("tick_gap_disarms");
  const auto c_nan = health.AddCounter("non_finite_forces");
  const auto c_dropped = health.AddCounter("datagrams_dropped");
  health.SetState(v1::Health::STATE_READY);

  std::array<std::uint8_t, 2048> rx{};
  std::array<std::byte, device::kCommandFrameSize> command{};
  v1::FingerStates states;
  net::UdpEndpoint::Endpoint from;
  std::uint64_t bad_models = 0;
  std::uint64_t foreign_frames = 0;
  const std::int64_t start_ns = base::SteadyNowNs();
  std::int64_t stop_at_ns = std::numeric_limits<std::int64_t>::max();
  bool stopping = false;
  loop.Run(
      [&](const runtime::TickInfo& tick) {
        const double t_s = static_cast<double>(tick.now_ns - start_ns) * 1e-9;
        // read: controller frames (bounded against floods), then models and control
        // frames carry their kernel arrival time, so motion-to-force latency includes the wait
        for (int i = 0; i < 64; ++i) {
          std::int64_t arrival_ns = 0;
          const auto bytes = socket.ReceiveOne(rx, &from, &arrival_ns);
          if (!bytes) break;
          if (from != controller) {  // only the configured controller may move the fingers
            ++foreign_frames;
            continue;
          }
          const double arrival_s = static_cast<double>(arrival_ns - start_ns) * 1e-9;
          bridge->OnStatusDatagram(std::as_bytes(std::span(rx.data(), std::min(*bytes, rx.size()))),
                                   std::min(arrival_s, t_s));
        }
        context.messenger().Drain([&](const v1::Envelope& e, const net::Messenger::Endpoint&) {
          switch (context.HandleControl(e)) {
            case services::ServiceContext::ControlResult::kForUs:
              // SHUTDOWN is handled below through StopRequested (zero force first)
              if (context.last_command() == v1::Control::COMMAND_ZERO_FORCE) bridge->SetZeroForceHold(true);
              if (context.last_command() == v1::Control::COMMAND_ENABLE_FORCE) bridge->SetZeroForceHold(false);
              return;
            case services::ServiceContext::ControlResult::kForOthers:
              return;
            case services::ServiceContext::ControlResult::kNotControl:
              break;
          }
          if (e.body_case() != v1::Envelope::kForceModel) return;
          for (const v1::FingerForceModel& m : e.force_model().fingers()) {
            device::Manipulator manipulator;
            if (!ToManipulator(m.finger(), &manipulator) || !IsWellFormed(m)) {
              ++bad_models;
              continue;
            }
            bridge->SetForceModel(manipulator, ToForceModel(m), t_s);
          }
        }, 16);
        // a stop request: zero force first, exit after stop_zero_force_s of zero commands
        if (!stopping && context.StopRequested(tick.now_ns)) {
          stopping = true;
          bridge->RequestShutdown();
          stop_at_ns = tick.now_ns + static_cast<std::int64_t>(options.stop_zero_force_s * 1e9);
        }
        // predict one link latency ahead: from a pose's measurement to its force acting on the
        // finger = the wait in our socket (motion-to-force) + the way up and the way back down
        // (about one controller round trip)
        if (options.prediction_horizon_ms < 0 && tick.tick % horizon_update_every == 0 &&
            bridge->link_round_trip().count() > 100 && bridge->motion_to_force_latency().count() > 100) {
          bridge->SetPredictionHorizon(bridge->motion_to_force_latency().p50_s() +
                                       bridge->link_round_trip().p50_s());
        }
        // update + write
        // after skipped cycles, the time that really passed (ramps and averages stay true)
        bridge->Tick(t_s, tick.dt_s * static_cast<double>(1 + tick.skipped), command);
        socket.SendTo(std::span(reinterpret_cast<const std::uint8_t*>(command.data()), command.size()), controller);
        const auto k = static_cast<std::int64_t>(tick.tick);
        if ((local && k % local_every == 0) || (global && k % global_every == 0)) {
          FillFingerStates(*bridge, &states);
          if (local && k % local_every == 0) context.Send(*local, states);
          if (global && k % global_every == 0) context.Send(*global, states);
        }
        std::uint64_t non_finite = 0;
        for (int i = 0; i < 2; ++i) {
          non_finite += bridge->safety(static_cast<device::Manipulator>(i)).counters().non_finite;
        }
        health.SetCounter(c_status_ok, bridge->frame_counters().accepted());
        health.SetCounter(c_status_bad, bridge->frame_counters().TotalRejected());
        health.SetCounter(c_foreign, foreign_frames);
        health.SetCounter(c_models, bridge->counters().force_models);
        health.SetCounter(c_models_bad, bad_models);
        health.SetCounter(c_lost, bridge->counters().device_lost_events);
        health.SetCounter(c_gap, bridge->counters().tick_gap_disarms);
        health.SetCounter(c_nan, non_finite);
        health.SetCounter(c_dropped, context.messenger().received().TotalDropped());
        health.SetState(bridge->device_lost() ? v1::Health::STATE_DEGRADED : v1::Health::STATE_READY);
        context.Tick(tick.now_ns);
      },
      [&] { return stopping && base::SteadyNowNs() >= stop_at_ns; });

  const auto& m2f = bridge->motion_to_force_latency();
  const auto& rtt = bridge->link_round_trip();
  context.log().info(
      "device_bridge: {} ticks, overruns {}, tick compute p50 {:.1f} us p99 {:.1f} us; status frames {} accepted, {} rejected; {} force models; "
      "motion-to-force p50 {:.1f} us p99 {:.1f} us max {:.1f} us; controller round trip p50 {:.1f} us "
      "p99 {:.1f} us max {:.1f} us",
      loop.stats().ticks, loop.stats().overruns, loop.stats().compute.Percentile(0.5) * 1e-3,
      loop.stats().compute.Percentile(0.99) * 1e-3, bridge->frame_counters().accepted(),
      bridge->frame_counters().TotalRejected(), bridge->counters().force_models, m2f.p50_s() * 1e6,
      m2f.p99_s() * 1e6, m2f.max_s() * 1e6, rtt.p50_s() * 1e6, rtt.p99_s() * 1e6, rtt.max_s() * 1e6);
  return 0;
}

}  // namespace
}  // namespace haptex::device_bridge

int main(int argc, char** argv) {
  auto options = std::make_shared<haptex::device_bridge::Options>();
  return haptex::services::RunService(
      argc, argv, "device_bridge", "The GRAB device bridge (5 kHz, clamps and watchdogs)",
      [options](CLI::App& app) {
        app.add_option("--controller-bind", options->controller_bind, "GRAB protocol socket, HOST:PORT")
            ->capture_default_str();
        app.add_option("--controller", options->controller, "the GRAB controller (or haptex-mock-grab), HOST:PORT")
            ->required();
        app.add_option("--prediction-horizon-ms", options->prediction_horizon_ms,
                       "predict finger poses this far ahead (default: the measured latency from a pose's "
                       "measurement to its force reaching the finger)")
            ->check(CLI::Range(0.0, 50.0));
        app.add_option("--rate", options->rate_hz, "bridge rate [Hz] (the controller's)")
            ->check(CLI::Range(100.0, 20000.0))->capture_default_str();
      },
      [options](haptex::services::ServiceContext& context) { return haptex::device_bridge::Run(context, *options); });
}
