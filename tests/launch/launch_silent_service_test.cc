// A service that goes silent without dying (SIGSTOP: the process exists, its sockets stay open, it
// sends nothing) during the demo's pinch. The launcher notices the missing Health after
// silent_after_s (3 s), kills and restarts it, and the run ends with exit code 0. Meanwhile the
// device is safe: a silent local_contact leaves the bridge without ForceModels (its stale-model
// watchdog ramps to zero); a silent bridge leaves the mock controller without commands (its own
// host watchdog zeroes the force). A silent global_sim is the case the dual layer is built for:
// local_contact keeps rendering from the patch it has, so force continues, bounded.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <signal.h>

#include <chrono>
#include <cmath>
#include <ostream>
#include <thread>

#include "tests/launch/launch_test_support.h"
#include "tests/support/subprocess.h"

namespace haptex::launch {
namespace {

using namespace std::chrono_literals;

struct SilentCase {
  const char* service;
  bool force_must_stop;  // the device path depends on this service at haptic rate
};

void PrintTo(const SilentCase& c, std::ostream* os) { *os << c.service; }

class LaunchSilentServiceTest : public ::testing::TestWithParam<SilentCase> {};

TEST_P(LaunchSilentServiceTest, SilentServiceIsRestartedAndTheDeviceStaysSafe) {
  const SilentCase c = GetParam();
  const std::string name = c.service;
  const std::string dir = testing::FreshDir(std::string("silent_") + name);
  const std::string run = dir + "/run";
  haptex::testing::Subprocess launcher(testing::DemoLaunchArgv(run, false));
  const int pid = testing::RunningServicePid(launcher, name);
  ASSERT_GT(pid, 0);
  const std::string log = run + "/mock_grab_forces.csv";
  ASSERT_TRUE(testing::WaitUntilBothFingersPress(log)) << "the demo never pinched\n" << launcher.Stdout();

  const double stopped_ns = static_cast<double>(base::SteadyNowNs());
  ASSERT_EQ(kill(pid, SIGSTOP), 0);
  // The launcher must find it silent by itself (no exit status to see: the process lives on).
  testing::WaitForOutput(launcher, name + ": restarted", 60s);
  const double restarted_seen_ns = static_cast<double>(base::SteadyNowNs());
  std::this_thread::sleep_for(500ms);
  launcher.Signal(SIGINT);
  const auto code = launcher.WaitFor(90s);
  ASSERT_TRUE(code.has_value()) << launcher.Stdout();
  EXPECT_EQ(*code, 0) << launcher.Stdout();
  // Not before the silence threshold less one Health period (5 Hz): the last Health before the
  // stop starts the 3 s, so the restart was for silence, not something else.
  EXPECT_GE((restarted_seen_ns - stopped_ns) * 1e-9, 3.0 - 0.2 - 0.05);

  // The watchdogs' 20 ms and 5 ms are asserted where time is simulated (stall_response_test);
  // here, whatever the host does: the force reaches zero while the service is silent and stays
  // there until it is restarted.
  const auto rows = testing::MockForceRows(log);
  double zero_after_ms = -1.0, peak_while_silent_N = 0.0;
  int nonzero_after_zero = 0;
  for (const testing::ForceRow& r : rows) {
    if (r.t_ns < stopped_ns || r.t_ns > restarted_seen_ns - 1e9) continue;  // the restart is under way by then
    peak_while_silent_N = std::max({peak_while_silent_N, r.thumb_N, r.index_N});
    const bool zero = r.thumb_N == 0.0 && r.index_N == 0.0;
    if (zero_after_ms < 0.0 && zero) zero_after_ms = (r.t_ns - stopped_ns) * 1e-6;
    if (zero_after_ms >= 0.0 && !zero) ++nonzero_after_zero;
  }
  std::printf("[silent] %s: zero force %.2f ms after SIGSTOP, peak while silent %.2f N, restart seen %.2f s after\n",
              name.c_str(), zero_after_ms, peak_while_silent_N, (restarted_seen_ns - stopped_ns) * 1e-9);
  EXPECT_LE(peak_while_silent_N, 20.0) << "the bridge's peak clamp";
  if (c.force_must_stop) {
    ASSERT_GE(zero_after_ms, 0.0) << "force never reached zero while " << name << " was silent";
    EXPECT_EQ(nonzero_after_zero, 0) << "the force came back while " << name << " was silent";
  }
  EXPECT_THAT(testing::ReadText(run + "/summary.json"),
              ::testing::ContainsRegex("\"service\":\"" + name + "\",\"detail\":\"after silent for 3.0 s"));
}

INSTANTIATE_TEST_SUITE_P(DemoServices, LaunchSilentServiceTest,
                         ::testing::Values(SilentCase{"local_contact", true}, SilentCase{"device_bridge", true},
                                           SilentCase{"global_sim", false}),
                         [](const auto& param_info) { return std::string(param_info.param.service); });

}  // namespace
}  // namespace haptex::launch
