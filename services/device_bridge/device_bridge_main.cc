// haptex-device-bridge: owns the GRAB device. At the controller's rate (5 kHz) it reads the
// controller's StatusFrames, estimates and predicts each fingertip, turns the newest ForceModel
// into a force (F = F0 + K (x - x0)), clamps it (peak, continuous, slew; NaN -> zero), ramps it
// to zero when models go stale or the device is lost, and sends the CommandFrame (BridgeLoop).
// Nothing else talks to the controller.
//
// GRAB socket: receives StatusFrames, sends CommandFrames to --controller.
// haptex socket: receives ForceModel (local_contact), Control; sends FingerStates to
// local_contact and global_sim, Health to the launcher.
// Stopping: forces go to zero first (zero commands for --stop-zero-force), then the process exits.

#include <spdlog/spdlog.h>

#include <iostream>

#include "libs/net/peer_names.h"
#include "libs/scene/scene_defaults.h"
#include "libs/scene/scene_device.h"
#include "services/common/device_link.h"
#include "services/common/run_loop.h"
#include "services/device_bridge/bridge_loop.h"

namespace haptex::device_bridge {
namespace {

struct Options {
  std::string controller_bind = "127.0.0.1:0";
  std::string controller;
  double rate_hz = device::kControllerRate_Hz;
  double stop_zero_force_s = 0.030;
  double prediction_horizon_ms = -1.0;  // < 0: the measured latency, updated as it runs
  std::string passivity;                // "on", "off"; empty: the scene's
};

int Run(services::ServiceContext& context, const Options& options) {
  const v1::Scene scene = context.scene() != nullptr ? context.scene()->scene : v1::Scene{};
  BridgeLoopConfig config{scene::BridgeConfigFromScene(scene), options.rate_hz,
                          scene::FingerStatesToLocalHz(scene), scene::FingerStatesToGlobalHz(scene),
                          scene::ClothFrameHz(scene),          options.prediction_horizon_ms < 0};
  if (!config.measured_prediction_horizon)
    config.bridge.estimator.prediction_horizon_s = options.prediction_horizon_ms * 1e-3;
  if (!options.passivity.empty()) config.bridge.passivity.enabled = options.passivity == "on";
  BridgeLoop work(config,
                  {context.FindPeer(net::peer::kLocalContact), context.FindPeer(net::peer::kGlobalSim),
                   context.FindPeer(net::peer::kViewer)},
                  &context.health());
  services::DeviceLink controller(options.controller_bind, options.controller);
  std::cout << "device_bridge controller socket on " << controller.local_address() << std::endl;

  const auto controller_kernel_drops = context.health().AddCounter("controller_datagrams_dropped_by_kernel");
  constexpr std::size_t kDrainAtMost = 4096;
  const auto drain_budget_ns = static_cast<std::int64_t>(0.25e9 / options.rate_hz);
  runtime::PeriodicLoop loop("device_bridge", options.rate_hz);
  context.health().AddLoop(&loop.stats());
  context.health().SetState(v1::Health::STATE_READY);
  std::int64_t stop_at_ns = std::numeric_limits<std::int64_t>::max();
  loop.Run(
      [&](const runtime::TickInfo& tick) {
        const double t_s = context.SecondsSinceStart(tick.now_ns);
        controller.Drain([&](std::span<const std::byte> bytes, std::int64_t arrival_ns, bool from_controller) {
          work.ReadController(bytes, context.SecondsSinceStart(arrival_ns), t_s, from_controller);
        });
        // everything waiting (newest model wins), unless a flood would hold the tick: then a
        // quarter of the period, and the rest next tick (the kernel counts what overflows)
        services::ReadMessages(context, work, t_s, kDrainAtMost, tick.now_ns + drain_budget_ns);
        if (stop_at_ns == std::numeric_limits<std::int64_t>::max() && context.StopRequested(tick.now_ns)) {
          work.RequestShutdown();
          stop_at_ns = tick.now_ns + static_cast<std::int64_t>(options.stop_zero_force_s * 1e9);
        }
        work.Update(t_s, tick.dt_s * static_cast<double>(1 + tick.skipped));
        controller.Send(work.command());
        work.Write(context);
        context.health().SetCounter(controller_kernel_drops, controller.kernel_drops());
        context.Tick(tick.now_ns);
      },
      [&] { return base::SteadyNowNs() >= stop_at_ns; });

  context.log().info("device_bridge: {} ticks, overruns {}, tick compute p50 {:.1f} us p99 {:.1f} us; {}",
                     loop.stats().ticks, loop.stats().overruns, loop.stats().compute.Percentile(0.5) * 1e-3,
                     loop.stats().compute.Percentile(0.99) * 1e-3, work.Summary());
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
        app.add_option("--passivity", options->passivity,
                       "the passivity controller: on or off (default: the scene's, else on); off only to measure it")
            ->check(CLI::IsMember({"on", "off"}));
        app.add_option("--rate", options->rate_hz, "bridge rate [Hz] (the controller's)")
            ->check(CLI::Range(haptex::device::kMinGrabRate_Hz, haptex::device::kMaxGrabRate_Hz))
            ->capture_default_str();
      },
      [options](haptex::services::ServiceContext& context) { return haptex::device_bridge::Run(context, *options); });
}
