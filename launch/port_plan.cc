#include "launch/port_plan.h"

#include <algorithm>
#include <set>
#include <stdexcept>

namespace haptex::launch {
namespace {

using P = v1::ServicePlacement;

const P* PlacementOf(const v1::Scene& scene, ServiceKind kind) {
  for (const P& placement : scene.services()) {
    if (placement.service() == kind) return &placement;
  }
  return nullptr;
}

bool IsLoopback(const std::string& address) {
  return address.rfind("127.", 0) == 0 || address == "localhost" || address == "::1";
}

}  // namespace

std::string HostPort::Peer() const {
  const bool v6 = address.find(':') != std::string::npos;
  return (v6 ? "[" + address + "]" : address) + ":" + std::to_string(port);
}

std::string HostPort::Bind() const {
  if (IsLoopback(address)) return Peer();
  const bool v6 = address.find(':') != std::string::npos;
  return (v6 ? std::string("[::]") : std::string("0.0.0.0")) + ":" + std::to_string(port);
}

const PlacedService* PortPlan::Find(ServiceKind kind) const {
  for (const PlacedService& s : services) {
    if (s.service.kind == kind) return &s;
  }
  return nullptr;
}

std::string PlacedRelay::Name() const { return std::string(Spec(a).name) + "-" + std::string(Spec(b).name); }

const PlacedRelay* PortPlan::FindRelay(ServiceKind x, ServiceKind y) const {
  for (const PlacedRelay& r : relays) {
    if ((r.a == x && r.b == y) || (r.a == y && r.b == x)) return &r;
  }
  return nullptr;
}

int RelayPortOffset(ServiceKind x, ServiceKind y) {
  const auto& table = ServiceTable();
  const auto index = [&](ServiceKind kind) {
    for (std::size_t i = 0; i < table.size(); ++i) {
      if (table[i].kind == kind) return static_cast<int>(i);
    }
    throw std::out_of_range("no launcher table entry for a relayed service");
  };
  const int n = static_cast<int>(table.size());
  const int i = std::min(index(x), index(y));
  const int j = std::max(index(x), index(y));
  const int pair = i * n - i * (i + 1) / 2 + (j - i - 1);  // pairs (0,1), (0,2), ..., (n-2,n-1)
  return kRelayPortOffset + 2 * pair;
}

std::string HostOf(const v1::Scene& scene, ServiceKind kind) {
  const P* placement = PlacementOf(scene, kind);
  return placement == nullptr || placement->host().empty() ? "local" : placement->host();
}

std::map<std::string, std::string> HostAddresses(const v1::Scene& scene) {
  std::map<std::string, std::string> hosts = {{"local", "127.0.0.1"}};
  for (const v1::Host& host : scene.hosts()) hosts[host.name()] = host.address();
  return hosts;
}

bool IsMultiHost(const v1::Scene& scene) {
  for (const P& placement : scene.services()) {
    if (!placement.host().empty() && placement.host() != "local") return true;
  }
  return false;
}

PortPlan AssignPorts(const v1::Scene& scene, const std::vector<PlannedService>& services, std::uint16_t base_port,
                     const std::function<std::uint16_t()>& free_port,
                     const std::vector<v1::LinkImpairment>& impaired_links) {
  if (base_port == 0 && IsMultiHost(scene)) {
    throw std::invalid_argument(
        "services on several hosts need fixed ports: give --base-port (the same on every host)");
  }
  const auto addresses = HostAddresses(scene);
  std::set<std::pair<std::string, std::uint16_t>> used;
  const auto take = [&](const std::string& host, std::uint32_t placed, int offset, const std::string& what) {
    HostPort hp{host, addresses.at(host), 0};
    if (placed != 0) {
      hp.port = static_cast<std::uint16_t>(placed);
    } else if (base_port != 0) {
      const int port = base_port + offset;
      if (port > 65535) throw std::invalid_argument("--base-port " + std::to_string(base_port) + " is too high");
      hp.port = static_cast<std::uint16_t>(port);
    } else {
      // the kernel may hand out a port it gave a moment ago (each probe socket is closed at
      // once): ask again rather than plan one port twice
      hp.port = free_port();
      for (int again = 0; again < 100 && used.count({host, hp.port}) > 0; ++again) hp.port = free_port();
    }
    if (placed == 0 && base_port == 0 && used.count({host, hp.port}) > 0) {
      throw std::invalid_argument("no free port on host " + host + " after 100 tries (" + what + ")");
    }
    if (!used.insert({host, hp.port}).second) {
      throw std::invalid_argument("port " + std::to_string(hp.port) + " on host " + host + " is given twice (" + what +
                                  "); change the scene's ports or --base-port");
    }
    return hp;
  };

  PortPlan plan;
  // one launcher per host that runs a service; the launcher's own placement sets its port
  const P* launcher = PlacementOf(scene, P::SERVICE_LAUNCHER);
  std::set<std::string> hosts = {HostOf(scene, P::SERVICE_LAUNCHER)};
  for (const PlannedService& s : services) hosts.insert(HostOf(scene, s.kind));
  for (const std::string& host : hosts) {
    plan.launchers[host] = take(host, launcher ? launcher->port() : 0, kLauncherPortOffset, "launcher");
  }
  for (const PlannedService& s : services) {
    const ServiceSpec& spec = Spec(s.kind);
    const std::string host = HostOf(scene, s.kind);
    const P* placement = PlacementOf(scene, s.kind);
    PlacedService placed{s, take(host, placement ? placement->port() : 0, spec.port_offset, std::string(spec.name)),
                         std::nullopt};
    if (spec.controller_port_offset >= 0) {
      // a real controller sends its status to a port it is configured with: the scene may fix the bridge's
      const std::uint32_t placed_controller =
          s.kind == P::SERVICE_DEVICE_BRIDGE ? scene.device().bridge_controller_port() : 0;
      placed.controller =
          take(host, placed_controller, spec.controller_port_offset, std::string(spec.name) + " controller socket");
    }
    plan.services.push_back(std::move(placed));
  }
  for (const v1::LinkImpairment& link : impaired_links) {
    const PlacedService* a = plan.Find(link.a());
    const PlacedService* b = plan.Find(link.b());
    if (a == nullptr || b == nullptr || link.a() == link.b()) {
      throw std::invalid_argument("an impaired link must join two services of the run, got " +
                                  P::Service_Name(link.a()) + " and " + P::Service_Name(link.b()));
    }
    PlacedRelay relay{link.a(), link.b(), a->controller.has_value() && b->controller.has_value(), {}, {}};
    const std::string host = a->haptex.host;
    const int offset = RelayPortOffset(link.a(), link.b());
    relay.listen = take(host, 0, offset, "relay " + relay.Name());
    relay.upstream = take(host, 0, offset + 1, "relay " + relay.Name() + " upstream");
    plan.relays.push_back(std::move(relay));
  }
  return plan;
}

}  // namespace haptex::launch
