// Each service's command line: shared options, peers that are in the run, its own flags.
#include "launch/command_line.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>

#include "launch/impair_option.h"
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
                                                    "global_sim=127.0.0.1:40001", "viewer=127.0.0.1:40009"));
  EXPECT_THAT(Peers(mock), ::testing::ElementsAre("launcher=127.0.0.1:40000"));
  EXPECT_EQ(After(bridge, "--record"), "/run/recordings/device_bridge.pb");
  EXPECT_THAT(bridge, Not(Contains("--duration")));  // the launcher stops the services itself
  EXPECT_THAT(bridge, Not(Contains(HasSubstr("SESSION_KEY"))));
}

TEST_F(LaunchCommandLineTest, LocalContactAndTactilePeers) {
  Plan(testing::ShippedScene("demo"));
  EXPECT_THAT(Peers(Argv(P::SERVICE_LOCAL_CONTACT)),
              ::testing::ElementsAre("launcher=127.0.0.1:40000", "global_sim=127.0.0.1:40001", "bridge=127.0.0.1:40003",
                                     "tactile=127.0.0.1:40005", "viewer=127.0.0.1:40009"));
  EXPECT_THAT(Peers(Argv(P::SERVICE_TACTILE)),
              ::testing::ElementsAre("launcher=127.0.0.1:40000", "display=127.0.0.1:40008", "viewer=127.0.0.1:40009"));
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

// A real controller sends its status to the port it is configured with: the scene fixes the
// bridge's controller-side port, which wins over the base port.
TEST_F(LaunchCommandLineTest, TheSceneFixesTheBridgesControllerPort) {
  Plan(testing::SceneFromText(R"(
    name: "real" fabric { database_name: "wang2011_black_denim_11oz" }
    fingers { finger: FINGER_THUMB }
    device { grab { controller_address: "127.0.0.1:7000" } bridge_controller_port: 7002 })"));
  EXPECT_EQ(plan_.Find(P::SERVICE_DEVICE_BRIDGE)->controller->port, 7002);
  EXPECT_EQ(After(Argv(P::SERVICE_DEVICE_BRIDGE), "--controller-bind"), "127.0.0.1:7002");
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

// --impair 'device_bridge-local_contact:...': the bridge sends to the relay's listen socket,
// local_contact to its upstream socket; the relay forwards to each one's real address.
class LaunchRelayCommandLineTest : public LaunchCommandLineTest {
 protected:
  void PlanWith(const v1::Scene& scene, const std::string& impair, std::uint16_t base_port = 40000) {
    scene_ = scene;
    link_ = ParseImpairOption(impair);
    plan_ = AssignPorts(scene_, DeriveServices(scene_), base_port, nullptr, {link_});
  }
  std::vector<std::string> RelayArgv() {
    return RelayCommandLine(plan_.relays.at(0), scene::ResolveLink(link_), plan_,
                            {"/b", "/s/demo.textproto", "/run", "info"}, "/self/haptex");
  }
  v1::LinkImpairment link_;
};

TEST_F(LaunchRelayCommandLineTest, PeersOfAnImpairedLinkPointAtTheRelay) {
  PlanWith(testing::ShippedScene("demo"), "device_bridge-local_contact:rtt_ms=20,loss=0.02,seed=1");
  const int listen = 40000 + RelayPortOffset(P::SERVICE_DEVICE_BRIDGE, P::SERVICE_LOCAL_CONTACT);
  const std::string relay_listen = "127.0.0.1:" + std::to_string(listen);
  const std::string relay_upstream = "127.0.0.1:" + std::to_string(listen + 1);
  EXPECT_THAT(
      Peers(Argv(P::SERVICE_DEVICE_BRIDGE)),
      ::testing::ElementsAre("launcher=127.0.0.1:40000", "local_contact=" + relay_listen, "global_sim=127.0.0.1:40001",
                             "viewer=127.0.0.1:40009"));  // the bridge's other links stay direct
  EXPECT_THAT(Peers(Argv(P::SERVICE_LOCAL_CONTACT)),
              ::testing::ElementsAre("launcher=127.0.0.1:40000", "global_sim=127.0.0.1:40001",
                                     "bridge=" + relay_upstream, "tactile=127.0.0.1:40005", "viewer=127.0.0.1:40009"));
  EXPECT_THAT(Peers(Argv(P::SERVICE_GLOBAL_SIM)), Contains("local_contact=127.0.0.1:40002"));
  EXPECT_EQ(After(Argv(P::SERVICE_DEVICE_BRIDGE), "--controller"), "127.0.0.1:40007");  // GRAB link direct

  const auto relay = RelayArgv();
  EXPECT_EQ(relay[0], "/self/haptex");
  EXPECT_EQ(relay[1], "relay");
  EXPECT_EQ(After(relay, "--listen"), relay_listen);
  EXPECT_EQ(After(relay, "--upstream-bind"), relay_upstream);
  EXPECT_EQ(After(relay, "--to"), "127.0.0.1:40002");       // local_contact's real address
  EXPECT_EQ(After(relay, "--back-to"), "127.0.0.1:40003");  // the bridge's
  EXPECT_EQ(After(relay, "--delay-ms"), "10");              // rtt_ms split evenly
  EXPECT_EQ(After(relay, "--loss"), "0.02");
  EXPECT_EQ(After(relay, "--seed"), "1,2");
  EXPECT_EQ(After(relay, "--json"), "/run/network/device_bridge-local_contact.json");
  // what the relay's defaults already say is left out
  for (const char* flag : {"--jitter-ms", "--jitter-dist", "--reorder", "--duplicate", "--rate-kbps", "--burst-loss",
                           "--outage-after-s", "--outage-s"}) {
    EXPECT_THAT(relay, Not(Contains(flag))) << flag;
  }
}

TEST_F(LaunchRelayCommandLineTest, EachDirectionGetsItsOwnValuesExactly) {
  PlanWith(testing::ShippedScene("demo"),
           "local_contact-device_bridge:delay_ms=0.1234567891234,jitter_ms=2,jitter_distribution=normal,"
           "burst_loss=0.01/0.5,reorder=0.05,reorder_delay_ms=3,duplicate=0.001,rate_kbps=800,seed=9,"
           "outage_after_s=4.5,outage_s=1,back.outage_s=2,"
           "forward.loss=0.1,back.burst_loss=0.02/0.25/0.9/0.01,back.seed=4");
  const auto relay = RelayArgv();
  EXPECT_EQ(After(relay, "--to"), "127.0.0.1:40003");       // forward is local_contact -> bridge here
  EXPECT_EQ(After(relay, "--back-to"), "127.0.0.1:40002");  // local_contact's real address
  EXPECT_EQ(After(relay, "--delay-ms"), "0.1234567891234");
  EXPECT_EQ(After(relay, "--jitter-ms"), "2");
  EXPECT_EQ(After(relay, "--jitter-dist"), "normal");
  EXPECT_EQ(After(relay, "--loss"), "0.1,0");
  EXPECT_EQ(After(relay, "--burst-loss-forward"), "0.01,0.5,1,0");
  EXPECT_EQ(After(relay, "--burst-loss-back"), "0.02,0.25,0.9,0.01");
  EXPECT_EQ(After(relay, "--reorder"), "0.05");
  EXPECT_EQ(After(relay, "--reorder-delay-ms"), "3");
  EXPECT_EQ(After(relay, "--duplicate"), "0.001");
  EXPECT_EQ(After(relay, "--rate-kbps"), "800");
  EXPECT_EQ(After(relay, "--outage-after-s"), "4.5");
  EXPECT_EQ(After(relay, "--outage-s"), "1,2");
  EXPECT_EQ(After(relay, "--seed"), "9,4");
  // the relay's peers: the bridge sends to the upstream socket now
  const int listen = 40000 + RelayPortOffset(P::SERVICE_DEVICE_BRIDGE, P::SERVICE_LOCAL_CONTACT);
  EXPECT_THAT(Peers(Argv(P::SERVICE_LOCAL_CONTACT)), Contains("bridge=127.0.0.1:" + std::to_string(listen)));
  EXPECT_THAT(Peers(Argv(P::SERVICE_DEVICE_BRIDGE)), Contains("local_contact=127.0.0.1:" + std::to_string(listen + 1)));
}

TEST_F(LaunchRelayCommandLineTest, TheGrabLinkIsRelayedOnTheControllerSockets) {
  PlanWith(testing::ShippedScene("demo"), "device_bridge-mock_grab:delay_ms=1");
  const int listen = 40000 + RelayPortOffset(P::SERVICE_DEVICE_BRIDGE, P::SERVICE_MOCK_GRAB);
  EXPECT_EQ(After(Argv(P::SERVICE_DEVICE_BRIDGE), "--controller"), "127.0.0.1:" + std::to_string(listen));
  EXPECT_EQ(After(Argv(P::SERVICE_MOCK_GRAB), "--bridge"), "127.0.0.1:" + std::to_string(listen + 1));
  EXPECT_EQ(After(Argv(P::SERVICE_DEVICE_BRIDGE), "--controller-bind"), "127.0.0.1:40004");  // binds stay
  const auto relay = RelayArgv();
  EXPECT_EQ(After(relay, "--to"), "127.0.0.1:40007");       // the mock's GRAB socket
  EXPECT_EQ(After(relay, "--back-to"), "127.0.0.1:40004");  // the bridge's GRAB socket
  EXPECT_THAT(Peers(Argv(P::SERVICE_DEVICE_BRIDGE)), Contains("local_contact=127.0.0.1:40002"));
}

TEST_F(LaunchRelayCommandLineTest, AcrossHostsTheRelayIsReachedAtItsHostsAddress) {
  PlanWith(testing::ShippedScene("remote"), "device_bridge-local_contact:rtt_ms=40", 47600);
  const int listen = 47600 + RelayPortOffset(P::SERVICE_DEVICE_BRIDGE, P::SERVICE_LOCAL_CONTACT);
  // the relay on lab (the bridge's host); local_contact on compute sends to lab's address
  EXPECT_THAT(Peers(Argv(P::SERVICE_DEVICE_BRIDGE)), Contains("local_contact=192.0.2.10:" + std::to_string(listen)));
  EXPECT_THAT(Peers(Argv(P::SERVICE_LOCAL_CONTACT)), Contains("bridge=192.0.2.10:" + std::to_string(listen + 1)));
  const auto relay = RelayArgv();
  EXPECT_EQ(After(relay, "--listen"), "0.0.0.0:" + std::to_string(listen));
  EXPECT_EQ(After(relay, "--upstream-bind"), "0.0.0.0:" + std::to_string(listen + 1));
  EXPECT_EQ(After(relay, "--to"), "192.0.2.20:47602");
  EXPECT_EQ(After(relay, "--back-to"), "192.0.2.10:47603");
}

TEST(LaunchJoinCommandLineTest, QuotesSpaces) { EXPECT_EQ(JoinCommandLine({"a", "b c", ""}), "a 'b c' ''"); }

}  // namespace
}  // namespace haptex::launch
