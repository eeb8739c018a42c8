// haptex-tactile: turns where and how each finger slides over the fabric (TouchTrace from
// local_contact) into drive amplitudes for the two 6 x 4 pin displays (PinFrame), at the
// display's rate. The fabric's virtual surface is built at start-up (or loaded from a tile file
// made by `haptex tactile build`), so the loop only looks heights up.
//
// Receives: TouchTrace, Control. Sends: PinFrame to the display peer, Health to the launcher.

#include <spdlog/spdlog.h>

#include <memory>

#include "libs/net/peer_names.h"
#include "libs/scene/scene_defaults.h"
#include "libs/scene/tactile_fabric.h"
#include "services/common/run_loop.h"
#include "services/tactile/tactile_loop.h"

namespace haptex::tactile_service {
namespace {

struct Options {
  std::string tile;  // a tile file; else built from the scene's fabric
  scene::TactileSurfaceOverrides surface;
  double rate_hz = 0;  // 0: the scene's display rate
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
  tactile::RendererConfig config =
      scene::RendererConfigFromScene(context.scene() ? context.scene()->scene : v1::Scene{});
  if (options.rate_hz > 0) config.display_rate_hz = options.rate_hz;
  const double rate_hz = config.display_rate_hz;
  TactileLoop work(std::make_unique<tactile::RendererModel>(LoadOrBuildTile(context, options), config),
                   TactileLoop::kDefaultStaleAfterS, context.RequirePeer(net::peer::kDisplay), &context.health());
  if (const auto viewer = context.FindPeer(net::peer::kViewer)) {
    work.SetViewer(*viewer, 1.0 / scene::ClothFrameHz(context.scene() ? context.scene()->scene : v1::Scene{}));
  }

  runtime::PeriodicLoop loop("tactile", rate_hz);
  context.health().AddLoop(&loop.stats());
  context.health().SetState(v1::Health::STATE_READY);
  services::RunLoop(context, loop, work);
  work.WriteSilence(context);  // leave the display silent
  context.log().info("tactile: {} pin frames sent, {} touch traces, loop overruns {}", work.frames_sent(),
                     work.touch_traces(), loop.stats().overruns);
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
        app.add_option("--rate", options->rate_hz, "display rate [Hz] (default: the scene's)")
            ->check(CLI::Range(10.0, 5000.0));
        app.add_option("--pattern", options->surface.pattern,
                       "weave pattern if the fabric has none: plain, twill, satin");
        app.add_option("--warp-pitch-mm", options->surface.warp_pitch_mm, "warp thread pitch [mm]");
        app.add_option("--weft-pitch-mm", options->surface.weft_pitch_mm, "weft thread pitch [mm]");
        app.add_option("--yarn-mm", options->surface.yarn_diameter_mm, "yarn diameter [mm]");
        app.add_option("--smd-um", options->surface.smd_um, "roughness KES SMD [um]");
      },
      [options](haptex::services::ServiceContext& context) { return haptex::tactile_service::Run(context, *options); });
}
