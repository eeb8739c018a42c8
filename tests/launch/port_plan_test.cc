// Port assignment: scene placements win, then base port + offset, else free ports on one host.
#include "launch/port_plan.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <set>

#include "tests/launch/launch_test_support.h"

namespace haptex::launch {
namespace {

using P = v1::ServicePlacement;
using ::testing::HasSubstr;

TEST(LaunchPortPlanTest, BasePortPlusTableOffsets) {
  const v1::Scene scene = testing::ShippedScene("demo");
  const PortPlan plan = AssignPorts(scene, DeriveServices(scene), 40000, [] { return std::uint16_t{1}; });
  ASSERT_EQ(plan.services.size(), 6u);
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
  EXPECT_EQ(ports.size(), 9u);  // launcher + 6 services + 2 controller sockets
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
  EXPECT_EQ(ports.size(), 9u);
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

TEST(LaunchPortPlanTest, HostsDefaultToLocal) {
  const v1::Scene scene = testing::ShippedScene("demo");
  EXPECT_FALSE(IsMultiHost(scene));
  EXPECT_EQ(HostOf(scene, P::SERVICE_TACTILE), "local");
  EXPECT_EQ(HostAddresses(scene).at("local"), "127.0.0.1");
}

}  // namespace
}  // namespace haptex::launch
