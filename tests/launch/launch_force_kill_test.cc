// kill -9 during the demo while the mock user pinches the fabric (real force on both fingers):
// the force the mock's fingers get is zero within 20 ms of the kill, the service is restarted,
// and the run ends with exit code 0. The demo runs without tactile (the database's fabrics have no
// weave data yet). Time is compared on one clock: the mock's force log is CLOCK_MONOTONIC, as is
// std::chrono::steady_clock here.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <signal.h>

#include <chrono>
#include <cmath>
#include <regex>
#include <sstream>
#include <thread>

#include "tests/launch/launch_test_support.h"
#include "tests/support/subprocess.h"

namespace haptex::launch {
namespace {

using namespace std::chrono_literals;

std::int64_t MonotonicNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

class LaunchForceKillTest : public ::testing::TestWithParam<const char*> {};

TEST_P(LaunchForceKillTest, ForceIsZeroWithin20msAndTheRunRecovers) {
  const std::string name = GetParam();
  const std::string dir = testing::FreshDir(std::string("force_kill_") + name);
  const std::string run = dir + "/run";
  haptex::testing::Subprocess launcher({haptex::testing::BuildDir() + "/cli/haptex", "launch",
                                        testing::ShippedScenePath("demo"), "--skip", "tactile", "--skip",
                                        "mock_pins", "--duration", "0", "--out", run});
  testing::WaitForOutput(launcher, "running \\(until Ctrl-C\\)");
  const int pid = std::stoi(testing::WaitForOutput(launcher, name + ": started \\(pid ([0-9]+)"));
  // Wait until the pinch presses both fingers (the demo pinches from about 2.2 s).
  const std::string log = run + "/mock_grab_forces.csv";
  bool pressing = false;
  for (auto until = std::chrono::steady_clock::now() + 60s; !pressing && std::chrono::steady_clock::now() < until;) {
    std::this_thread::sleep_for(50ms);
    const auto rows = testing::MockForceRows(log);
    pressing = !rows.empty() && rows.back().thumb_N > 0.5 && rows.back().index_N > 0.5;
  }
  ASSERT_TRUE(pressing) << "the demo never pinched\n" << launcher.Stdout();
  const double killed_ns = static_cast<double>(MonotonicNs());
  ASSERT_EQ(kill(pid, SIGKILL), 0);
  testing::WaitForOutput(launcher, name + ": restarted");
  std::this_thread::sleep_for(500ms);
  launcher.Signal(SIGINT);
  const auto code = launcher.WaitFor(90s);
  ASSERT_TRUE(code.has_value()) << launcher.Stdout();
  EXPECT_EQ(*code, 0) << launcher.Stdout();

  const auto rows = testing::MockForceRows(log);
  double zero_after_ms = -1.0;
  for (const testing::ForceRow& r : rows) {
    if (r.t_ns < killed_ns) continue;
    if (r.thumb_N == 0.0 && r.index_N == 0.0) {
      zero_after_ms = (r.t_ns - killed_ns) * 1e-6;
      break;
    }
  }
  std::printf("[force-kill] %s: the mock's fingers at zero force %.2f ms after the kill\n", name.c_str(), zero_after_ms);
  ASSERT_GE(zero_after_ms, 0.0) << "force never reached zero after the kill";
  EXPECT_LE(zero_after_ms, 20.0);
  EXPECT_THAT(testing::ReadText(run + "/summary.json"),
              ::testing::ContainsRegex("\"service\":\"" + name + "\",\"detail\":\"after signal 9"));
}

INSTANTIATE_TEST_SUITE_P(ForceCarryingServices, LaunchForceKillTest,
                         ::testing::Values("local_contact", "global_sim", "device_bridge"),
                         [](const auto& param_info) { return std::string(param_info.param); });

}  // namespace
}  // namespace haptex::launch
