// haptex-local-contact: the haptic-rate layer (paper sections 4 and 5). Every tick it takes the
// newest FingerStates, runs the contact models on the local patch and one step of the patch's
// dynamics, and sends a ForceModel per finger to the device bridge (F0, K, x0: the bridge
// evaluates it at 5 kHz), a TouchTrace to tactile, and once per global step the patch's state and
// contact forces to global_sim as a PatchResult (LocalContactLoop). Patches are built on a helper
// thread (PatchBuilder).
//
// Receives: FingerStates (bridge), LocalPatch (global_sim), Control.
// Sends: ForceModel to "bridge", TouchTrace to "tactile" (optional), PatchResult to "global_sim",
// Health to the launcher.

#include <spdlog/spdlog.h>

#include "libs/dual_layer/refined_grid.h"
#include "libs/net/peer_names.h"
#include "libs/scene/cloth_setup.h"
#include "libs/scene/scene_contact.h"
#include "libs/scene/scene_defaults.h"
#include "libs/scene/scene_device.h"
#include "services/common/run_loop.h"
#include "services/local_contact/local_contact_loop.h"

namespace haptex::local_contact {
namespace {

struct Options {
  double rate_hz = 0;  // 0: the scene's local rate
  int max_patch_particles = PatchBuildSpec{}.max_patch_particles;
};

int Run(services::ServiceContext& context, const Options& options) {
  if (context.scene() == nullptr) throw std::invalid_argument("local_contact needs --scene");
  const scene::LoadedScene& loaded = *context.scene();
  LocalContactConfig config;
  config.rate_hz = options.rate_hz > 0 ? options.rate_hz : scene::LocalRateHz(loaded.scene);
  config.scene_fingers = scene::SceneFingers(loaded.scene);
  config.force_model_ttl_s = scene::ForceModelStaleS(loaded.scene);
  config.viewer_hz = scene::ClothFrameHz(loaded.scene);
  const scene::ClothSetup setup = scene::MakeClothSetup(loaded);
  PatchBuildSpec spec{setup.material,
                      setup.model_options,
                      scene::LocalStepOptions(loaded.scene, config.rate_hz),
                      scene::ContactOptionsFromScene(loaded),
                      0,
                      options.max_patch_particles};
  spec.particle_id_space =
      static_cast<int>(dual_layer::MakeRefinedGrid(setup.grid.particles_warp, setup.grid.particles_weft,
                                                   static_cast<int>(loaded.scene.model().patch_refinement()))
                           .id_space());
  PatchBuilder builder(spec, PatchBuilder::Threading::kOwnThread);
  const LocalContactPeers peers{context.RequirePeer(net::peer::kBridge), context.FindPeer(net::peer::kGlobalSim),
                                context.FindPeer(net::peer::kTactile), context.FindPeer(net::peer::kViewer)};
  LocalContactLoop work(config, peers, &builder, &context.health());

  runtime::PeriodicLoop loop("local_contact", config.rate_hz);
  runtime::LatencyHistogram compute;
  context.health().AddLoop(&loop.stats());
  context.health().AddLatency("tick_compute", &compute);
  context.health().SetState(v1::Health::STATE_READY);
  services::RunLoop(context, loop, work, &compute);
  work.WriteZeroForce(context);

  const auto& c = work.counters();
  context.log().info(
      "local_contact: {} force models, {} patches ({} handed off, {} busy, {} rejected), "
      "{} results, overruns {}, tick compute p50 {:.1f} us p99 {:.1f} us",
      c.force_models_sent, c.patches_received, c.patch_handoffs, c.patches_dropped_busy,
      c.patches_rejected + builder.build_failures(), c.patch_results_sent, loop.stats().overruns,
      compute.Percentile(0.5) * 1e-3, compute.Percentile(0.99) * 1e-3);
  return 0;
}

}  // namespace
}  // namespace haptex::local_contact

int main(int argc, char** argv) {
  auto options = std::make_shared<haptex::local_contact::Options>();
  return haptex::services::RunService(
      argc, argv, "local_contact", "haptic-rate contact on the local patch; ForceModel to the bridge",
      [options](CLI::App& app) {
        app.add_option("--rate", options->rate_hz, "local rate [Hz] (default: the scene's)")
            ->check(CLI::Range(100.0, 10000.0));
        app.add_option("--max-patch-particles", options->max_patch_particles, "largest patch accepted from global_sim")
            ->check(CLI::Range(16, 65536))
            ->capture_default_str();
      },
      [options](haptex::services::ServiceContext& context) { return haptex::local_contact::Run(context, *options); });
}
