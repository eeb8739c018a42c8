#include "launch/command_line.h"

#include <sstream>

#include "launch/impair_option.h"

namespace haptex::launch {
namespace {

using P = v1::ServicePlacement;

std::string Number(double value) {
  std::ostringstream s;
  s << value;
  return s.str();
}

// Where `self` sends what it sends `other`: the relay's socket when their link is impaired (the
// listen socket for the link's first service, the upstream one for its second), else `direct`.
std::string Via(const PortPlan& plan, ServiceKind self, ServiceKind other, bool device_link,
                const std::string& direct) {
  const PlacedRelay* relay = plan.FindRelay(self, other);
  if (relay == nullptr || relay->device_link != device_link) return direct;
  return relay->a == self ? relay->listen.Peer() : relay->upstream.Peer();
}

const HostPort& RealAddress(const PortPlan& plan, ServiceKind kind, bool device_link) {
  const PlacedService* service = plan.Find(kind);
  return device_link ? *service->controller : service->haptex;
}

// `flag F` or `flag F,B`; nothing when both are the relay's default.
void AddPerDirection(std::vector<std::string>* argv, const char* flag, const std::string& forward,
                     const std::string& back, const std::string& relay_default) {
  if (forward == relay_default && back == relay_default) return;
  argv->insert(argv->end(), {flag, forward == back ? forward : forward + "," + back});
}

std::string BurstFlagValue(const netsim::GilbertElliottConfig& burst) {
  return ExactNumber(burst.p_good_to_bad) + "," + ExactNumber(burst.p_bad_to_good) + "," + ExactNumber(burst.loss_bad) +
         "," + ExactNumber(burst.loss_good);
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
      address = Via(plan, spec.kind, peer.service, false, other->haptex.Peer());
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
      const std::string controller = mock != nullptr
                                         ? Via(plan, spec.kind, P::SERVICE_MOCK_GRAB, true, mock->controller->Peer())
                                         : scene.device().grab().controller_address();
      argv.insert(argv.end(), {"--controller", controller});
      if (scene.rates().bridge_hz() > 0) argv.insert(argv.end(), {"--rate", Number(scene.rates().bridge_hz())});
      break;
    }
    case P::SERVICE_MOCK_GRAB: {
      argv.insert(argv.end(), {"--controller-bind", service.controller->Bind()});
      if (const PlacedService* bridge = plan.Find(P::SERVICE_DEVICE_BRIDGE)) {
        argv.insert(argv.end(),
                    {"--bridge", Via(plan, spec.kind, P::SERVICE_DEVICE_BRIDGE, true, bridge->controller->Peer())});
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
    case P::SERVICE_VIEWER:
      if (options.viewer_http_port >= 0) {
        argv.insert(argv.end(), {"--http-port", std::to_string(options.viewer_http_port)});
      }
      break;
    default:
      break;  // tactile, global_sim and local_contact take everything from the scene
  }
  return argv;
}

std::string RelayReportPath(const std::string& run_dir, const PlacedRelay& relay) {
  return run_dir + "/network/" + relay.Name() + ".json";
}

std::vector<std::string> RelayCommandLine(const PlacedRelay& relay, const scene::LinkDirections& directions,
                                          const PortPlan& plan, const CommandOptions& options,
                                          const std::string& haptex_path) {
  std::vector<std::string> argv = {haptex_path,
                                   "relay",
                                   "--listen",
                                   relay.listen.Bind(),
                                   "--to",
                                   RealAddress(plan, relay.b, relay.device_link).Peer(),
                                   "--upstream-bind",
                                   relay.upstream.Bind(),
                                   "--back-to",
                                   RealAddress(plan, relay.a, relay.device_link).Peer()};
  const netsim::ImpairmentConfig& f = directions.forward;
  const netsim::ImpairmentConfig& b = directions.back;
  const netsim::ImpairmentConfig none;
  const auto number = [&](const char* flag, double forward, double back, double relay_default) {
    AddPerDirection(&argv, flag, ExactNumber(forward), ExactNumber(back), ExactNumber(relay_default));
  };
  number("--delay-ms", f.delay_ms, b.delay_ms, none.delay_ms);
  number("--jitter-ms", f.jitter_ms, b.jitter_ms, none.jitter_ms);
  AddPerDirection(&argv, "--jitter-dist", std::string(netsim::JitterDistributionName(f.jitter_distribution)),
                  std::string(netsim::JitterDistributionName(b.jitter_distribution)),
                  std::string(netsim::JitterDistributionName(none.jitter_distribution)));
  number("--loss", f.loss, b.loss, none.loss);
  // burst loss values contain commas: one flag for both directions, or one per direction
  const std::string burst_forward = BurstFlagValue(f.burst), burst_back = BurstFlagValue(b.burst);
  const std::string no_burst = BurstFlagValue(none.burst);
  if (burst_forward == burst_back) {
    if (burst_forward != no_burst) argv.insert(argv.end(), {"--burst-loss", burst_forward});
  } else {
    if (burst_forward != no_burst) argv.insert(argv.end(), {"--burst-loss-forward", burst_forward});
    if (burst_back != no_burst) argv.insert(argv.end(), {"--burst-loss-back", burst_back});
  }
  number("--reorder", f.reorder, b.reorder, none.reorder);
  number("--reorder-delay-ms", f.reorder_delay_ms, b.reorder_delay_ms, none.reorder_delay_ms);
  number("--duplicate", f.duplicate, b.duplicate, none.duplicate);
  number("--rate-kbps", f.rate_kbps, b.rate_kbps, none.rate_kbps);
  number("--outage-after-s", f.outage_after_s, b.outage_after_s, none.outage_after_s);
  number("--outage-s", f.outage_s, b.outage_s, none.outage_s);
  argv.insert(argv.end(),
              {"--seed", std::to_string(directions.forward_seed) + "," + std::to_string(directions.back_seed)});
  argv.insert(argv.end(), {"--json", RelayReportPath(options.run_dir, relay)});
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
