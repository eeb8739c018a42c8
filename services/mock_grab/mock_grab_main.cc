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
#include "libs/base/clock.h"
#include "libs/runtime/periodic_loop.h"
#include "services/common/service_context.h"
#include "services/mock_grab/force_log.h"

namespace haptex::mock_grab {
namespace {

struct Options {
  std::string controller_bind = "127.0.0.1:0";
  std::string bridge;
  std::string script;  // empty: the scene's, else idle; the scene's parameters apply either way
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
  if (name == "demo") return device::ScriptKind::kDemo;
  throw std::invalid_argument("unknown script '" + name +
                              "' (idle, approach, grasp, pinch, rub, lift, playback or demo)");
}

device::ScriptKind KindFromScene(v1::MockUserScript::Kind kind) {
  switch (kind) {
    case v1::MockUserScript::KIND_APPROACH_AND_TOUCH: return device::ScriptKind::kApproachAndTouch;
    case v1::MockUserScript::KIND_GRASP_AND_SQUEEZE: return device::ScriptKind::kGraspAndSqueeze;
    case v1::MockUserScript::KIND_PINCH_AND_STRETCH: return device::ScriptKind::kPinchAndStretch;
    case v1::MockUserScript::KIND_RUB: return device::ScriptKind::kRub;
    case v1::MockUserScript::KIND_LIFT: return device::ScriptKind::kLift;
    case v1::MockUserScript::KIND_PLAYBACK: return device::ScriptKind::kPlayback;
    case v1::MockUserScript::KIND_DEMO: return device::ScriptKind::kDemo;
    default: return device::ScriptKind::kIdle;
  }
}

double Or(double value, double fallback) { return value > 0 ? value : fallback; }

// The scene's fabric and user, in D. Frame D = W until the scene carries the device's pose
// (the bridge runs with DeviceBridgeConfig::X_WD = identity), so the geometry is W's: the thumb
// is on the front of the fabric, the user's side (+y for a hanging fabric, above a flat one).
void ApplyScene(const v1::Scene& scene, const device::MockControllerConfig& config,
                device::ScriptParams* script) {
  const v1::ClothGeometry& cloth = scene.cloth();
  const Eigen::Vector3d stand_W(cloth.stand_position_w_m().x(), cloth.stand_position_w_m().y(),
                                cloth.stand_position_w_m().z());
  const double height_m = Or(cloth.height_m(), 0.20);
  const bool flat = cloth.mounting() == v1::ClothGeometry::MOUNTING_FLAT_LEDGE;
  // fabric_normal_D points from the thumb's side to the index's side
  script->fabric_normal_D = flat ? Eigen::Vector3d(0, 0, -1) : Eigen::Vector3d(0, -1, 0);
  // default touch point: the fabric's centre at rest (scene.proto, cloth_setup.h)
  script->fabric_point_D_m = stand_W + (flat ? Eigen::Vector3d(0, height_m / 2, 0)
                                             : Eigen::Vector3d(0, 0, -height_m / 2));

  bool has_thumb = false, has_index = false;
  for (const v1::FingerSpec& f : scene.fingers()) {
    const double radius_m = Or(f.radius_m(), 0.008);
    if (f.finger() == v1::FINGER_THUMB) {
      has_thumb = true;
      script->pad_offset_m[static_cast<std::size_t>(device::Manipulator::kThumb)] = radius_m;
    } else if (f.finger() == v1::FINGER_INDEX) {
      has_index = true;
      script->pad_offset_m[static_cast<std::size_t>(device::Manipulator::kIndex)] = radius_m;
    }
  }
  if (has_index && !has_thumb) script->touch_finger = device::Manipulator::kIndex;

  if (!scene.device().has_mock()) return;
  const v1::MockUserScript& user = scene.device().mock().user();
  script->kind = KindFromScene(user.kind());
  if (user.has_touch_point_w_m()) {
    script->fabric_point_D_m = {user.touch_point_w_m().x(), user.touch_point_w_m().y(),
                                user.touch_point_w_m().z()};
  }
  // scene.proto's defaults for what the scene leaves at 0
  const double speed_m_per_s = Or(user.speed_m_per_s(), 0.05);
  const double squeeze_N = Or(user.squeeze_force_n(), 2.0);
  const double stretch_m = Or(user.stretch_m(), 0.01);
  script->speed_m_per_s = speed_m_per_s;
  script->hold_s = Or(user.hold_s(), 0.5);
  // the user moves at this speed through each phase (kDemo: the peak speed of every move)
  script->approach_duration_s = script->rest_gap_m / speed_m_per_s;
  script->stretch_duration_s = stretch_m / speed_m_per_s;
  script->lift_duration_s = script->lift_height_m / speed_m_per_s;
  // the user aims beyond the fabric so that its grip spring pulls with the squeeze force
  script->press_depth_m = squeeze_N / config.finger.user_stiffness_N_per_m;
  script->stretch_D_m = Eigen::Vector3d(stretch_m, 0, 0);
  script->rub_amplitude_m = Or(user.rub_amplitude_m(), 0.01);
}

device::ScriptParams MakeScript(const services::ServiceContext& context, const Options& options,
                                const device::MockControllerConfig& config) {
  device::ScriptParams script;
  std::string playback = options.playback_csv;
  if (context.scene() != nullptr) {
    ApplyScene(context.scene()->scene, config, &script);
    if (playback.empty()) playback = context.scene()->scene.device().mock().user().playback_csv();
  }
  // --script picks the kind; the scene's geometry and user parameters still apply
  if (!options.script.empty()) script.kind = KindFromName(options.script);
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
  const std::int64_t start_ns = base::SteadyNowNs();
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
          sample.host_sequence = controller->host_sequence();
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
        app.add_option("--script", options->script, "idle, approach, grasp, pinch, rub, lift, playback or demo (default: the scene's)");
        app.add_option("--playback-csv", options->playback_csv, "trajectory for the playback script");
        app.add_option("--force-log", options->force_log, "write what the fingers felt to this CSV");
        app.add_option("--rate", options->rate_hz, "controller rate [Hz]")->check(CLI::Range(100.0, 20000.0))->capture_default_str();
        app.add_option("--seed", options->seed, "sensor-noise seed");
      },
      [options](haptex::services::ServiceContext& context) { return haptex::mock_grab::Run(context, *options); });
}
