// The launcher's service table: every launched service has one consistent entry.
#include "launch/service_table.h"

#include <gtest/gtest.h>

#include "libs/net/peer_names.h"
#include "libs/scene/scene_network.h"

#include <algorithm>
#include <set>

namespace haptex::launch {
namespace {

using P = v1::ServicePlacement;

TEST(LaunchServiceTableTest, EveryServiceOnceWithDistinctRanksAndPorts) {
  std::set<int> kinds, starts, stops, offsets;
  std::set<std::string_view> names;
  for (const ServiceSpec& spec : ServiceTable()) {
    EXPECT_TRUE(kinds.insert(spec.kind).second) << spec.name;
    EXPECT_TRUE(names.insert(spec.name).second) << spec.name;
    EXPECT_TRUE(starts.insert(spec.start_rank).second) << spec.name;
    EXPECT_TRUE(stops.insert(spec.stop_rank).second) << spec.name;
    EXPECT_TRUE(offsets.insert(spec.port_offset).second) << spec.name;
    if (spec.controller_port_offset >= 0) {
      EXPECT_TRUE(offsets.insert(spec.controller_port_offset).second);
    }
    EXPECT_NE(spec.port_offset, kLauncherPortOffset);
    EXPECT_EQ(spec.executable.find("haptex-"), spec.executable.rfind('/') + 1) << spec.executable;
  }
  EXPECT_EQ(kinds.size(), 7u);  // every service but the launcher
}

TEST(LaunchServiceTableTest, PeersAreLauncherOrKnownServices) {
  for (const ServiceSpec& spec : ServiceTable()) {
    EXPECT_EQ(spec.peers.front().peer_name, "launcher") << spec.name;
    for (const PeerSpec& peer : spec.peers) {
      if (peer.service != P::SERVICE_LAUNCHER) {
        EXPECT_NO_THROW(Spec(peer.service)) << spec.name;
      }
    }
  }
}

// A service drops what is not addressed to a name it answers to (Envelope.destination): every name
// the table gives a peer is that service's own name or one of its libs/net/peer_names.h aliases.
TEST(LaunchServiceTableTest, EveryPeerNameIsOneItsServiceAnswersTo) {
  for (const ServiceSpec& spec : ServiceTable()) {
    for (const PeerSpec& peer : spec.peers) {
      if (peer.service == P::SERVICE_LAUNCHER) continue;  // every launcher answers to "launcher"
      const std::string_view own = Spec(peer.service).name;
      const std::vector<std::string> aliases = net::peer::AlsoKnownAs(own);
      const bool answers =
          peer.peer_name == own || std::find(aliases.begin(), aliases.end(), peer.peer_name) != aliases.end();
      EXPECT_TRUE(answers) << spec.name << " calls " << own << " '" << peer.peer_name << "'";
    }
  }
}

TEST(LaunchServiceTableTest, SafeOrders) {
  // the bridge starts first and is the last haptex service to stop; its controller stops after it
  EXPECT_EQ(Spec(P::SERVICE_DEVICE_BRIDGE).start_rank, 0);
  for (const ServiceSpec& spec : ServiceTable()) {
    if (spec.kind == P::SERVICE_DEVICE_BRIDGE || spec.kind == P::SERVICE_MOCK_GRAB) continue;
    EXPECT_LT(spec.stop_rank, Spec(P::SERVICE_DEVICE_BRIDGE).stop_rank) << spec.name;
  }
  EXPECT_GT(Spec(P::SERVICE_MOCK_GRAB).stop_rank, Spec(P::SERVICE_DEVICE_BRIDGE).stop_rank);
}

// Impaired links may join the pairs that send each other something: a peer in the table either
// way, or the two ends of the GRAB protocol. The scene layer's list must be that.
TEST(LaunchServiceTableTest, TheSceneLayerAgreesOnWhichServicesTalk) {
  const auto lists = [](const ServiceSpec& from, ServiceKind to) {
    for (const PeerSpec& peer : from.peers) {
      if (peer.service == to) return true;
    }
    return false;
  };
  for (const ServiceSpec& x : ServiceTable()) {
    for (const ServiceSpec& y : ServiceTable()) {
      if (x.kind == y.kind) continue;
      const bool grab = x.controller_port_offset >= 0 && y.controller_port_offset >= 0;
      EXPECT_EQ(scene::ExchangeDatagrams(x.kind, y.kind), lists(x, y.kind) || lists(y, x.kind) || grab)
          << x.name << " - " << y.name;
    }
  }
  for (const ServiceSpec& spec : ServiceTable()) EXPECT_EQ(scene::ServiceName(spec.kind), spec.name);
}

TEST(LaunchServiceTableTest, RealTimeRanksFollowTheRates) {
  const auto rank = [](ServiceKind kind) { return Spec(kind).rt_rank; };
  EXPECT_EQ(rank(P::SERVICE_DEVICE_BRIDGE), 0);
  EXPECT_EQ(rank(P::SERVICE_MOCK_GRAB), 0);
  EXPECT_LT(rank(P::SERVICE_DEVICE_BRIDGE), rank(P::SERVICE_LOCAL_CONTACT));
  EXPECT_LT(rank(P::SERVICE_LOCAL_CONTACT), rank(P::SERVICE_TACTILE));
  EXPECT_LT(rank(P::SERVICE_TACTILE), rank(P::SERVICE_GLOBAL_SIM));
  EXPECT_EQ(kRelayRtRank, rank(P::SERVICE_LOCAL_CONTACT)) << "relays carry the haptic link";
  EXPECT_EQ(FifoPriorityFor(50, 3), 47);
  EXPECT_EQ(FifoPriorityFor(2, 3), 1) << "never below SCHED_FIFO's lowest";
}

TEST(LaunchServiceTableTest, LookUps) {
  EXPECT_EQ(FindSpec("mock_grab")->kind, P::SERVICE_MOCK_GRAB);
  EXPECT_EQ(FindSpec("nope"), nullptr);
  EXPECT_THROW(Spec(P::SERVICE_LAUNCHER), std::out_of_range);
}

}  // namespace
}  // namespace haptex::launch
