// haptex-global-sim: the whole fabric (libs/textile) at the scene's global rate, hanging from its
// stand (paper section 4, the low-rate layer). From the fingers' states it cuts the local patch
// each finger may touch over the next step and sends it to local_contact; it merges each
// PatchResult (the patch's new shape) back, holding that part through the next step
// (GlobalSimLoop, libs/dual_layer).
//
// Receives: FingerStates (device_bridge), PatchResult (local_contact), Control.
// Sends: LocalPatch to local_contact, ClothFrame to the optional "viewer" peer, Health.

#include <spdlog/spdlog.h>

#include "libs/net/peer_names.h"
#include "libs/scene/scene_defaults.h"
#include "services/common/run_loop.h"
#include "services/global_sim/global_sim_loop.h"

namespace haptex::global_sim {
namespace {

struct Options {
  double rate_hz = 0;  // 0: the scene's global rate
};

int Run(services::ServiceContext& context, const Options& options) {
  if (context.scene() == nullptr) throw std::invalid_argument("global_sim needs --scene");
  const double rate_hz = options.rate_hz > 0 ? options.rate_hz : scene::GlobalRateHz(context.scene()->scene);
  const GlobalSimPeers peers{context.FindPeer(net::peer::kLocalContact), context.FindPeer(net::peer::kViewer)};
  GlobalSimLoop work(*context.scene(), rate_hz, peers, &context.health());

  runtime::PeriodicLoop loop("global_sim", rate_hz);
  context.health().AddLoop(&loop.stats());
  context.health().SetState(v1::Health::STATE_READY);
  services::RunLoop(context, loop, work);

  const auto& c = work.counters();
  context.log().info("global_sim: {} steps, {} patches sent, {} results merged ({} rejected), overruns {}", c.steps,
                     c.patches_sent, c.results_merged, c.results_rejected, loop.stats().overruns);
  return 0;
}

}  // namespace
}  // namespace haptex::global_sim

int main(int argc, char** argv) {
  auto options = std::make_shared<haptex::global_sim::Options>();
  return haptex::services::RunService(
      argc, argv, "global_sim", "the whole fabric at the global rate; cuts local patches",
      [options](CLI::App& app) {
        app.add_option("--rate", options->rate_hz, "global rate [Hz] (default: the scene's)")
            ->check(CLI::Range(1.0, 1000.0));
      },
      [options](haptex::services::ServiceContext& context) { return haptex::global_sim::Run(context, *options); });
}
