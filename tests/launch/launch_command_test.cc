// `haptex launch` refusing what it cannot run, with messages that say where and how to fix it
// (no service is started here), and `--dry-run` showing the plan.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <regex>

#include "tests/launch/launch_test_support.h"
#include "tests/support/subprocess.h"

namespace haptex::launch {
namespace {

using ::testing::HasSubstr;

using Result = haptex::testing::Finished;

Result Haptex(std::vector<std::string> args) {
  args.insert(args.begin(), haptex::testing::BuildDir() + "/cli/haptex");
  return haptex::testing::RunToEnd(std::move(args));
}

TEST(LaunchCommandTest, SyntaxErrorsAtFileLineColumn) {
  const std::string path = testing::FreshDir("launch_syntax") + "/bad.textproto";
  testing::WriteText(
      path,
      "name: \"bad\"\nfabric { database_name: \"wang2011_black_denim_11oz\" }\nfingers { finger: FINGER_PINKY }\n");
  const Result r = Haptex({"launch", path});
  EXPECT_EQ(r.code, 2);
  EXPECT_THAT(r.err, HasSubstr(path + ":3:"));
  EXPECT_THAT(r.err, HasSubstr("FINGER_PINKY"));
}

TEST(LaunchCommandTest, SemanticErrorsSayTheFix) {
  const std::string path = testing::FreshDir("launch_semantic") + "/bad.textproto";
  testing::WriteText(path,
                     "name: \"bad\"\nfabric { database_name: \"wang2011_black_denim_11oz\" }\n"
                     "fingers { finger: FINGER_INDEX }\n"
                     "tactile { enabled: true }\n");
  const Result r = Haptex({"launch", path});
  EXPECT_EQ(r.code, 2);
  EXPECT_THAT(r.err, HasSubstr(path + ":3:1: a scene with fingers needs a device: `device { mock {} }`"));
  EXPECT_THAT(r.err, HasSubstr(path + ":4:"));
  EXPECT_THAT(r.err, HasSubstr("mock_display: true"));
}

TEST(LaunchCommandTest, MissingExecutablesAreNamedWithTheReasonAndTheWayOut) {
  const std::string empty_build = testing::FreshDir("launch_no_build");
  const Result r = Haptex({"launch", testing::ShippedScenePath("demo"), "--build-dir", empty_build});
  EXPECT_EQ(r.code, 2);
  EXPECT_THAT(r.err, HasSubstr("haptex-global-sim is not built (services/global_sim;"));
  EXPECT_THAT(r.err, HasSubstr("haptex-local-contact is not built"));
  EXPECT_THAT(r.err, HasSubstr("two fingers (thumb and index)"));
  EXPECT_THAT(r.err, HasSubstr("--skip global_sim"));
  EXPECT_THAT(r.err, HasSubstr("haptex-device-bridge is not built"));
}

TEST(LaunchCommandTest, DryRunPrintsWhatStartsAndWhy) {
  const Result r = Haptex({"launch", testing::ShippedScenePath("hanging"), "--dry-run", "--base-port", "41000"});
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("start  global_sim: the fabric, with no fingers: global_sim alone"));
  EXPECT_THAT(r.out, HasSubstr("not    local_contact: no fingers: no contact models"));
  EXPECT_THAT(r.out, HasSubstr("not    tactile: tactile display off"));
  EXPECT_THAT(r.out, HasSubstr("global_sim (local): "));
  EXPECT_THAT(r.out, HasSubstr("--bind 127.0.0.1:41001 --peer launcher=127.0.0.1:41000"));
}

TEST(LaunchCommandTest, TheViewerOnDemandIsStartedAndEveryServiceShownToIt) {
  const Result without = Haptex({"launch", testing::ShippedScenePath("hanging"), "--dry-run", "--base-port", "41000"});
  EXPECT_THAT(without.out, HasSubstr("not    viewer: viewer off"));
  EXPECT_THAT(without.out, Not(HasSubstr("viewer=")));
  const Result r = Haptex({"launch", testing::ShippedScenePath("hanging"), "--dry-run", "--base-port", "41000",
                           "--viewer", "--viewer-port", "0"});
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("start  viewer: viewer on"));
  EXPECT_THAT(r.out, HasSubstr("--peer viewer=127.0.0.1:41009"));  // global_sim sends it the cloth
  EXPECT_THAT(r.out, HasSubstr("viewer (local): "));
  EXPECT_THAT(r.out, HasSubstr("--http-port "));
}

