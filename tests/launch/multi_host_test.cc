// Two hosts made of network namespaces joined by a veth pair: `haptex launch --host a` runs the
// mock controller in one, `--host b` the device bridge in the other; each finds the other at the
// scene's addresses. Needs root (ip netns); skipped with a message elsewhere. The namespaces are
// removed even when the test fails.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <utility>

#include "tests/launch/launch_test_support.h"
#include "tests/support/subprocess.h"

namespace haptex::launch {
namespace {

using namespace std::chrono_literals;
using ::testing::ContainsRegex;
using ::testing::HasSubstr;
using ::testing::Not;

std::string IpTool() {
  for (const char* path : {"/usr/sbin/ip", "/sbin/ip", "/usr/bin/ip", "/bin/ip"}) {
    if (access(path, X_OK) == 0) return path;
  }
  return "";
}

// Runs a command to its end; its exit code (or -1) and stderr.
std::pair<int, std::string> Run(const std::vector<std::string>& argv) {
  haptex::testing::Subprocess p(argv);
  const auto code = p.WaitFor(30s);
  return {code.value_or(-1), p.Stderr()};
}

// Two namespaces and a veth pair between them; destroyed with the object.
class TwoHosts {
 public:
  /// The two hosts' addresses on the veth link (a /24).
  TwoHosts(std::string address_a = "192.0.2.1", std::string address_b = "192.0.2.2")
      : ip_(IpTool()), address_a_(std::move(address_a)), address_b_(std::move(address_b)) {
    const std::string id = std::to_string(getpid() % 100000);
    a_ = "hx_a_" + id;
    b_ = "hx_b_" + id;
    veth_a_ = "hxa" + id;
    veth_b_ = "hxb" + id;
  }
  ~TwoHosts() {
    if (ip_.empty()) return;
    Run({ip_, "netns", "del", a_});  // deleting a namespace deletes its end of the veth pair
    Run({ip_, "netns", "del", b_});
  }
  /// Empty on success, else why the hosts could not be made.
  std::string Create() {
    if (geteuid() != 0) return "needs root (ip netns)";
    if (ip_.empty()) return "no `ip` command (iproute2)";
    const std::vector<std::vector<std::string>> steps = {
        {ip_, "netns", "add", a_},
        {ip_, "netns", "add", b_},
        {ip_, "link", "add", veth_a_, "type", "veth", "peer", "name", veth_b_},
        {ip_, "link", "set", veth_a_, "netns", a_},
        {ip_, "link", "set", veth_b_, "netns", b_},
        {ip_, "-n", a_, "addr", "add", address_a_ + "/24", "dev", veth_a_},
        {ip_, "-n", b_, "addr", "add", address_b_ + "/24", "dev", veth_b_},
        {ip_, "-n", a_, "link", "set", veth_a_, "up"},
        {ip_, "-n", b_, "link", "set", veth_b_, "up"},
        {ip_, "-n", a_, "link", "set", "lo", "up"},
        {ip_, "-n", b_, "link", "set", "lo", "up"},
    };
    for (const auto& step : steps) {
      const auto [code, err] = Run(step);
      if (code != 0) return "`" + step[1] + " " + step[2] + " " + step[3] + "` failed: " + err;
    }
    return "";
  }
  std::vector<std::string> In(const std::string& ns, std::vector<std::string> argv) const {
    argv.insert(argv.begin(), {ip_, "netns", "exec", ns});
    return argv;
  }
  const std::string& a() const { return a_; }
  const std::string& b() const { return b_; }

