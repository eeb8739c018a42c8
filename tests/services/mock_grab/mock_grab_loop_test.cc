// MockGrabLoop in process: CommandFrames in, StatusFrames out, and what the fingers felt in the
// force log, read back by the one force-log reader; and no allocation in its warmed-up tick.

#include "services/mock_grab/mock_grab_loop.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <memory>

#include "launch/force_log_reader.h"
#include "libs/device/grab_protocol.h"
#include "tests/support/allocation_counter.h"
#include "tests/support/captured_outbox.h"

namespace haptex::mock_grab {
namespace {

constexpr double kDt = 0.0002;

std::array<std::byte, device::kCommandFrameSize> Command(std::uint32_t sequence, float thumb_z_N) {
  device::CommandFrame frame;
  frame.sequence = sequence;
  frame.manipulators[0].force_D_N = {0.0f, 0.0f, thumb_z_N};
  frame.manipulators[0].flags = device::command_flags::kForceEnable;
  std::array<std::byte, device::kCommandFrameSize> bytes{};
  device::EncodeCommandFrame(frame, bytes);
  return bytes;
}

TEST(MockGrabLoopTest, CommandsMoveTheFingersAndTheForceLogRecordsThem) {
  const std::string path = ::testing::TempDir() + "/mock_grab_loop_" + std::to_string(getpid()) + ".csv";
  runtime::HealthReporter health("mock_grab");
  haptex::testing::CapturedOutbox out;
  constexpr std::int64_t kOrigin = 1'000'000'000;
  {
    ForceLog log(path);
    MockGrabLoop loop(device::MockControllerConfig{}, device::ScriptParams{}, &log, kOrigin, &health);
    for (int k = 0; k < 100; ++k) {
      const double t = k * kDt;
      const auto command = Command(static_cast<std::uint32_t>(k + 1), k < 50 ? 0.0f : 1.5f);
      loop.ReadHost(command, t, true);
      loop.Update(t, kDt);
      loop.Write(out);
      device::StatusFrame status;
      ASSERT_EQ(device::DecodeStatusFrame(loop.status(), device::GrabValueLimits{}, &status),
                device::FrameError::kNone);
      EXPECT_EQ(status.echo_host_sequence, static_cast<std::uint32_t>(k + 1));
    }
    EXPECT_EQ(loop.controller().frame_counters().accepted(), 100u);
    // garbage from the host is refused and counted
    const std::array<std::byte, 7> garbage{};
    loop.ReadHost(garbage, 0.02, true);
    EXPECT_EQ(loop.controller().frame_counters().TotalRejected(), 1u);
  }  // the log drains and closes
  const auto rows = launch::ReadForceLogRows(path);
  ASSERT_EQ(rows.size(), 100u);
  EXPECT_EQ(rows[0].time_ns, kOrigin);
  EXPECT_EQ(rows[99].time_ns, kOrigin + 99 * 200'000);
  EXPECT_EQ(rows[10].commanded_D_N[0][2], 0.0);
  EXPECT_FLOAT_EQ(static_cast<float>(rows[99].commanded_D_N[0][2]), 1.5f);
  EXPECT_EQ(rows[99].host_sequence, 100u);
  EXPECT_FALSE(rows[99].host_timed_out);
  std::remove(path.c_str());
}

std::uint64_t Counter(runtime::HealthReporter& health, const std::string& name) {
  for (const auto& c : health.Build(0.0).counters()) {
    if (c.name() == name) return c.value();
  }
  ADD_FAILURE() << "no counter " << name;
  return 0;
}

// A real controller is configured with its host: a CommandFrame from anywhere else, however valid
// and however new its sequence, changes nothing and is counted.
TEST(MockGrabLoopTest, CommandsFromStrangersChangeNothingAndAreCounted) {
  runtime::HealthReporter health("mock_grab");
  haptex::testing::CapturedOutbox out;
  MockGrabLoop loop(device::MockControllerConfig{}, device::ScriptParams{}, nullptr, 0, &health);
  std::uint32_t host_sequence = 0;
  for (int k = 0; k < 100; ++k) {
    const double t = k * kDt;
    loop.ReadHost(Command(++host_sequence, 0.5f), t, true);
    if (k >= 50) loop.ReadHost(Command(0x40000000u + static_cast<std::uint32_t>(k), 15.0f), t, false);  // forged
    loop.Update(t, kDt);
    loop.Write(out);
    EXPECT_FLOAT_EQ(static_cast<float>(loop.controller().finger(device::Manipulator::kThumb).commanded_force_D_N.z()),
                    0.5f)
        << "tick " << k;
    EXPECT_EQ(loop.controller().host_sequence(), host_sequence);
  }
  EXPECT_EQ(loop.commands_from_strangers(), 50u);
  EXPECT_EQ(Counter(health, "commands_from_strangers"), 50u);
  EXPECT_EQ(Counter(health, "commands_accepted"), 100u) << "the strangers' were not even decoded";
  EXPECT_EQ(Counter(health, "commands_rejected"), 0u);
  // nor do strangers keep the host watchdog quiet: the host falls silent, the force goes
  for (int k = 100; k < 200; ++k) {
    loop.ReadHost(Command(0x40000000u + static_cast<std::uint32_t>(k), 15.0f), k * kDt, false);
    loop.Update(k * kDt, kDt);
  }
  EXPECT_TRUE(loop.controller().host_timed_out());
  EXPECT_EQ(loop.controller().finger(device::Manipulator::kThumb).commanded_force_D_N.norm(), 0.0);
}

TEST(MockGrabLoopTest, WarmedUpTickDoesNotAllocate) {
  if (!haptex::testing::AllocationCountingSupported()) GTEST_SKIP() << "allocation counting is off in this build";
  const std::string path = ::testing::TempDir() + "/mock_grab_loop_alloc_" + std::to_string(getpid()) + ".csv";
  runtime::HealthReporter health("mock_grab");
  haptex::testing::CapturedOutbox out;
  out.capture = false;
  ForceLog log(path);
  MockGrabLoop loop(device::MockControllerConfig{}, device::ScriptParams{}, &log, 0, &health);
  const auto command = Command(1, 1.0f);
  for (int k = 0; k < 100; ++k) {
    loop.ReadHost(command, k * kDt, true);
    loop.Update(k * kDt, kDt);
    loop.Write(out);
  }
  haptex::testing::AllocationCounter counter;
  for (int k = 100; k < 1100; ++k) {
    loop.ReadHost(command, k * kDt, true);
    loop.Update(k * kDt, kDt);
    loop.Write(out);
  }
  EXPECT_EQ(counter.count(), 0);
  std::remove(path.c_str());
}

}  // namespace
}  // namespace haptex::mock_grab
