// kill -9 of each service in turn during the demo while the mock user pinches the fabric (real
// force on both fingers): the force the mock's fingers get reaches zero after the kill (the
// launcher holds the device at zero force while any service restarts; how fast, 20 ms for the
// models and 5 ms for the controller, is asserted on the simulated clock), the service is
// restarted, and the run ends with exit code 0. The force-carrying services are killed in the demo without
// its tactile pair (tactile, mock_pins: no force, and two more processes on this 2-core machine);
// those two in the whole demo. The mock controller itself (the device) restarts at zero force.
// Time is compared on one clock: the mock's force log is CLOCK_MONOTONIC, as is
// base::SteadyNowNs here.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <signal.h>

#include <chrono>
#include <cmath>
#include <ostream>
#include <regex>
#include <sstream>
#include <thread>
#include <vector>

#include "tests/launch/launch_test_support.h"
#include "tests/support/subprocess.h"

namespace haptex::launch {
namespace {

using namespace std::chrono_literals;

struct KillCase {
  const char* service;
  bool with_tactile;
};

void PrintTo(const KillCase& c, std::ostream* os) { *os << c.service; }

class LaunchForceKillTest : public ::testing::TestWithParam<KillCase> {};

TEST_P(LaunchForceKillTest, ForceReachesZeroAndTheRunRecovers) {
  const std::string name = GetParam().service;
  const std::string dir = testing::FreshDir(std::string("force_kill_") + name);
  const std::string run = dir + "/run";
  haptex::testing::Subprocess launcher(testing::DemoLaunchArgv(run, GetParam().with_tactile));
  const int pid = testing::RunningServicePid(launcher, name);
  ASSERT_GT(pid, 0);
  // Wait until the pinch presses both fingers (the demo pinches from about 2.2 s).
  const std::string log = run + "/mock_grab_forces.csv";
  ASSERT_TRUE(testing::WaitUntilBothFingersPress(log)) << "the demo never pinched\n" << launcher.Stdout();
  const double killed_ns = static_cast<double>(base::SteadyNowNs());
  ASSERT_EQ(kill(pid, SIGKILL), 0);
  testing::WaitForOutput(launcher, name + ": restarted");
  std::this_thread::sleep_for(500ms);
  launcher.Signal(SIGINT);
  const auto code = launcher.WaitFor(90s);
  ASSERT_TRUE(code.has_value()) << launcher.Stdout();
  EXPECT_EQ(*code, 0) << launcher.Stdout();

  if (name == "mock_grab") {
    // the device died with its force; its new instance starts at zero and ramps up
    const auto restarted = testing::MockForceRows(run + "/mock_grab_forces.restart1.csv");
    ASSERT_FALSE(restarted.empty());
    EXPECT_EQ(restarted.front().thumb_N, 0.0);
    EXPECT_EQ(restarted.front().index_N, 0.0);
    EXPECT_THAT(testing::ReadText(run + "/summary.json"),
                ::testing::ContainsRegex("\"service\":\"mock_grab\",\"detail\":\"after signal 9"));
    return;
  }
  // The watchdogs' 20 ms (models) and 5 ms (controller) are asserted where time is simulated
  // (stall_response_test: AStoppedContactService..., AStoppedBridge...); here, whatever the host
  // does: the force reaches zero after the kill.
  const auto rows = testing::MockForceRows(log);
  double zero_after_ms = -1.0;
  for (const testing::ForceRow& r : rows) {
    if (r.t_ns >= killed_ns && r.thumb_N == 0.0 && r.index_N == 0.0) {
      zero_after_ms = (r.t_ns - killed_ns) * 1e-6;
      break;
    }
  }
  std::printf("[force-kill] %s: the mock's fingers at zero force %.2f ms after the kill\n", name.c_str(),
              zero_after_ms);
  ASSERT_GE(zero_after_ms, 0.0) << "force never reached zero after the kill";
  EXPECT_THAT(testing::ReadText(run + "/summary.json"),
              ::testing::ContainsRegex("\"service\":\"" + name + "\",\"detail\":\"after signal 9"));
}

INSTANTIATE_TEST_SUITE_P(DemoServices, LaunchForceKillTest,
                         ::testing::Values(KillCase{"local_contact", false}, KillCase{"global_sim", false},
                                           KillCase{"device_bridge", false}, KillCase{"tactile", true},
                                           KillCase{"mock_pins", true}, KillCase{"mock_grab", false}),
                         [](const auto& param_info) { return std::string(param_info.param.service); });

}  // namespace
}  // namespace haptex::launch
