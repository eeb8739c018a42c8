#pragma once
// Where each service of a run listens: its host, its haptex UDP port and (bridge and mock
// controller) its GRAB protocol port; and where each host's launcher listens. Pure: a free-port
// source is passed in for single-host runs that let the system pick ports.

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

struct PortPlan {
  std::vector<PlacedService> services;        // in start order
  std::map<std::string, HostPort> launchers;  // per host name that runs a service (and "local")
  const PlacedService* Find(ServiceKind kind) const;
};

/// Base port used when a scene spreads services over several hosts and none was given: every
/// host's launcher must compute the same ports.
inline constexpr std::uint16_t kDefaultMultiHostBasePort = 47600;

/// The host each service runs on (the scene's placement, else "local") and the hosts' addresses
/// ("local" is 127.0.0.1 unless the scene defines it).
std::string HostOf(const v1::Scene& scene, ServiceKind kind);
std::map<std::string, std::string> HostAddresses(const v1::Scene& scene);
/// True when the scene places any service (or the launcher) on a host other than "local".
bool IsMultiHost(const v1::Scene& scene);

/// Assigns ports. A port placed in the scene wins; else base_port + the table's offset when
/// base_port > 0; else one from free_port (single-host runs only). Throws std::invalid_argument
/// when a multi-host scene has base_port 0, or when two sockets of one host get one port.
PortPlan AssignPorts(const v1::Scene& scene, const std::vector<PlannedService>& services, std::uint16_t base_port,
                     const std::function<std::uint16_t()>& free_port);

}  // namespace haptex::launch
