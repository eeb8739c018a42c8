#pragma once
// The services the launcher knows: one table entry each (name, executable, start and stop rank,
// the peers it is given, its own flags). Adding a service is adding an entry here and, in
// service_set.cc, the reason a scene needs it.

#include <string>
#include <string_view>
#include <vector>

#include "haptex/v1/scene.pb.h"

namespace haptex::launch {

using ServiceKind = v1::ServicePlacement::Service;

/// One peer a service is told about: the name it looks the peer up by, and which service it is
/// (SERVICE_LAUNCHER for the launcher of the service's own host).
struct PeerSpec {
  std::string_view peer_name;
  ServiceKind service;
};

struct ServiceSpec {
  ServiceKind kind;
  std::string_view name;        // Health sender, Control target, file names ("device_bridge")
  std::string_view executable;  // relative to the build folder
  std::string_view built_by;    // where its source lives, for "not built" messages
  int start_rank;               // lower starts first
  int stop_rank;                // lower stops first
  int port_offset;              // its UDP port = base port + offset (unless the scene places it)
  int controller_port_offset;   // the GRAB protocol socket's offset; -1: none
  /// Under `--rt-priority P` it runs at SCHED_FIFO P - rt_rank (at least 1): rate-monotonic, so the
  /// 5 kHz loops preempt the 1 kHz contact loop, which preempts tactile, which preempts global_sim's
  /// multi-millisecond steps (at one priority those held the bridge off both cores).
  int rt_rank;
  std::vector<PeerSpec> peers;  // peers it is given, when that peer is in the run
};

/// An rt_rank for a service that stays at normal scheduling under `--rt-priority`.
inline constexpr int kNotRealTime = -1;
/// The SCHED_FIFO priority of a service of `rt_rank` under the launcher's `launcher_priority`;
/// -1 (normal scheduling, not the launcher's inherited one; ChildProcess) for kNotRealTime.
inline int FifoPriorityFor(int launcher_priority, int rt_rank) {
  if (rt_rank == kNotRealTime) return -1;
  return launcher_priority - rt_rank >= 1 ? launcher_priority - rt_rank : 1;
}
/// Relays carry the haptic link at 1 kHz: local_contact's rank.
inline constexpr int kRelayRtRank = 1;

/// Every service, in start order. The launcher's own port is base port + kLauncherPortOffset.
const std::vector<ServiceSpec>& ServiceTable();
inline constexpr int kLauncherPortOffset = 0;

/// Throws std::out_of_range for a kind without an entry (SERVICE_LAUNCHER, unspecified).
const ServiceSpec& Spec(ServiceKind kind);
/// The entry named `name` ("mock_grab"), or nullptr.
const ServiceSpec* FindSpec(std::string_view name);

}  // namespace haptex::launch
