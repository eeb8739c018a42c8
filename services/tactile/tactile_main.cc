// haptex-tactile: turns where and how each finger slides over the fabric (TouchTrace from
// local_contact) into drive amplitudes for the two 6 x 4 pin displays (PinFrame), at the
// display's rate. The fabric's virtual surface is built at start-up (or loaded from a tile file
// made by `haptex tactile build`), so the loop only looks heights up.
//
// Receives: TouchTrace, Control. Sends: PinFrame to the display peer, Health to the launcher.

#include <spdlog/spdlog.h>

#include <memory>

#include "libs/base/clock.h"
#include "libs/runtime/periodic_loop.h"
#include "libs/scene/tactile_fabric.h"
#include "services/common/service_context.h"
#include "services/tactile/tactile_loop.h"

namespace haptex::tactile_service {
namespace {

struct Options {
  std::string tile;  // a tile file; else built from the scene's fabric
  scene::TactileSurfaceOverrides surface;
  double rate_hz = 0;  // 0: the scene's display rate, else 500
};

tactile::PeriodicTile LoadOrBuildTile(services::ServiceContext& context, const Options& options) {
  if (!options.tile.empty()) {
    try {
      return tactile::PeriodicTile::LoadFile(options.tile);
    } catch (const std::runtime_error& e) {
      throw std::invalid_argument("tile " + options.tile + ": " + e.what());
    }
  }
  if (context.scene() == nullptr) return scene::BuildVirtualFabric(v1::Fabric(), options.surface).tile;
  const v1::TactileSurface& from_scene = context.scene()->scene.tactile().surface();
  if (!from_scene.source().citation().empty()) {
    context.log().info("tactile: surface values from the scene: {}", from_scene.source().citation());
  }
  return scene::BuildVirtualFabric(context.scene()->fabric, scene::WithSceneSurface(from_scene, options.surface)).tile;
}

int Run(services::ServiceContext& context, const Options& options) {
  const auto display = context.RequirePeer("display");
  double rate_hz = options.rate_hz;
  if (rate_hz <= 0 && context.scene() != nullptr) rate_hz = context.scene()->scene.tactile().display_rate_hz();
  if (rate_hz <= 0) rate_hz = 500;
  tactile::RendererConfig config;
  config.display_rate_hz = rate_hz;
  TactileLoop work(std::make_unique<tactile::RendererModel>(LoadOrBuildTile(context, options), config));

  auto& health = context.health();
  runtime::PeriodicLoop loop("tactile", rate_hz);
  health.AddLoop(&loop.stats());
  const auto c_frames = health.AddCounter("pin_frames_sent");
  const auto c_traces = health.AddCounter("touch_traces");
  const auto c_bad = health.AddCounter("bad_input");
  const auto c_dropped = health.AddCounter("datagrams_dropped");
  health.SetState(v1::Health::STATE_READY);

  v1::PinFrame frame;
  std::uint64_t frames = 0, traces = 0;
  const std::int64_t start_ns = base::SteadyNowNs();
  std::int64_t now_ns = start_ns;
  loop.Run(
      [&](const runtime::TickInfo& tick) {
        now_ns = tick.now_ns;
        const double t_s = static_cast<double>(tick.now_ns - start_ns) * 1e-9;
        context.messenger().Drain([&](const v1::Envelope& e, const net::Messenger::Endpoint&) {
          if (context.HandleControl(e) != services::ServiceContext::ControlResult::kNotControl) return;
          if (e.body_case() != v1::Envelope::kTouchTrace) return;
          work.OnTouchTrace(e.touch_trace(), t_s);
          ++traces;
        });
        const double dt_s = tick.dt_s * static_cast<double>(1 + tick.skipped);
        if (work.Tick(t_s, dt_s, &frame) && context.Send(display, frame)) ++frames;
        health.SetCounter(c_frames, frames);
        health.SetCounter(c_traces, traces);
        health.SetCounter(c_bad, work.bad_fingers() + work.counters(0).bad_input + work.counters(1).bad_input);
        health.SetCounter(c_dropped, context.messenger().received().TotalDropped());
        context.Tick(tick.now_ns);
      },
      [&] { return context.StopRequested(now_ns); });
  // leave the display silent
  for (auto& finger : *frame.mutable_fingers()) {
    for (auto& a : *finger.mutable_amplitude_40hz()) a = 0.0f;
    for (auto& a : *finger.mutable_amplitude_320hz()) a = 0.0f;
  }
  if (frame.fingers_size() > 0) context.Send(display, frame);
  context.log().info("tactile: {} pin frames sent, {} touch traces, loop overruns {}", frames, traces,
                     loop.stats().overruns);
  return 0;
}

}  // namespace
}  // namespace haptex::tactile_service

int main(int argc, char** argv) {
  auto options = std::make_shared<haptex::tactile_service::Options>();
  return haptex::services::RunService(
      argc, argv, "tactile", "TouchTrace -> pin amplitudes (40 Hz and 320 Hz per pin)",
      [options](CLI::App& app) {
        app.add_option("--tile", options->tile, "periodic tile file from `haptex tactile build`");
        app.add_option("--rate", options->rate_hz, "display rate [Hz] (default: the scene's, else 500)")
            ->check(CLI::Range(10.0, 5000.0));
        app.add_option("--pattern", options->surface.pattern, "weave pattern if the fabric has none: plain, twill, satin");
        app.add_option("--warp-pitch-mm", options->surface.warp_pitch_mm, "warp thread pitch [mm]");
        app.add_option("--weft-pitch-mm", options->surface.weft_pitch_mm, "weft thread pitch [mm]");
        app.add_option("--yarn-mm", options->surface.yarn_diameter_mm, "yarn diameter [mm]");
        app.add_option("--smd-um", options->surface.smd_um, "roughness KES SMD [um]");
      },
      [options](haptex::services::ServiceContext& context) { return haptex::tactile_service::Run(context, *options); });
}