TEST(LaunchCommandTest, HostsAndSkipsAreChecked) {
  const std::string remote = testing::ShippedScenePath("remote");
  Result r = Haptex({"launch", remote});
  EXPECT_EQ(r.code, 2);
  EXPECT_THAT(r.err, HasSubstr("run `haptex launch SCENE --host NAME` on each"));
  r = Haptex({"launch", remote, "--host", "moon"});
  EXPECT_EQ(r.code, 2);
  EXPECT_THAT(r.err, HasSubstr("--host moon: the scene has no such host (hosts: compute, lab, local)"));
  r = Haptex({"launch", remote, "--host", "lab", "--dry-run"});
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("remote local_contact (on compute)"));
  EXPECT_THAT(r.out, HasSubstr("start  mock_grab"));
  EXPECT_THAT(r.out, HasSubstr("launcher@lab on 192.0.2.10:47600"));
  r = Haptex({"launch", testing::ShippedScenePath("hanging"), "--skip", "tactile"});
  EXPECT_EQ(r.code, 2);
  EXPECT_THAT(r.err, HasSubstr("--skip tactile: the scene does not need a service of that name"));
}

TEST(LaunchCommandTest, ImpairShowsItsRelayAndTheRewiredPeers) {
  const Result r = Haptex({"launch", testing::ShippedScenePath("pinch_stretch"), "--dry-run", "--base-port", "41000",
                           "--impair", "device_bridge-local_contact:rtt_ms=20,loss=0.02,seed=1"});
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("impair device_bridge-local_contact (--impair): rtt_ms=20,loss=0.02,seed=1; through a "
                               "relay on local (127.0.0.1:41024, 127.0.0.1:41025)"));
  EXPECT_THAT(r.out, HasSubstr("relay device_bridge-local_contact (local): "));
  EXPECT_THAT(r.out, HasSubstr(" relay --listen 127.0.0.1:41024 --to 127.0.0.1:41002 --upstream-bind 127.0.0.1:41025 "
                               "--back-to 127.0.0.1:41003 --delay-ms 10 --loss 0.02 --seed 1,2 --json "));
  EXPECT_THAT(r.out, HasSubstr("--peer local_contact=127.0.0.1:41024 --peer global_sim=127.0.0.1:41001"));
  EXPECT_THAT(r.out, HasSubstr("--peer bridge=127.0.0.1:41025"));
}

TEST(LaunchCommandTest, BadImpairmentsAreRefusedWithExitCodeTwo) {
  const std::string scene = testing::ShippedScenePath("pinch_stretch");
  for (const auto& [impair, says] : std::vector<std::pair<std::string, std::string>>{
           {"device_bridge-local_contact:loss=nan", "loss must be a finite number, got nan"},
           {"device_bridge-local_contact:jitter=5", "unknown key 'jitter'"},
           {"device_bridge-pins", "unknown service 'pins'"},
           {"local_contact-tactile", "the scene does not run tactile"},
           {"global_sim-mock_grab", "global_sim and mock_grab exchange no datagrams"}}) {
    const Result r = Haptex({"launch", scene, "--dry-run", "--impair", impair});
    EXPECT_EQ(r.code, 2) << impair;
    EXPECT_THAT(r.err, HasSubstr("--impair '" + impair + "': " + says));
  }
}

TEST(LaunchCommandTest, SceneNetworkErrorsAtFileLineColumn) {
  const std::string path = testing::FreshDir("launch_network") + "/bad.textproto";
  testing::WriteText(path,
                     "name: \"bad\"\nfabric { database_name: \"wang2011_black_denim_11oz\" }\n"
                     "fingers { finger: FINGER_INDEX }\ndevice { mock {} }\n"
                     "network { links { a: SERVICE_DEVICE_BRIDGE b: SERVICE_LOCAL_CONTACT\n"
                     "  rtt_ms: inf } }\n");
  for (const char* command : {"launch", "scene"}) {
    const Result r = std::string(command) == "launch" ? Haptex({"launch", path}) : Haptex({"scene", "check", path});
    EXPECT_EQ(r.code, 2) << command;
    EXPECT_THAT(r.err, HasSubstr(path + ":6:3: network.links[0].rtt_ms must be a finite number, got inf")) << command;
  }
}

