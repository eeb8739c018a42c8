// haptex-mock-grab: a stand-in for the GRAB controller. Speaks the controller side of the GRAB
// protocol (docs/grab-protocol.md) at 5 kHz on its own UDP socket: two simulated fingertips
// pulled by an artificial user along a script and pushed by the forces the host commands, with
// the real controller's quantisation, sensor noise, workspace limits and host watchdog
// (MockGrabLoop).
//
// GRAB socket: receives CommandFrames from --bridge only (others are counted as
// commands_from_strangers), sends StatusFrames to --bridge.
// haptex socket: receives Control; sends Health to the launcher.

#include <spdlog/spdlog.h>

#include <iostream>

#include "services/common/device_link.h"
#include "services/common/run_loop.h"
#include "services/mock_grab/mock_grab_loop.h"
#include "services/mock_grab/mock_user.h"

namespace haptex::mock_grab {
namespace {

struct Options {
  std::string controller_bind = "127.0.0.1:0";
  std::string bridge;
  std::string script;  // empty: the scene's, else idle; the scene's parameters apply either way
  std::string playback_csv;
  std::string force_log;
  double rate_hz = device::kControllerRate_Hz;
  std::uint64_t seed = 1;
};

int Run(services::ServiceContext& context, const Options& options) {
  device::MockControllerConfig config;
  config.seed = options.seed;
  config.Validate();
  std::unique_ptr<ForceLog> log;
  if (!options.force_log.empty()) log = std::make_unique<ForceLog>(options.force_log);
  const v1::Scene scene = context.scene() != nullptr ? context.scene()->scene : v1::Scene{};
  MockGrabLoop work(config, MockUser(scene, options.script, options.playback_csv, config), log.get(),
                    context.start_ns(), &context.health());
  services::DeviceLink bridge(options.controller_bind, options.bridge);
  // tests and the launcher read this line to find the controller port
  std::cout << "mock_grab controller listening on " << bridge.local_address() << std::endl;

  runtime::PeriodicLoop loop("mock_grab", options.rate_hz);
  context.health().AddLoop(&loop.stats());
  context.health().SetState(v1::Health::STATE_READY);
  std::int64_t now_ns = context.start_ns();
  loop.Run(
      [&](const runtime::TickInfo& tick) {
        now_ns = tick.now_ns;
        const double t_s = context.SecondsSinceStart(tick.now_ns);
        bridge.Drain([&](std::span<const std::byte> bytes, std::int64_t, bool from_bridge) {
          work.ReadHost(bytes, t_s, from_bridge);
        });
        services::ReadMessages(context, work, t_s, 8);
        // the time that really passed: a stall of ours is the core's to see (it pauses its world)
        work.Update(t_s, tick.dt_s * static_cast<double>(1 + tick.skipped));
        bridge.Send(work.status());
        work.Write(context);
        context.Tick(tick.now_ns);
      },
      [&] { return context.StopRequested(now_ns); });

  const device::MockGrabController& c = work.controller();
  context.log().info("mock_grab: {} steps, {} commands accepted, {} rejected, {} host timeouts, loop overruns {}",
                     c.counters().steps, c.commands_accepted(), c.frame_counters().TotalRejected(),
                     c.counters().host_timeouts, loop.stats().overruns);
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
        app.add_option("--bridge", options->bridge,
                       "the bridge's GRAB socket: StatusFrames go there, commands count only from there")
            ->required();
        app.add_option("--script", options->script,
                       "idle, approach, grasp, pinch, rub, lift, playback, demo or fold (default: the scene's)");
        app.add_option("--playback-csv", options->playback_csv, "trajectory for the playback script");
        app.add_option("--force-log", options->force_log, "write what the fingers felt to this CSV");
        app.add_option("--rate", options->rate_hz, "controller rate [Hz]")
            ->check(CLI::Range(haptex::device::kMinGrabRate_Hz, haptex::device::kMaxGrabRate_Hz))
            ->capture_default_str();
        app.add_option("--seed", options->seed, "sensor-noise seed");
      },
      [options](haptex::services::ServiceContext& context) { return haptex::mock_grab::Run(context, *options); });
}