 private:
  std::string ip_, address_a_, address_b_, a_, b_, veth_a_, veth_b_;
};

TEST(LaunchMultiHostTest, MockControllerAndBridgeOnTwoHosts) {
  TwoHosts hosts;
  if (const std::string why = hosts.Create(); !why.empty()) {
    GTEST_SKIP() << "two-host test skipped: " << why;
  }
  const std::string dir = testing::FreshDir("multi_host");
  const std::string scene = dir + "/two_hosts.textproto";
  testing::WriteText(scene, R"(
name: "two_hosts"
fabric { database_name: "wang2011_black_denim_11oz" }
fingers { finger: FINGER_THUMB }
fingers { finger: FINGER_INDEX }
device { mock { user { kind: KIND_RUB } } }
hosts { name: "a" address: "192.0.2.1" }
hosts { name: "b" address: "192.0.2.2" }
services { service: SERVICE_MOCK_GRAB host: "a" }
services { service: SERVICE_DEVICE_BRIDGE host: "b" }
services { service: SERVICE_GLOBAL_SIM host: "b" }
services { service: SERVICE_LOCAL_CONTACT host: "b" }
session_key { hex: "00112233445566778899aabbccddeeff00112233445566778899aabbccddeeff" }
)");
  const std::string haptex = haptex::testing::BuildDir() + "/cli/haptex";
  haptex::testing::Subprocess host_a(
      hosts.In(hosts.a(), {haptex, "launch", scene, "--host", "a", "--duration", "4", "--out", dir + "/run_a"}));
  haptex::testing::Subprocess host_b(
      hosts.In(hosts.b(), {haptex, "launch", scene, "--host", "b", "--skip", "global_sim", "--skip", "local_contact",
                           "--duration", "4", "--out", dir + "/run_b"}));
  const auto code_a = host_a.WaitFor(120s);
  const auto code_b = host_b.WaitFor(120s);
  EXPECT_EQ(code_a, 0) << host_a.Stdout() << host_a.Stderr();
  EXPECT_EQ(code_b, 0) << host_b.Stdout() << host_b.Stderr();
  EXPECT_THAT(host_a.Stdout(), HasSubstr("remote device_bridge (on b)"));
  EXPECT_THAT(host_a.Stdout(), HasSubstr("launcher receiving Health on 192.0.2.1:47600"));

  // each launcher heard its own service; the bridge saw the other host's controller frames, and
  // the controller the bridge's commands
  const std::string a = testing::ReadText(dir + "/run_a/summary.json");
  const std::string b = testing::ReadText(dir + "/run_b/summary.json");
  EXPECT_THAT(a, ContainsRegex(R"("name":"mock_grab",[^}]*"started_here":true[^}]*"health_received":true)"));
  EXPECT_THAT(a, ContainsRegex(R"("commands_accepted":[1-9])"));
  EXPECT_THAT(b, ContainsRegex(R"("name":"device_bridge",[^}]*"started_here":true[^}]*"health_received":true)"));
  EXPECT_THAT(b, ContainsRegex(R"("status_frames_accepted":[1-9])"));
  EXPECT_THAT(b, HasSubstr(R"("status_frames_from_strangers":0)"));
  EXPECT_THAT(b, ContainsRegex(R"("name":"mock_grab","reason":[^}]*"host":"a","address":"192.0.2.1:47606")"));
}

// An impaired link across hosts: the relay runs on the host of the link's first service (the
// bridge's, a), local_contact on b sends to a's relay, and each launcher is given the same
// --impair. The bridge gets local_contact's force models through the relay both ways.
TEST(LaunchMultiHostTest, ARelayedLinkBetweenTwoHosts) {
  TwoHosts hosts;
  if (const std::string why = hosts.Create(); !why.empty()) {
    GTEST_SKIP() << "two-host test skipped: " << why;
  }
  const std::string dir = testing::FreshDir("multi_host_relay");
  const std::string scene = dir + "/two_hosts.textproto";
  testing::WriteText(scene, R"(
name: "two_hosts_relayed"
fabric { database_name: "wang2011_black_denim_11oz" }
cloth { particles_u: 21 particles_v: 21 }
fingers { finger: FINGER_THUMB }
fingers { finger: FINGER_INDEX }
device { mock { user { kind: KIND_RUB } } }
hosts { name: "a" address: "192.0.2.1" }
hosts { name: "b" address: "192.0.2.2" }
services { service: SERVICE_MOCK_GRAB host: "a" }
services { service: SERVICE_DEVICE_BRIDGE host: "a" }
services { service: SERVICE_GLOBAL_SIM host: "b" }
services { service: SERVICE_LOCAL_CONTACT host: "b" }
session_key { hex: "00112233445566778899aabbccddeeff00112233445566778899aabbccddeeff" }
)");
  const std::string haptex = haptex::testing::BuildDir() + "/cli/haptex";
  const std::string impair = "device_bridge-local_contact:delay_ms=5";
  haptex::testing::Subprocess host_a(hosts.In(hosts.a(), {haptex, "launch", scene, "--host", "a", "--duration", "4",
                                                          "--out", dir + "/run_a", "--impair", impair}));
  haptex::testing::Subprocess host_b(hosts.In(hosts.b(), {haptex, "launch", scene, "--host", "b", "--duration", "4",
                                                          "--out", dir + "/run_b", "--impair", impair}));
  const auto code_a = host_a.WaitFor(120s);
  const auto code_b = host_b.WaitFor(120s);
  EXPECT_EQ(code_a, 0) << host_a.Stdout() << host_a.Stderr();
  EXPECT_EQ(code_b, 0) << host_b.Stdout() << host_b.Stderr();
  EXPECT_THAT(host_a.Stdout(), HasSubstr("relay device_bridge-local_contact: started"));
  EXPECT_THAT(host_b.Stdout(), Not(HasSubstr("relay device_bridge-local_contact: started")));
  EXPECT_THAT(host_b.Stdout(), HasSubstr("through a relay on a (192.0.2.1:"));

  const std::string a = testing::ReadText(dir + "/run_a/summary.json");
  const std::string b = testing::ReadText(dir + "/run_b/summary.json");
  EXPECT_THAT(a, ContainsRegex(R"("force_models":[1-9])")) << "the bridge on a got b's force models";
  EXPECT_THAT(a, ContainsRegex(R"("link":"device_bridge-local_contact",.*"started_here":true)"));
  EXPECT_THAT(a, ContainsRegex(R"("achieved":\{"duration_s":[0-9.]+,"forward":\{"received":[1-9][0-9]*,)"));
  EXPECT_THAT(a, ContainsRegex(R"("back":\{"received":[1-9][0-9]*,)"));
  EXPECT_THAT(b, ContainsRegex(R"("link":"device_bridge-local_contact",.*"started_here":false)"));
  EXPECT_THAT(b, HasSubstr("its report is in that host's run folder"));
}

// The shipped scene `name` as its comment tells a user to run it: `--host lab` in one namespace,
// `--host compute` in the other, one key in HAPTEX_SESSION_KEY; both must exit 0 after 6 s.
// Returns the two summary.json texts.
struct Summaries {
  std::string lab, compute;
};
Summaries RunOnLabAndCompute(TwoHosts& hosts, const std::string& name) {
  const std::string dir = testing::FreshDir("multi_host_" + name);
  const std::string scene = testing::ShippedScenePath(name);
  const std::string haptex = haptex::testing::BuildDir() + "/cli/haptex";
  const std::vector<std::string> key{
      "HAPTEX_SESSION_KEY=00112233445566778899aabbccddeeff00112233445566778899aabbccddeeff"};
  haptex::testing::Subprocess lab(
      hosts.In(hosts.a(), {haptex, "launch", scene, "--host", "lab", "--duration", "6", "--out", dir + "/lab"}), key);
  haptex::testing::Subprocess compute(
      hosts.In(hosts.b(), {haptex, "launch", scene, "--host", "compute", "--duration", "6", "--out", dir + "/compute"}),
      key);
  const auto code_lab = lab.WaitFor(150s);
  const auto code_compute = compute.WaitFor(150s);
  EXPECT_EQ(code_lab, 0) << lab.Stdout() << lab.Stderr();
  EXPECT_EQ(code_compute, 0) << compute.Stdout() << compute.Stderr();
  return {testing::ReadText(dir + "/lab/summary.json"), testing::ReadText(dir + "/compute/summary.json")};
}

// The remote scene: the device, its bridge and the mock pin display on "lab", the simulation and
// tactile rendering on "compute". Forces from compute reach the controller on lab; pin frames from
// compute reach the display on lab.
TEST(LaunchMultiHostTest, ShippedRemoteSceneOnLabAndCompute) {
  TwoHosts hosts("192.0.2.10", "192.0.2.20");
  if (const std::string why = hosts.Create(); !why.empty()) {
    GTEST_SKIP() << "two-host test skipped: " << why;
  }
  const Summaries s = RunOnLabAndCompute(hosts, "remote");
  EXPECT_THAT(s.compute,
              ContainsRegex(R"("name":"local_contact",[^}]*"started_here":true[^}]*"health_received":true)"));
  EXPECT_THAT(s.compute, ContainsRegex(R"("name":"tactile",[^}]*"started_here":true[^}]*"health_received":true)"));
  EXPECT_THAT(s.lab, ContainsRegex(R"("force_models":[1-9])")) << "the bridge on lab got compute's force models";
  EXPECT_THAT(s.lab, ContainsRegex(R"("frames_played":[1-9])")) << "the display on lab got compute's pin frames";
  EXPECT_THAT(s.compute, ContainsRegex(R"("patches_sent":[1-9])"));
}

// The other placement (remote_global): only global_sim on "compute"; the bridge, local_contact and
// tactile on "lab". Patches from compute reach local_contact on lab, whose force models drive the
// controller there.
TEST(LaunchMultiHostTest, ShippedRemoteGlobalSceneOnLabAndCompute) {
  TwoHosts hosts("192.0.2.10", "192.0.2.20");
  if (const std::string why = hosts.Create(); !why.empty()) {
    GTEST_SKIP() << "two-host test skipped: " << why;
  }
  const Summaries s = RunOnLabAndCompute(hosts, "remote_global");
  EXPECT_THAT(s.lab, ContainsRegex(R"("name":"local_contact",[^}]*"started_here":true[^}]*"health_received":true)"));
  EXPECT_THAT(s.compute, ContainsRegex(R"("name":"global_sim",[^}]*"started_here":true[^}]*"health_received":true)"));
  EXPECT_THAT(s.lab, ContainsRegex(R"("patches_received":[1-9])")) << "local_contact on lab got compute's patches";
  EXPECT_THAT(s.lab, ContainsRegex(R"("force_models":[1-9])"));
  EXPECT_THAT(s.compute, ContainsRegex(R"("patches_sent":[1-9])"));
}

}  // namespace
}  // namespace haptex::launch
