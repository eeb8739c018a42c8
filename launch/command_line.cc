#include "launch/command_line.h"

#include <sstream>

namespace haptex::launch {
namespace {

using P = v1::ServicePlacement;

std::string Number(double value) {
  std::ostringstream s;
  s << value;
  return s.str();
}

}  // namespace

std::string ExecutablePath(const std::string& build_dir, ServiceKind kind) {
  return build_dir + "/" + std::string(Spec(kind).executable);
}

std::string RecordingPath(const std::string& run_dir, ServiceKind kind) {
  return run_dir + "/recordings/" + std::string(Spec(kind).name) + ".pb";
}

std::string ForceLogPath(const std::string& run_dir) { return run_dir + "/mock_grab_forces.csv"; }

std::vector<std::string> CommandLine(const PlacedService& service, const PortPlan& plan, const v1::Scene& scene,
                                     const CommandOptions& options) {
  const ServiceSpec& spec = Spec(service.service.kind);
  std::vector<std::string> argv = {ExecutablePath(options.build_dir, spec.kind), "--scene", options.scene_path,
                                   "--bind", service.haptex.Bind()};
  // peers: the launcher of this host, and each peer service that is part of the run
  for (const PeerSpec& peer : spec.peers) {
    std::string address;
    if (peer.service == P::SERVICE_LAUNCHER) {
      address = plan.launchers.at(service.haptex.host).Peer();
    } else if (const PlacedService* other = plan.Find(peer.service)) {
      address = other->haptex.Peer();
    } else if (peer.service == P::SERVICE_MOCK_PINS && scene.tactile().enabled() && !scene.tactile().mock_display()) {
      address = scene.tactile().display_address();  // a real pin display
    }
    if (!address.empty()) argv.insert(argv.end(), {"--peer", std::string(peer.peer_name) + "=" + address});
  }
  argv.insert(argv.end(), {"--log-level", options.log_level});
  if (scene.rates().health_hz() > 0) argv.insert(argv.end(), {"--health-hz", Number(scene.rates().health_hz())});
  if (!scene.has_recording() || scene.recording().enabled()) {
    argv.insert(argv.end(), {"--record", RecordingPath(options.run_dir, spec.kind)});
  }

  // the service's own flags
  switch (spec.kind) {
    case P::SERVICE_DEVICE_BRIDGE: {
      argv.insert(argv.end(), {"--controller-bind", service.controller->Bind()});
      const PlacedService* mock = plan.Find(P::SERVICE_MOCK_GRAB);
      const std::string controller =
          mock != nullptr ? mock->controller->Peer() : scene.device().grab().controller_address();
      argv.insert(argv.end(), {"--controller", controller});
      if (scene.rates().bridge_hz() > 0) argv.insert(argv.end(), {"--rate", Number(scene.rates().bridge_hz())});
      break;
    }
    case P::SERVICE_MOCK_GRAB: {
      argv.insert(argv.end(), {"--controller-bind", service.controller->Bind()});
      if (const PlacedService* bridge = plan.Find(P::SERVICE_DEVICE_BRIDGE)) {
        argv.insert(argv.end(), {"--bridge", bridge->controller->Peer()});
      }
      argv.insert(argv.end(), {"--force-log", ForceLogPath(options.run_dir)});
      if (scene.device().mock().seed() != 0) {
        argv.insert(argv.end(), {"--seed", std::to_string(scene.device().mock().seed())});
      }
      if (scene.rates().bridge_hz() > 0) argv.insert(argv.end(), {"--rate", Number(scene.rates().bridge_hz())});
      break;
    }
    case P::SERVICE_MOCK_PINS:
      argv.insert(argv.end(), {"--log-csv", options.run_dir + "/pins.csv"});
      break;
    default:
      break;  // tactile, global_sim and local_contact take everything from the scene
  }
  return argv;
}

std::string JoinCommandLine(const std::vector<std::string>& argv) {
  std::string line;
  for (const std::string& a : argv) {
    if (!line.empty()) line += ' ';
    line += a.find(' ') == std::string::npos && !a.empty() ? a : "'" + a + "'";
  }
  return line;
}

}  // namespace haptex::launch
