#pragma once
// Where each service of a run listens: its host, its haptex UDP port and (bridge and mock
// controller) its GRAB protocol port; where each host's launcher listens; and where the relay of
// each impaired link listens. Pure: a free-port source is passed in for single-host runs that let
// the system pick ports.

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "haptex/v1/scene.pb.h"
#include "launch/service_set.h"

namespace haptex::launch {

struct HostPort {
  std::string host;     // the scene's host name ("local")
  std::string address;  // the host's address as the others reach it ("127.0.0.1")
  std::uint16_t port = 0;
  /// "address:port" (IPv6 literals in brackets): where peers send.
  std::string Peer() const;
  /// What the service binds: the address itself on loopback, else the wildcard with the port.
  std::string Bind() const;
};

struct PlacedService {
  PlannedService service;
  HostPort haptex;                     // Messenger socket
  std::optional<HostPort> controller;  // GRAB protocol socket (bridge, mock controller)
};

/// The relay of one impaired link between services a and b (`haptex relay`, on a's host): a sends
/// to `listen`, b to `upstream`; the relay forwards a's datagrams to b's real address and b's to
/// a's, each direction impaired. Services send to the peer on their command line, not to the
/// source of what they received, hence two fixed sockets.
struct PlacedRelay {
  ServiceKind a;
  ServiceKind b;
  bool device_link = false;  // the GRAB protocol sockets (bridge and mock controller), not the haptex ones
  HostPort listen;
  HostPort upstream;
  /// "device_bridge-local_contact" (a, then b).
  std::string Name() const;
};

struct PortPlan {
  std::vector<PlacedService> services;        // in start order
  std::map<std::string, HostPort> launchers;  // per host name that runs a service (and "local")
  std::vector<PlacedRelay> relays;            // one per impaired link, in the links' order
  const PlacedService* Find(ServiceKind kind) const;
  /// The relay between x and y (either order), or nullptr.
  const PlacedRelay* FindRelay(ServiceKind x, ServiceKind y) const;
};

/// Base port used when a scene spreads services over several hosts and none was given: every
/// host's launcher must compute the same ports.
inline constexpr std::uint16_t kDefaultMultiHostBasePort = 47600;

/// A relay's ports with a base port: base + kRelayPortOffset + 2 k (listen) and + 1 (upstream),
/// k the index of its pair among all pairs of the launcher's table, so every host computes the
/// same ports whatever order the links were given in.
inline constexpr int kRelayPortOffset = 16;
int RelayPortOffset(ServiceKind x, ServiceKind y);

/// The host each service runs on (the scene's placement, else "local") and the hosts' addresses
/// ("local" is 127.0.0.1 unless the scene defines it).
std::string HostOf(const v1::Scene& scene, ServiceKind kind);
std::map<std::string, std::string> HostAddresses(const v1::Scene& scene);
/// True when the scene places any service (or the launcher) on a host other than "local".
bool IsMultiHost(const v1::Scene& scene);

/// Assigns ports. A port placed in the scene wins (a service's placement; the bridge's controller
/// socket: device.bridge_controller_port); else base_port + the table's offset when
/// base_port > 0; else one from free_port (single-host runs only). Each link in `impaired_links`
/// gets a relay on its first service's host. Throws std::invalid_argument when a multi-host scene
/// has base_port 0, when two sockets of one host get one port, or when a link's service is not
/// among `services`.
PortPlan AssignPorts(const v1::Scene& scene, const std::vector<PlannedService>& services, std::uint16_t base_port,
                     const std::function<std::uint16_t()>& free_port,
                     const std::vector<v1::LinkImpairment>& impaired_links = {});

}  // namespace haptex::launch
