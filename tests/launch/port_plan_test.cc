// Port assignment: scene placements win, then base port + offset, else free ports on one host.
#include "launch/port_plan.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <tuple>

#include "tests/launch/launch_test_support.h"

namespace haptex::launch {
namespace {

using P = v1::ServicePlacement;
using ::testing::HasSubstr;

TEST(LaunchPortPlanTest, BasePortPlusTableOffsets) {
  const v1::Scene scene = testing::ShippedScene("demo");
  const PortPlan plan = AssignPorts(scene, DeriveServices(scene), 40000, [] { return std::uint16_t{1}; });
  ASSERT_EQ(plan.services.size(), 7u);
  EXPECT_EQ(plan.launchers.at("local").port, 40000);
  const PlacedService* bridge = plan.Find(P::SERVICE_DEVICE_BRIDGE);
  ASSERT_NE(bridge, nullptr);
  EXPECT_EQ(bridge->haptex.port, 40000 + Spec(P::SERVICE_DEVICE_BRIDGE).port_offset);
  ASSERT_TRUE(bridge->controller.has_value());
  EXPECT_EQ(bridge->controller->port, 40000 + Spec(P::SERVICE_DEVICE_BRIDGE).controller_port_offset);
  EXPECT_EQ(bridge->haptex.Peer(), "127.0.0.1:" + std::to_string(bridge->haptex.port));
  EXPECT_EQ(bridge->haptex.Bind(), bridge->haptex.Peer());  // loopback binds the address itself
  EXPECT_FALSE(plan.Find(P::SERVICE_TACTILE)->controller.has_value());
}

TEST(LaunchPortPlanTest, FreePortsWhenNoBasePortOnOneHost) {
  const v1::Scene scene = testing::ShippedScene("demo");
  std::uint16_t next = 50000;
  const PortPlan plan = AssignPorts(scene, DeriveServices(scene), 0, [&] { return next++; });
  std::set<std::uint16_t> ports = {plan.launchers.at("local").port};
  for (const PlacedService& s : plan.services) {
    EXPECT_TRUE(ports.insert(s.haptex.port).second);
    if (s.controller) {
      EXPECT_TRUE(ports.insert(s.controller->port).second);
    }
  }
  EXPECT_EQ(ports.size(), 10u);  // launcher + 7 services + 2 controller sockets
}

TEST(LaunchPortPlanTest, AFreePortHandedOutTwiceIsAskedForAgain) {
  const v1::Scene scene = testing::ShippedScene("demo");
  // the kernel's ephemeral ports can repeat: every port comes twice here
  int calls = 0;
  const PortPlan plan =
      AssignPorts(scene, DeriveServices(scene), 0, [&] { return static_cast<std::uint16_t>(50000 + calls++ / 2); });
  std::set<std::uint16_t> ports = {plan.launchers.at("local").port};
  for (const PlacedService& s : plan.services) {
    EXPECT_TRUE(ports.insert(s.haptex.port).second);
    if (s.controller) {
      EXPECT_TRUE(ports.insert(s.controller->port).second);
    }
  }
  EXPECT_EQ(ports.size(), 10u);
}

TEST(LaunchPortPlanTest, ScenePlacementWins) {
  const v1::Scene scene = testing::SceneFromText(R"(
    name: "placed" fabric { database_name: "wang2011_black_denim_11oz" }
    fingers { finger: FINGER_INDEX } device { mock {} }
    services { service: SERVICE_DEVICE_BRIDGE port: 41234 }
    services { service: SERVICE_LAUNCHER port: 41000 })");
  const PortPlan plan = AssignPorts(scene, DeriveServices(scene), 45000, [] { return std::uint16_t{1}; });
  EXPECT_EQ(plan.Find(P::SERVICE_DEVICE_BRIDGE)->haptex.port, 41234);
  EXPECT_EQ(plan.launchers.at("local").port, 41000);
  EXPECT_EQ(plan.Find(P::SERVICE_MOCK_GRAB)->haptex.port, 45000 + Spec(P::SERVICE_MOCK_GRAB).port_offset);
}

TEST(LaunchPortPlanTest, CollisionIsRefusedWithTheFix) {
  const v1::Scene scene = testing::SceneFromText(R"(
    name: "clash" fabric { database_name: "wang2011_black_denim_11oz" }
    fingers { finger: FINGER_INDEX } device { mock {} }
    services { service: SERVICE_DEVICE_BRIDGE port: 45006 })");  // = base + the mock's offset
  try {
    AssignPorts(scene, DeriveServices(scene), 45000, [] { return std::uint16_t{1}; });
    FAIL() << "expected a port clash";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("port 45006 on host local is given twice"));
    EXPECT_THAT(e.what(), HasSubstr("--base-port"));
  }
}

TEST(LaunchPortPlanTest, RemoteSceneUsesHostAddressesAndOneLauncherPerHost) {
  const v1::Scene scene = testing::ShippedScene("remote");
  EXPECT_TRUE(IsMultiHost(scene));
  EXPECT_THROW(AssignPorts(scene, DeriveServices(scene), 0, [] { return std::uint16_t{1}; }), std::invalid_argument);
  const PortPlan plan = AssignPorts(scene, DeriveServices(scene), kDefaultMultiHostBasePort, nullptr);
  EXPECT_EQ(plan.launchers.at("lab").Peer(), "192.0.2.10:" + std::to_string(kDefaultMultiHostBasePort));
  EXPECT_EQ(plan.launchers.at("compute").address, "192.0.2.20");
  const PlacedService* contact = plan.Find(P::SERVICE_LOCAL_CONTACT);
  EXPECT_EQ(contact->haptex.host, "compute");
  EXPECT_EQ(contact->haptex.address, "192.0.2.20");
  EXPECT_EQ(contact->haptex.Bind(), "0.0.0.0:" + std::to_string(contact->haptex.port));  // not loopback: wildcard
  EXPECT_EQ(plan.Find(P::SERVICE_MOCK_GRAB)->haptex.host, "lab");
  // both hosts' launchers compute the same ports
  const PortPlan again = AssignPorts(scene, DeriveServices(scene), kDefaultMultiHostBasePort, nullptr);
  for (std::size_t i = 0; i < plan.services.size(); ++i) {
    EXPECT_EQ(plan.services[i].haptex.Peer(), again.services[i].haptex.Peer());
  }
}

v1::LinkImpairment Link(ServiceKind a, ServiceKind b) {
  v1::LinkImpairment link;
  link.set_a(a);
  link.set_b(b);
  return link;
}

TEST(LaunchPortPlanTest, RelayPortsAreBasePlusThePairsOffsetWhateverTheLinksOrder) {
  const v1::Scene scene = testing::ShippedScene("demo");
  const auto links = {Link(P::SERVICE_DEVICE_BRIDGE, P::SERVICE_LOCAL_CONTACT),
                      Link(P::SERVICE_TACTILE, P::SERVICE_MOCK_PINS)};
  const PortPlan plan = AssignPorts(scene, DeriveServices(scene), 40000, nullptr, links);
  ASSERT_EQ(plan.relays.size(), 2u);
  const PlacedRelay& contact = plan.relays[0];
  EXPECT_EQ(contact.Name(), "device_bridge-local_contact");
  EXPECT_FALSE(contact.device_link);
  const int offset = RelayPortOffset(P::SERVICE_DEVICE_BRIDGE, P::SERVICE_LOCAL_CONTACT);
  EXPECT_EQ(contact.listen.port, 40000 + offset);
  EXPECT_EQ(contact.upstream.port, 40000 + offset + 1);
  EXPECT_EQ(contact.listen.Bind(), "127.0.0.1:" + std::to_string(40000 + offset));
  EXPECT_EQ(plan.FindRelay(P::SERVICE_LOCAL_CONTACT, P::SERVICE_DEVICE_BRIDGE), &plan.relays[0]);  // either order
  EXPECT_EQ(plan.FindRelay(P::SERVICE_GLOBAL_SIM, P::SERVICE_LOCAL_CONTACT), nullptr);

  // the other order of links, and of a link's ends: the same ports
  const PortPlan reversed = AssignPorts(
      scene, DeriveServices(scene), 40000, nullptr,
      {Link(P::SERVICE_MOCK_PINS, P::SERVICE_TACTILE), Link(P::SERVICE_LOCAL_CONTACT, P::SERVICE_DEVICE_BRIDGE)});
  EXPECT_EQ(reversed.relays[1].listen.port, contact.listen.port);
  EXPECT_EQ(reversed.relays[0].listen.port, plan.relays[1].listen.port);
}

TEST(LaunchPortPlanTest, EveryPairHasItsOwnRelayPortsAboveTheServices) {
  std::set<int> ports;
  int highest_service_port = kLauncherPortOffset;
  for (const ServiceSpec& s : ServiceTable()) {
    highest_service_port = std::max({highest_service_port, s.port_offset, s.controller_port_offset});
  }
  for (const ServiceSpec& x : ServiceTable()) {
    for (const ServiceSpec& y : ServiceTable()) {
      if (x.kind == y.kind) continue;
      const int offset = RelayPortOffset(x.kind, y.kind);
      EXPECT_EQ(offset, RelayPortOffset(y.kind, x.kind));
      EXPECT_GT(offset, highest_service_port);
      ports.insert(offset);
      ports.insert(offset + 1);
    }
  }
  const std::size_t n = ServiceTable().size();
  EXPECT_EQ(ports.size(), n * (n - 1));       // two ports per unordered pair, none shared
  EXPECT_LE(*ports.rbegin(), 65535 - 65000);  // fits above the highest --base-port
}

TEST(LaunchPortPlanTest, TheGrabLinkIsRelayedBetweenTheControllerSockets) {
  const v1::Scene scene = testing::ShippedScene("demo");
  const PortPlan plan =
      AssignPorts(scene, DeriveServices(scene), 40000, nullptr, {Link(P::SERVICE_DEVICE_BRIDGE, P::SERVICE_MOCK_GRAB)});
  EXPECT_TRUE(plan.relays.at(0).device_link);
}

TEST(LaunchPortPlanTest, FreeRelayPortsOnOneHostAreDistinct) {
  const v1::Scene scene = testing::ShippedScene("demo");
  std::uint16_t next = 50000;
  const PortPlan plan = AssignPorts(scene, DeriveServices(scene), 0, [&] { return next++; },
                                    {Link(P::SERVICE_DEVICE_BRIDGE, P::SERVICE_LOCAL_CONTACT)});
  std::set<std::uint16_t> ports = {plan.launchers.at("local").port};
  for (const PlacedService& s : plan.services) {
    ports.insert(s.haptex.port);
    if (s.controller) ports.insert(s.controller->port);
  }
  ports.insert(plan.relays.at(0).listen.port);
  ports.insert(plan.relays.at(0).upstream.port);
  EXPECT_EQ(ports.size(), 12u);
}

TEST(LaunchPortPlanTest, ARemoteLinksRelayRunsOnItsFirstServicesHost) {
  const v1::Scene scene = testing::ShippedScene("remote");
  for (const auto& [a, b, host] : {std::tuple{P::SERVICE_DEVICE_BRIDGE, P::SERVICE_LOCAL_CONTACT, "lab"},
                                   std::tuple{P::SERVICE_LOCAL_CONTACT, P::SERVICE_DEVICE_BRIDGE, "compute"}}) {
    const PortPlan plan = AssignPorts(scene, DeriveServices(scene), kDefaultMultiHostBasePort, nullptr, {Link(a, b)});
    const PlacedRelay& relay = plan.relays.at(0);
    EXPECT_EQ(relay.listen.host, host);
    EXPECT_EQ(relay.upstream.host, host);
    EXPECT_EQ(relay.upstream.Bind(), "0.0.0.0:" + std::to_string(relay.upstream.port));  // the other host sends here
    EXPECT_EQ(relay.listen.port, kDefaultMultiHostBasePort + RelayPortOffset(a, b));
  }
}

TEST(LaunchPortPlanTest, ALinkToAServiceOutsideTheRunIsRefused) {
  const v1::Scene scene = testing::ShippedScene("rub_friction");  // no tactile
  EXPECT_THROW(
      AssignPorts(scene, DeriveServices(scene), 40000, nullptr, {Link(P::SERVICE_LOCAL_CONTACT, P::SERVICE_TACTILE)}),
      std::invalid_argument);
}

TEST(LaunchPortPlanTest, HostsDefaultToLocal) {
  const v1::Scene scene = testing::ShippedScene("demo");
  EXPECT_FALSE(IsMultiHost(scene));
  EXPECT_EQ(HostOf(scene, P::SERVICE_TACTILE), "local");
  EXPECT_EQ(HostAddresses(scene).at("local"), "127.0.0.1");
}

}  // namespace
}  // namespace haptex::launch
