#include "cli/view_command.h"

#include <chrono>
#include <iostream>
#include <memory>
#include <thread>

#include "libs/runtime/shutdown_signal.h"
#include "services/viewer/foxglove_server.h"
#include "services/viewer/run_replay.h"
#include "services/viewer/web_files.h"

namespace haptex::cli {
namespace {

struct ViewOptions {
  std::string run_dir;
  int port = 8765;
  std::string bind = "127.0.0.1";
  double seconds = 0;  // 0: until Ctrl-C
};

int View(const ViewOptions& o) {
  viewer::RunReplay replay;
  viewer::WebFiles web;
  try {
    replay = viewer::LoadRunForReplay(o.run_dir);
    web = viewer::FindWebFiles();
  } catch (const std::exception& e) {
    std::cerr << "haptex view: " << e.what() << "\n";
    return 2;
  }
  viewer::FoxgloveServer::Options options;
  options.bind_address = o.bind;
  options.port = static_cast<std::uint16_t>(o.port);
  options.web_root = web.page_dir;
  options.three_root = web.three_dir;
  options.name = "haptex replay of " + replay.scene_name;
  std::unique_ptr<viewer::FoxgloveServer> server;
  try {
    server = std::make_unique<viewer::FoxgloveServer>(options);
  } catch (const std::exception& e) {
    std::cerr << "haptex view: " << e.what() << "\n";
    return 2;
  }
  server->SetDocument("/session.json", replay.session_json, "application/json");
  server->SetDocument("/run.mcap", std::move(replay.mcap_bytes), "application/octet-stream");
  runtime::InstallShutdownHandlers();
  std::cout << "replay of " << o.run_dir << " (" << replay.scene_name << ", " << replay.messages
            << " messages) on http://" << o.bind << ":" << server->port() << "/ ; Ctrl-C stops" << std::endl;
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(o.seconds);
  while (!runtime::ShutdownRequested() && (o.seconds <= 0 || std::chrono::steady_clock::now() < until)) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return 0;
}

}  // namespace

void AddViewCommand(CLI::App& app, int* exit_code) {
  auto o = std::make_shared<ViewOptions>();
  CLI::App* view = app.add_subcommand("view", "Replay a finished run in the viewer's page (play, pause, timeline)");
  view->add_option("RUN_FOLDER", o->run_dir, "a run folder of haptex launch (with its run.mcap)")->required();
  view->add_option("--port", o->port, "the page's TCP port (0: any free port)")
      ->check(CLI::Range(0, 65535))
      ->capture_default_str();
  view->add_option("--bind", o->bind, "the address to serve on")->capture_default_str();
  view->add_option("--seconds", o->seconds, "stop after this long (0: until Ctrl-C)")->check(CLI::Range(0.0, 1e7));
  view->callback([o, exit_code] { *exit_code = View(*o); });
}

}  // namespace haptex::cli
