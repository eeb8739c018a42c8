// Each service's command line: shared options, peers that are in the run, its own flags.
#include "launch/command_line.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>

#include "tests/launch/launch_test_support.h"

namespace haptex::launch {
namespace {

using P = v1::ServicePlacement;
using ::testing::Contains;
using ::testing::HasSubstr;
using ::testing::Not;

class LaunchCommandLineTest : public ::testing::Test {
 protected:
  void Plan(const v1::Scene& scene) {
    scene_ = scene;
    plan_ = AssignPorts(scene_, DeriveServices(scene_), 40000, nullptr);
  }
  std::vector<std::string> Argv(ServiceKind kind) {
    return CommandLine(*plan_.Find(kind), plan_, scene_, {"/b", "/s/demo.textproto", "/run", "info"});
  }
  // the value after `flag` (the first one), or "" when absent
  static std::string After(const std::vector<std::string>& argv, const std::string& flag, int nth = 0) {
    for (std::size_t i = 0; i + 1 < argv.size(); ++i) {
      if (argv[i] == flag && nth-- == 0) return argv[i + 1];
    }
    return "";
  }
  static std::vector<std::string> Peers(const std::vector<std::string>& argv) {
    std::vector<std::string> peers;
    for (std::size_t i = 0; i + 1 < argv.size(); ++i) {
      if (argv[i] == "--peer") peers.push_back(argv[i + 1]);
    }
    return peers;
  }
  v1::Scene scene_;
  PortPlan plan_;
};

TEST_F(LaunchCommandLineTest, BridgeAndMockPointAtEachOther) {
  Plan(testing::ShippedScene("demo"));
  const auto bridge = Argv(P::SERVICE_DEVICE_BRIDGE);
  const auto mock = Argv(P::SERVICE_MOCK_GRAB);
  EXPECT_EQ(bridge[0], "/b/services/device_bridge/haptex-device-bridge");
  EXPECT_EQ(After(bridge, "--scene"), "/s/demo.textproto");
  EXPECT_EQ(After(bridge, "--bind"), "127.0.0.1:40003");
  EXPECT_EQ(After(bridge, "--controller-bind"), "127.0.0.1:40004");
  EXPECT_EQ(After(bridge, "--controller"), "127.0.0.1:40007");
  EXPECT_EQ(After(mock, "--controller-bind"), "127.0.0.1:40007");
  EXPECT_EQ(After(mock, "--bridge"), "127.0.0.1:40004");
  EXPECT_EQ(After(mock, "--force-log"), "/run/mock_grab_forces.csv");
  EXPECT_EQ(After(mock, "--seed"), "1");
  EXPECT_EQ(After(bridge, "--rate"), "5000");
  EXPECT_THAT(Peers(bridge), ::testing::ElementsAre("launcher=127.0.0.1:40000", "local_contact=127.0.0.1:40002",
                                                    "global_sim=127.0.0.1:40001"));
  EXPECT_THAT(Peers(mock), ::testing::ElementsAre("launcher=127.0.0.1:40000"));
  EXPECT_EQ(After(bridge, "--record"), "/run/recordings/device_bridge.pb");
  EXPECT_THAT(bridge, Not(Contains("--duration")));  // the launcher stops the services itself
  EXPECT_THAT(bridge, Not(Contains(HasSubstr("SESSION_KEY"))));
}

TEST_F(LaunchCommandLineTest, LocalContactAndTactilePeers) {
  Plan(testing::ShippedScene("demo"));
  EXPECT_THAT(Peers(Argv(P::SERVICE_LOCAL_CONTACT)),
              ::testing::ElementsAre("launcher=127.0.0.1:40000", "global_sim=127.0.0.1:40001", "bridge=127.0.0.1:40003",
                                     "tactile=127.0.0.1:40005"));
  EXPECT_THAT(Peers(Argv(P::SERVICE_TACTILE)),
              ::testing::ElementsAre("launcher=127.0.0.1:40000", "display=127.0.0.1:40008"));
  EXPECT_EQ(After(Argv(P::SERVICE_MOCK_PINS), "--log-csv"), "/run/pins.csv");
}

TEST_F(LaunchCommandLineTest, PeersNotInTheRunAreLeftOut) {
  Plan(testing::ShippedScene("rub_friction"));  // no tactile
  EXPECT_THAT(Peers(Argv(P::SERVICE_LOCAL_CONTACT)), Not(Contains(HasSubstr("tactile="))));
}

TEST_F(LaunchCommandLineTest, RealDevicesAreAddressedFromTheScene) {
  Plan(testing::SceneFromText(R"(
    name: "real" fabric { database_name: "wang2011_black_denim_11oz" }
    fingers { finger: FINGER_THUMB } device { grab { controller_address: "127.0.0.1:7000" } }
    tactile { enabled: true display_address: "127.0.0.1:7001" }
    rates { health_hz: 10 } recording { enabled: false })"));
  const auto bridge = Argv(P::SERVICE_DEVICE_BRIDGE);
  EXPECT_EQ(After(bridge, "--controller"), "127.0.0.1:7000");
  EXPECT_EQ(After(bridge, "--health-hz"), "10");
  EXPECT_THAT(bridge, Not(Contains("--record")));
  EXPECT_THAT(Peers(Argv(P::SERVICE_TACTILE)), Contains("display=127.0.0.1:7001"));
}

TEST_F(LaunchCommandLineTest, RemoteHostsGetTheirOwnLauncherAndWildcardBinds) {
  scene_ = testing::ShippedScene("remote");
  plan_ = AssignPorts(scene_, DeriveServices(scene_), 47600, nullptr);
  const auto mock = Argv(P::SERVICE_MOCK_GRAB);   // on lab
  const auto tactile = Argv(P::SERVICE_TACTILE);  // on compute
  EXPECT_EQ(After(mock, "--bind"), "0.0.0.0:47606");
  EXPECT_EQ(After(mock, "--bridge"), "192.0.2.10:47604");
  EXPECT_THAT(Peers(mock), Contains("launcher=192.0.2.10:47600"));
  EXPECT_THAT(Peers(tactile), Contains("launcher=192.0.2.20:47600"));
  EXPECT_THAT(Peers(tactile), Contains("display=192.0.2.10:47608"));  // the pins are at the lab
}

TEST(LaunchJoinCommandLineTest, QuotesSpaces) { EXPECT_EQ(JoinCommandLine({"a", "b c", ""}), "a 'b c' ''"); }

}  // namespace
}  // namespace haptex::launch
