// haptex-viewer: the fabric, the fingers and their forces for a person to watch (docs/viewer.md).
// It serves the page (web/viewer, three.js) and speaks the Foxglove WebSocket protocol on one TCP
// port, so the page and Foxglove see the same channels; ViewerLoop passes on what the services
// send it and builds the 3-D scene. It only watches: nothing here reaches a haptic loop, and the
// server's thread and clients never hold the loop (FoxgloveServer drops for a slow client).
//
// Receives: ClothFrame (global_sim), FingerStates (device_bridge), ForceModel and TouchTrace
// (local_contact), PinFrame (tactile), Health (each), Control.
// Sends: Health to the launcher.

#include <spdlog/spdlog.h>

#include <chrono>
#include <iostream>

#include "libs/scene/scene_defaults.h"
#include "services/common/run_loop.h"
#include "services/viewer/foxglove_sink.h"
#include "services/viewer/session_info.h"
#include "services/viewer/viewer_loop.h"
#include "services/viewer/web_files.h"

namespace haptex::viewer {
namespace {

struct Options {
  int http_port = -1;  // < 0: the scene's
  std::string http_bind;
};

int Run(services::ServiceContext& context, const Options& options) {
  if (context.scene() == nullptr) throw std::invalid_argument("viewer needs --scene");
  const v1::Scene& scene = context.scene()->scene;
  const WebFiles web = FindWebFiles();
  FoxgloveServer::Options server_options;
  server_options.bind_address = options.http_bind.empty() ? scene::ViewerBindAddress(scene) : options.http_bind;
  server_options.port =
      static_cast<std::uint16_t>(options.http_port >= 0 ? options.http_port : scene::ViewerPort(scene));
  server_options.web_root = web.page_dir;
  server_options.three_root = web.three_dir;
  server_options.name = "haptex " + scene.name();
  FoxgloveServer server(server_options);
  server.SetDocument("/session.json", SessionJson(*context.scene(), ""), "application/json");
  std::cout << "viewer page on http://" << server_options.bind_address << ":" << server.port() << "/" << std::endl;

  ViewerLoopConfig config;
  config.frame_hz = scene::ClothFrameHz(scene);
  config.epoch_at_start_ns = static_cast<std::uint64_t>(
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch())
          .count());
  config.scene = SceneViewConfigFromScene(*context.scene());
  FoxgloveSink sink(&server);
  ViewerLoop work(config, &sink, &context.health());
  const auto clients = context.health().AddCounter("clients_connected");
  const auto dropped = context.health().AddCounter("messages_dropped_slow_client");
  const auto bad = context.health().AddCounter("client_messages_bad");

  // twice the frame rate: a frame waits at most half a period for its turn
  runtime::PeriodicLoop loop("viewer", 2.0 * config.frame_hz);
  context.health().AddLoop(&loop.stats());
  context.health().SetState(v1::Health::STATE_READY);
  struct Counted {
    ViewerLoop& work;
    FoxgloveServer& server;
    runtime::HealthReporter& health;
    runtime::HealthReporter::CounterId clients, dropped, bad;
    void Read(const v1::Envelope& envelope, double t_s) { work.Read(envelope, t_s); }
    void Update(double t_s, double dt_s) {
      work.Update(t_s, dt_s);
      const FoxgloveServer::Counters c = server.counters();
      health.SetCounter(clients, c.clients_connected);
      health.SetCounter(dropped, c.messages_dropped_slow_client);
      health.SetCounter(bad, c.client_messages_bad);
    }
    void Write(services::Outbox& out) { work.Write(out); }
  } counted{work, server, context.health(), clients, dropped, bad};
  services::RunLoop(context, loop, counted);

  const auto& c = work.counters();
  const FoxgloveServer::Counters s = server.counters();
  context.log().info("viewer: {} messages passed on, {} whole cloth frames, {} scene updates, {} clients, {} dropped",
                     c.messages_passed_on, c.cloth_frames_whole, c.scene_updates, s.clients_connected,
                     s.messages_dropped_slow_client);
  return 0;
}

}  // namespace
}  // namespace haptex::viewer

int main(int argc, char** argv) {
  auto options = std::make_shared<haptex::viewer::Options>();
  return haptex::services::RunService(
      argc, argv, "viewer", "the fabric, fingers and forces in a web page and for Foxglove",
      [options](CLI::App& app) {
        app.add_option("--http-port", options->http_port, "the page's and WebSocket's TCP port (default: the scene's)")
            ->check(CLI::Range(0, 65535));
        app.add_option("--http-bind", options->http_bind, "the address to serve on (default: the scene's)");
      },
      [options](haptex::services::ServiceContext& context) { return haptex::viewer::Run(context, *options); });
}