TEST(LaunchCommandTest, DryRunPrintsThePlannedStalls) {
  const std::string path = testing::FreshDir("launch_stall_plan") + "/stalls.textproto";
  testing::WriteText(path, testing::ReadText(testing::ShippedScenePath("pinch_stretch")) +
                               "\nstalls { service: SERVICE_GLOBAL_SIM at_s: 0.5 duration_s: 0.2 }\n");
  const Result r = Haptex({"launch", path, "--dry-run", "--duration", "3", "--skip", "mock_grab", "--stall",
                           "local_contact@1.5s:100ms", "--stall", "all@2s:30ms", "--stall", "device_bridge@5s:1ms"});
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("stall global_sim@0.5s:0.2s (scene): SIGSTOP to global_sim 0.5 s after the run starts, "
                               "SIGCONT 0.2 s later\n"));
  EXPECT_THAT(r.out, HasSubstr("stall local_contact@1.5s:100ms (--stall): SIGSTOP to local_contact 1.5 s after the "
                               "run starts, SIGCONT 0.1 s later\n"));
  // all: what this launcher starts, but the viewer (mock_grab is --skip'ped)
  EXPECT_THAT(r.out, HasSubstr("stall all@2s:30ms (--stall): SIGSTOP to every service started here but the viewer "
                               "(device_bridge, global_sim, local_contact) 2 s after the run starts"));
  EXPECT_THAT(r.out, HasSubstr("stall device_bridge@5s:1ms (--stall): SIGSTOP to device_bridge 5 s after the run "
                               "starts, SIGCONT 0.001 s later; after the run's end (3 s): it will not happen"));
}

TEST(LaunchCommandTest, BadStallsAreRefusedWithExitCodeTwo) {
  const std::string scene = testing::ShippedScenePath("pinch_stretch");
  for (const auto& [stall, says] : std::vector<std::pair<std::string, std::string>>{
           {"local_contact@4.5s", "expected TARGET@AT:DURATION"},
           {"contact@4.5s:30ms", "unknown service 'contact'"},
           {"local_contact@4.5:30ms", "AT '4.5' needs its unit, s or ms"},
           {"local_contact@infs:30ms", "at_s must be a finite number, got inf"},
           {"all@1s:20s", "duration_s must be in (0, 10] s, got 20"},
           {"tactile@1s:30ms", "the scene does not run tactile (tactile display off)"}}) {
    const Result r = Haptex({"launch", scene, "--dry-run", "--stall", stall});
    EXPECT_EQ(r.code, 2) << stall;
    EXPECT_THAT(r.err, HasSubstr("--stall '" + stall + "': " + says));
  }
  Result r = Haptex({"launch", scene, "--dry-run", "--stall", "local_contact@1s:1s", "--stall", "all@1.5s:30ms"});
  EXPECT_EQ(r.code, 2);
  EXPECT_THAT(r.err, HasSubstr("--stall 'all@1.5s:30ms': overlaps --stall 'local_contact@1s:1s'"));
  r = Haptex({"launch", scene, "--dry-run", "--skip", "local_contact", "--stall", "local_contact@1s:1s"});
  EXPECT_EQ(r.code, 2);
  EXPECT_THAT(r.err, HasSubstr("--stall 'local_contact@1s:1s': local_contact is --skip'ped"));
}

TEST(LaunchCommandTest, SceneStallErrorsAtFileLineColumn) {
  const std::string path = testing::FreshDir("launch_stall_scene") + "/bad.textproto";
  testing::WriteText(path,
                     "name: \"bad\"\nfabric { database_name: \"wang2011_black_denim_11oz\" }\n"
                     "fingers { finger: FINGER_INDEX }\ndevice { mock {} }\n"
                     "stalls { service: SERVICE_LOCAL_CONTACT at_s: 1\n"
                     "  duration_s: 11 }\n");
  for (const char* command : {"launch", "scene"}) {
    const Result r = std::string(command) == "launch" ? Haptex({"launch", path}) : Haptex({"scene", "check", path});
    EXPECT_EQ(r.code, 2) << command;
    EXPECT_THAT(r.err, HasSubstr(path + ":6:3: duration_s must be in (0, 10] s, got 11")) << command;
  }
}

TEST(LaunchCommandTest, ASceneNameThatClimbsStillGetsAFolderInsideRuns) {
  const std::string path = testing::FreshDir("launch_climb") + "/climb.textproto";
  std::string scene = testing::ReadText(testing::ShippedScenePath("hanging"));
  scene.replace(scene.find("name: \"hanging\""), 16, "name: \"../../x\"");
  testing::WriteText(path, scene);
  const Result r = Haptex({"launch", path, "--dry-run", "--base-port", "41000"});
  EXPECT_EQ(r.code, 0) << r.err;
  std::smatch record;
  ASSERT_TRUE(std::regex_search(r.out, record, std::regex("--record (\\S+)/recordings/"))) << r.out;
  const std::filesystem::path run_dir = record[1].str();
  EXPECT_EQ(run_dir.parent_path().filename(), "runs");
  EXPECT_EQ(run_dir.filename().string().rfind("_._.._x-", 0), 0u) << run_dir;
}

TEST(LaunchCommandTest, TraceExportNeedsARunFolder) {
  const Result r = Haptex({"trace", "export", "/no/such/run", "--csv"});
  EXPECT_EQ(r.code, 2);
  EXPECT_THAT(r.err, HasSubstr("no run folder /no/such/run"));
}

}  // namespace
}  // namespace haptex::launch
