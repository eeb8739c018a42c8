// haptex-mock-grab: a stand-in for the GRAB controller. Speaks the controller side of the GRAB
// protocol (docs/grab-protocol.md) at 5 kHz on its own UDP socket: two simulated fingertips
// pulled by an artificial user along a script and pushed by the forces the host commands, with
// the real controller's quantisation, sensor noise, workspace limits and host watchdog.
//
// GRAB socket: receives CommandFrames, sends StatusFrames to --bridge.
// haptex socket: receives Control; sends Health to the launcher.

#include <spdlog/spdlog.h>

#include <array>
#include <cstddef>
#include <iostream>
#include <memory>

#include "libs/device/mock_grab_controller.h"
#include "libs/device/trajectory_csv.h"
#include "libs/net/udp_address.h"
#include "libs/net/udp_endpoint.h"
#include "libs/runtime/clock.h"
#include "libs/runtime/periodic_loop.h"
#include "services/common/service_context.h"
#include "services/mock_grab/force_log.h"

namespace haptex::mock_grab {
namespace {

struct Options {
  std::string controller_bind = "127.0.0.1:0";
  std::string bridge;
  std::string script;  // empty: the scene's, else idle
  std::string playback_csv;
  std::string force_log;
  double rate_hz = 5000;
  std::uint64_t seed = 1;
};

device::ScriptKind KindFromName(const std::string& name) {
  if (name == "idle") return device::ScriptKind::kIdle;
  if (name == "approach") return device::ScriptKind::kApproachAndTouch;
  if (name == "grasp") return device::ScriptKind::kGraspAndSqueeze;
  if (name == "pinch") return device::ScriptKind::kPinchAndStretch;
  if (name == "rub") return device::ScriptKind::kRub;
  if (name == "lift") return device::ScriptKind::kLift;
  if (name == "playback") return device::ScriptKind::kPlayback;
  throw std::invalid_argument("unknown script '" + name +
                              "' (idle, approach, grasp, pinch, rub, lift or playback)");
}

device::ScriptKind KindFromScene(v1::MockUserScript::Kind kind) {
  switch (kind) {
    case v1::MockUserScript::KIND_APPROACH_AND_TOUCH: return device::ScriptKind::kApproachAndTouch;
    case v1::MockUserScript::KIND_GRASP_AND_SQUEEZE: return device::ScriptKind::kGraspAndSqueeze;
    case v1::MockUserScript::KIND_PINCH_AND_STRETCH: return device::ScriptKind::kPinchAndStretch;
    case v1::MockUserScript::KIND_RUB: return device::ScriptKind::kRub;
    case v1::MockUserScript::KIND_LIFT: return device::ScriptKind::kLift;
    case v1::MockUserScript::KIND_PLAYBACK: return device::ScriptKind::kPlayback;
    default: return device::ScriptKind::kIdle;
  }
}

device::ScriptParams MakeScript(const services::ServiceContext& context, const Options& options,
                                const device::MockControllerConfig& config) {
  device::ScriptParams script;
  std::string playback = options.playback_csv;
  if (!options.script.empty()) {
    script.kind = KindFromName(options.script);
  } else if (context.scene() != nullptr && context.scene()->scene.device().has_mock()) {
    const v1::MockUserScript& user = context.scene()->scene.device().mock().user();
    script.kind = KindFromScene(user.kind());
    // frame D = W until the scene carries the device's pose (DeviceBridgeConfig::X_WD)
    if (user.has_touch_point_w_m()) {
      script.fabric_point_D_m = {user.touch_point_w_m().x(), user.touch_point_w_m().y(),
                                 user.touch_point_w_m().z()};
    }
    if (user.speed_m_per_s() > 0) {
      // the user moves at this speed through each phase
      script.approach_duration_s = script.rest_gap_m / user.speed_m_per_s();
      if (user.stretch_m() > 0) script.stretch_duration_s = user.stretch_m() / user.speed_m_per_s();
      script.lift_duration_s = script.lift_height_m / user.speed_m_per_s();
    }
    if (user.squeeze_force_n() > 0) {
      // the user aims beyond the fabric so that its grip spring pulls with the squeeze force
      script.press_depth_m = user.squeeze_force_n() / config.finger.user_stiffness_N_per_m;
    }
    if (user.stretch_m() > 0) script.stretch_D_m = Eigen::Vector3d(user.stretch_m(), 0, 0);
    if (user.rub_amplitude_m() > 0) script.rub_amplitude_m = user.rub_amplitude_m();
    if (playback.empty()) playback = user.playback_csv();
  }
  if (script.kind == device::ScriptKind::kPlayback) {
    if (playback.empty()) throw std::invalid_argument("the playback script needs --playback-csv FILE");
    script.trajectory = device::LoadTrajectoryCsv(playback);
  }
  script.Validate();
  return script;
}

int Run(services::ServiceContext& context, const Options& options) {
  device::MockControllerConfig config;
  config.seed = options.seed;
  config.Validate();
  auto controller = std::make_unique<device::MockGrabController>(config, MakeScript(context, options, config));
  net::UdpEndpoint socket(options.controller_bind);
  const auto bridge = net::ResolveUdpAddress(options.bridge);
  std::unique_ptr<ForceLog> log;
  if (!options.force_log.empty()) log = std::make_unique<ForceLog>(options.force_log);
  // tests and the launcher read this line to find the controller port
  std::cout << "mock_grab controller listening on " << net::FormatUdpAddress(socket.local_endpoint())
            << std::endl;

  auto& health = context.health();
  const auto c_steps = health.AddCounter("steps");
  const auto c_accepted = health.AddCounter("commands_accepted");
  const auto c_rejected = health.AddCounter("commands_rejected");
  const auto c_timeouts = health.AddCounter("host_timeouts");
  const auto c_log_dropped = health.AddCounter("force_log_dropped");
  runtime::PeriodicLoop loop("mock_grab", options.rate_hz);
  health.AddLoop(&loop.stats());
  health.SetState(v1::Health::STATE_READY);

  std::array<std::uint8_t, 2048> rx{};
  std::array<std::byte, device::kStatusFrameSize> status{};
  net::UdpEndpoint::Endpoint from;
  const std::int64_t start_ns = runtime::SteadyNowNs();
  std::int64_t now_ns = start_ns;
  loop.Run(
      [&](const runtime::TickInfo& tick) {
        now_ns = tick.now_ns;
        const double t_s = static_cast<double>(tick.now_ns - start_ns) * 1e-9;
        // commands: newest valid one wins inside the controller; bounded against floods
        for (int i = 0; i < 64; ++i) {
          const auto bytes = socket.ReceiveOne(rx, &from);
          if (!bytes) break;
          // a datagram larger than the buffer is cut, and rejected as too long by the decoder
          const std::size_t n = std::min(*bytes, rx.size());
          controller->OnCommandDatagram(std::as_bytes(std::span(rx.data(), n)), t_s);
        }
        controller->Step(t_s, tick.dt_s, status);
        socket.SendTo(std::span(reinterpret_cast<const std::uint8_t*>(status.data()), status.size()), bridge);
        if (log) {
          ForceSample sample;
          sample.time_ns = tick.now_ns;
          for (int f = 0; f < 2; ++f) {
            const auto& finger = controller->finger(static_cast<device::Manipulator>(f));
            for (int k = 0; k < 3; ++k) {
              sample.commanded_N[f][k] = static_cast<float>(finger.commanded_force_D_N(k));
              sample.applied_N[f][k] = static_cast<float>(finger.applied_force_D_N(k));
            }
          }
          sample.host_timed_out = controller->host_timed_out();
          log->Push(sample);
        }
        context.messenger().Drain([&](const v1::Envelope& e, const net::Messenger::Endpoint&) {
          (void)context.HandleControl(e);  // SHUTDOWN stops the loop
        }, 8);
        health.SetCounter(c_steps, controller->counters().steps);
        health.SetCounter(c_accepted, controller->frame_counters().accepted());
        health.SetCounter(c_rejected, controller->frame_counters().TotalRejected());
        health.SetCounter(c_timeouts, controller->counters().host_timeouts);
        if (log) health.SetCounter(c_log_dropped, log->dropped());
        context.Tick(tick.now_ns);
      },
      [&] { return context.StopRequested(now_ns); });

  context.log().info("mock_grab: {} steps, {} commands accepted, {} rejected, {} host timeouts, loop overruns {}",
                     controller->counters().steps, controller->frame_counters().accepted(),
                     controller->frame_counters().TotalRejected(), controller->counters().host_timeouts,
                     loop.stats().overruns);
  return 0;
}

}  // namespace
}  // namespace haptex::mock_grab

int main(int argc, char** argv) {
  auto options = std::make_shared<haptex::mock_grab::Options>();
  return haptex::services::RunService(
      argc, argv, "mock_grab", "Stand-in for the GRAB controller (GRAB protocol at 5 kHz)",
      [options](CLI::App& app) {
        app.add_option("--controller-bind", options->controller_bind, "GRAB protocol socket, HOST:PORT")
            ->capture_default_str();
        app.add_option("--bridge", options->bridge, "where StatusFrames go: the bridge's GRAB socket")->required();
        app.add_option("--script", options->script, "idle, approach, grasp, pinch, rub, lift or playback (default: the scene's)");
        app.add_option("--playback-csv", options->playback_csv, "trajectory for the playback script");
        app.add_option("--force-log", options->force_log, "write what the fingers felt to this CSV");
        app.add_option("--rate", options->rate_hz, "controller rate [Hz]")->check(CLI::Range(100.0, 20000.0))->capture_default_str();
        app.add_option("--seed", options->seed, "sensor-noise seed");
      },
      [options](haptex::services::ServiceContext& context) { return haptex::mock_grab::Run(context, *options); });
}
