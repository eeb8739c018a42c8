#include "libs/device/mock_grab_controller.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <stdexcept>
#include <vector>

#include "tests/support/allocation_counter.h"

namespace haptex::device {
namespace {

constexpr double kTick_s = 2e-4;
using StatusBytes = std::array<std::byte, kStatusFrameSize>;
using CommandBytes = std::array<std::byte, kCommandFrameSize>;

StatusFrame DecodeStatus(const StatusBytes& b) {
  StatusFrame f;
  EXPECT_EQ(DecodeStatusFrame(b, GrabValueLimits{}, &f), FrameError::kNone);
  return f;
}

CommandBytes Command(std::uint32_t sequence, const Eigen::Vector3f& thumb_N,
                     std::uint16_t flags = command_flags::kForceEnable) {
  CommandFrame c;
  c.sequence = sequence;
  c.manipulators[0].force_D_N = thumb_N;
  c.manipulators[0].flags = flags;
  CommandBytes b{};
  EncodeCommandFrame(c, b);
  return b;
}

TEST(MockGrabControllerTest, IdleFingersStayAtRestWithQuantisedPositions) {
  MockGrabController dut(MockControllerConfig{}, ScriptParams{});
  StatusBytes out{};
  for (int k = 0; k < 5000; ++k) dut.Step(k * kTick_s, kTick_s, out);
  const StatusFrame f = DecodeStatus(out);
  EXPECT_EQ(f.sequence, 5000u);
  EXPECT_EQ(f.controller_time_ns, 1000000000u);
  EXPECT_NEAR(f.manipulators[0].p_D_m.y(), -0.03f, 0.032e-3f);
  for (int axis = 0; axis < 3; ++axis) {
    const double counts = static_cast<double>(f.manipulators[0].p_D_m[axis]) / 0.032e-3;
    EXPECT_NEAR(counts, std::round(counts), 1e-3) << "axis " << axis;
  }
  EXPECT_NE(f.manipulators[0].flags & manipulator_flags::kCalibrated, 0);
  EXPECT_NE(f.controller_flags & controller_flags::kHostTimeout, 0);  // no host yet
}

TEST(MockGrabControllerTest, ForceNoiseIsBoundedAndSeeded) {
  MockControllerConfig config;
  MockGrabController a(config, ScriptParams{});
  MockGrabController b(config, ScriptParams{});
  config.seed = 2;
  MockGrabController c(config, ScriptParams{});
  StatusBytes oa{}, ob{}, oc{};
  bool any_difference = false;
  for (int k = 0; k < 2000; ++k) {
    a.Step(k * kTick_s, kTick_s, oa);
    b.Step(k * kTick_s, kTick_s, ob);
    c.Step(k * kTick_s, kTick_s, oc);
    ASSERT_EQ(oa, ob) << "same seed, same bytes";
    any_difference |= oa != oc;
    const StatusFrame f = DecodeStatus(oa);
    for (const ManipulatorStatus& m : f.manipulators) {
      ASSERT_LE(m.force_D_N.cwiseAbs().maxCoeff(), 0.1f);  // zero force plus +-0.1 N noise
    }
  }
  EXPECT_TRUE(any_difference);
}

TEST(MockGrabControllerTest, AppliesCommandsAndTimesOutAfterFiveMilliseconds) {
  MockGrabController dut(MockControllerConfig{}, ScriptParams{});
  StatusBytes out{};
  double t = 0.0;
  std::uint32_t seq = 0;
  for (int k = 0; k < 100; ++k, t += kTick_s) {
    dut.OnCommandDatagram(Command(++seq, {2.0f, 0.0f, 0.0f}), t);
    dut.Step(t, kTick_s, out);
  }
  EXPECT_NEAR(dut.finger(Manipulator::kThumb).applied_force_D_N.x(), 2.0, 1e-6);
  EXPECT_FALSE(dut.host_timed_out());
  EXPECT_GT(dut.finger(Manipulator::kThumb).v_D_m_per_s.x(), 0.0);  // pushed along +x
  const double last_command_s = t - kTick_s;
  for (int k = 0; k < 40; ++k, t += kTick_s) {
    dut.Step(t, kTick_s, out);
    const double silence = t - last_command_s;
    if (silence <= 0.005 - 1e-9) {
      EXPECT_EQ(dut.finger(Manipulator::kThumb).commanded_force_D_N.x(), 2.0) << silence;
    } else {
      EXPECT_EQ(dut.finger(Manipulator::kThumb).commanded_force_D_N, Eigen::Vector3d::Zero()) << silence;
      EXPECT_TRUE(dut.host_timed_out());
      EXPECT_NE(DecodeStatus(out).controller_flags & controller_flags::kHostTimeout, 0);
    }
  }
  EXPECT_EQ(dut.counters().host_timeouts, 1u);
}

// The mock's own process stalled 8 ms (one Step that long): its world pauses, so the host that
// sent a command just before is not timed out and the finger moves no more than in one short
// step. Silence while the mock runs still times out after 5 ms.
TEST(MockGrabControllerTest, ItsOwnStallPausesTheWorldAndDoesNotBlameTheHost) {
  MockGrabController dut(MockControllerConfig{}, ScriptParams{});
  StatusBytes out{};
  double t = 0.0;
  std::uint32_t seq = 0;
  for (int k = 0; k < 100; ++k, t += kTick_s) {
    dut.OnCommandDatagram(Command(++seq, {0.0f, 2.0f, 0.0f}), t);
    dut.Step(t, kTick_s, out);
  }
  const Eigen::Vector3d p_before = dut.finger(Manipulator::kThumb).p_D_m;
  const double v_before = dut.finger(Manipulator::kThumb).v_D_m_per_s.norm();
  dut.Step(t, 0.008, out);
  t += 0.008;
  EXPECT_EQ(dut.counters().world_pauses, 1u);
  EXPECT_FALSE(dut.host_timed_out()) << "the host is not blamed for the mock's own stall";
  EXPECT_EQ(DecodeStatus(out).controller_flags & controller_flags::kHostTimeout, 0);
  EXPECT_EQ(DecodeStatus(out).controller_time_ns, static_cast<std::uint64_t>(std::llround(t * 1e9)))
      << "its clock still tells the time that passed";
  const double moved_m = (dut.finger(Manipulator::kThumb).p_D_m - p_before).norm();
  EXPECT_LE(moved_m, (v_before + 2.0) * 0.001 + 1e-9) << "the world advanced at most 1 ms";
  // the host stays silent while the mock runs: timed out 5 ms of running time after its command
  int ticks_to_timeout = 0;
  while (!dut.host_timed_out() && ticks_to_timeout < 100) {
    dut.Step(t, kTick_s, out);
    t += kTick_s;
    ++ticks_to_timeout;
  }
  EXPECT_GE(ticks_to_timeout, 19);  // 5 ms less the 1 ms the world ran in the long step
  EXPECT_LE(ticks_to_timeout, 21);
  EXPECT_EQ(dut.counters().host_timeouts, 1u);
}

TEST(MockGrabControllerTest, ClampsToPeakAndHonoursEnableAndShutdown) {
  MockGrabController dut(MockControllerConfig{}, ScriptParams{});
  StatusBytes out{};
  double t = 0.0;
  for (int k = 0; k < 60; ++k, t += kTick_s) {  // 20 N at its own slew limit: 40 ticks
    dut.OnCommandDatagram(Command(1 + k, {0.0f, 0.0f, 24.0f}), t);
    dut.Step(t, kTick_s, out);
  }
  EXPECT_NEAR(dut.finger(Manipulator::kThumb).commanded_force_D_N.z(), 20.0, 1e-9);
  EXPECT_NE(DecodeStatus(out).manipulators[0].flags & manipulator_flags::kForceSaturated, 0);
  dut.OnCommandDatagram(Command(61, {0.0f, 0.0f, 5.0f}, 0), t);  // enable clear
  dut.Step(t, kTick_s, out);
  EXPECT_EQ(dut.finger(Manipulator::kThumb).commanded_force_D_N, Eigen::Vector3d::Zero());
  CommandFrame shutdown;
  shutdown.sequence = 62;
  shutdown.host_flags = host_flags::kShutdown;
  shutdown.manipulators[0].force_D_N = {1.0f, 0.0f, 0.0f};
  shutdown.manipulators[0].flags = command_flags::kForceEnable;
  CommandBytes b{};
  EncodeCommandFrame(shutdown, b);
  dut.OnCommandDatagram(b, t + kTick_s);
  dut.Step(t + kTick_s, kTick_s, out);
  EXPECT_EQ(dut.finger(Manipulator::kThumb).commanded_force_D_N, Eigen::Vector3d::Zero());
  EXPECT_EQ(DecodeStatus(out).echo_host_sequence, 62u);
}

// A controller that stalled and then takes the newest of many queued commands (a host's 8 N after
// zero) moves to it at its own slew limit, saying so; a cut to zero is immediate.
TEST(MockGrabControllerTest, MovesToANewCommandAtItsOwnSlewLimitAndCutsAtOnce) {
  MockGrabController dut(MockControllerConfig{}, ScriptParams{});
  StatusBytes out{};
  dut.OnCommandDatagram(Command(1, {0.0f, 0.0f, 8.0f}), 0.0);
  double previous = 0.0;
  for (int k = 0; k < 16; ++k) {
    dut.Step(k * kTick_s, kTick_s, out);
    const double f = dut.finger(Manipulator::kThumb).commanded_force_D_N.z();
    EXPECT_NEAR(f - previous, 0.5, 1e-9) << "tick " << k;
    // limiting until the last step, which lands on the command
    EXPECT_EQ(DecodeStatus(out).manipulators[0].flags & manipulator_flags::kForceSaturated,
              k < 15 ? manipulator_flags::kForceSaturated : 0)
        << "tick " << k;
    previous = f;
    dut.OnCommandDatagram(Command(2 + k, {0.0f, 0.0f, 8.0f}), (k + 1) * kTick_s);
  }
  dut.Step(16 * kTick_s, kTick_s, out);
  EXPECT_NEAR(dut.finger(Manipulator::kThumb).commanded_force_D_N.z(), 8.0, 1e-6);
  dut.OnCommandDatagram(Command(100, {0.0f, 0.0f, 0.0f}), 17 * kTick_s);
  dut.Step(17 * kTick_s, kTick_s, out);
  EXPECT_EQ(dut.finger(Manipulator::kThumb).commanded_force_D_N, Eigen::Vector3d::Zero()) << "a cut is immediate";
}

// docs/grab-protocol.md section 7.1: at boot the controller is in host timeout (zero force,
// HOST_TIMEOUT set, echo 0, not counted as a timeout) and takes the first valid command whatever
// its sequence.
TEST(MockGrabControllerTest, BootsInHostTimeoutAndTakesAnyFirstSequence) {
  MockGrabController dut(MockControllerConfig{}, ScriptParams{});
  StatusBytes out{};
  dut.Step(0.0, kTick_s, out);
  StatusFrame f = DecodeStatus(out);
  EXPECT_NE(f.controller_flags & controller_flags::kHostTimeout, 0);
  EXPECT_EQ(f.echo_host_sequence, 0u);
  EXPECT_EQ(f.manipulators[0].flags & manipulator_flags::kForceEnabled, 0);
  EXPECT_EQ(dut.counters().host_timeouts, 0u) << "the boot state is not a timeout event";
  dut.OnCommandDatagram(Command(0xC0000000u, {1.0f, 0.0f, 0.0f}), kTick_s);
  dut.Step(kTick_s, kTick_s, out);
  f = DecodeStatus(out);
  EXPECT_EQ(f.controller_flags & controller_flags::kHostTimeout, 0);
  EXPECT_EQ(f.echo_host_sequence, 0xC0000000u);
  EXPECT_NE(f.manipulators[0].flags & manipulator_flags::kForceEnabled, 0);
}

// A valid command whose sequence is not newer is ignored: it changes no force, no echo, sets no
// COMMAND_REJECTED and does not feed the watchdog, so the controller times out 5 ms after the last
// accepted command however many old ones arrive. After the timeout any sequence is taken again.
TEST(MockGrabControllerTest, OutOfOrderCommandsAreIgnoredAndDoNotFeedTheWatchdog) {
  MockGrabController dut(MockControllerConfig{}, ScriptParams{});
  StatusBytes out{};
  double t = 0.0;
  dut.OnCommandDatagram(Command(10, {1.0f, 0.0f, 0.0f}), t);
  dut.Step(t, kTick_s, out);
  for (int k = 0; k < 24; ++k) {  // 4.8 ms of an old command, repeated
    t += kTick_s;
    dut.OnCommandDatagram(Command(9, {3.0f, 0.0f, 0.0f}), t);
    dut.Step(t, kTick_s, out);
    const StatusFrame f = DecodeStatus(out);
    EXPECT_EQ(f.echo_host_sequence, 10u);
    EXPECT_EQ(f.controller_flags & controller_flags::kCommandRejected, 0);
    EXPECT_EQ(dut.finger(Manipulator::kThumb).commanded_force_D_N.x(), 1.0);
  }
  EXPECT_EQ(dut.counters().commands_out_of_order, 24u);
  EXPECT_FALSE(dut.host_timed_out());
  t += kTick_s;  // 5 ms after the last accepted command
  dut.Step(t, kTick_s, out);
  EXPECT_TRUE(dut.host_timed_out()) << "old commands do not feed the watchdog";
  EXPECT_EQ(dut.counters().host_timeouts, 1u);
  dut.OnCommandDatagram(Command(3, {1.0f, 0.0f, 0.0f}), t);  // a restarted host
  dut.Step(t, kTick_s, out);
  EXPECT_FALSE(dut.host_timed_out());
  EXPECT_EQ(DecodeStatus(out).echo_host_sequence, 3u);
}

// After SHUTDOWN: zero force at once, and the silence that follows sets no HOST_TIMEOUT and counts
// no timeout. Until 5 ms have passed only newer sequences are taken (a late duplicate of an older
// command cannot switch force back on); after that any sequence (a new host).
TEST(MockGrabControllerTest, ShutdownIsZeroForceWithoutATimeoutFault) {
  MockGrabController dut(MockControllerConfig{}, ScriptParams{});
  StatusBytes out{};
  double t = 0.0;
  for (std::uint32_t seq = 1; seq <= 20; ++seq, t += kTick_s) {
    dut.OnCommandDatagram(Command(seq, {1.0f, 0.0f, 0.0f}), t);
    dut.Step(t, kTick_s, out);
  }
  CommandFrame shutdown;
  shutdown.sequence = 21;
  shutdown.host_flags = host_flags::kShutdown;
  CommandBytes b{};
  EncodeCommandFrame(shutdown, b);
  dut.OnCommandDatagram(b, t);
  dut.Step(t, kTick_s, out);
  EXPECT_EQ(dut.finger(Manipulator::kThumb).commanded_force_D_N, Eigen::Vector3d::Zero());
  t += kTick_s;
  dut.OnCommandDatagram(Command(20, {1.0f, 0.0f, 0.0f}), t);  // a late duplicate
  dut.Step(t, kTick_s, out);
  EXPECT_EQ(dut.finger(Manipulator::kThumb).commanded_force_D_N, Eigen::Vector3d::Zero());
  EXPECT_EQ(DecodeStatus(out).echo_host_sequence, 21u);
  for (int k = 0; k < 100; ++k) {  // 20 ms of silence
    t += kTick_s;
    dut.Step(t, kTick_s, out);
    EXPECT_EQ(DecodeStatus(out).controller_flags & controller_flags::kHostTimeout, 0) << k;
  }
  EXPECT_EQ(dut.counters().host_timeouts, 0u);
  dut.OnCommandDatagram(Command(1, {1.0f, 0.0f, 0.0f}), t);  // a new host starts at 1
  dut.Step(t, kTick_s, out);
  EXPECT_EQ(DecodeStatus(out).echo_host_sequence, 1u);
  EXPECT_NE(DecodeStatus(out).manipulators[0].flags & manipulator_flags::kForceEnabled, 0);
}

// Status sequences skip 0 on the wrap; a command with sequence 0 is never acted on.
TEST(MockGrabControllerTest, SequencesSkipZero) {
  MockControllerConfig config;
  config.first_status_sequence = 0xFFFFFFFEu;
  MockGrabController dut(config, ScriptParams{});
  StatusBytes out{};
  std::vector<std::uint32_t> sequences;
  for (int k = 0; k < 4; ++k) {
    dut.Step(k * kTick_s, kTick_s, out);
    sequences.push_back(DecodeStatus(out).sequence);
  }
  EXPECT_EQ(sequences, (std::vector<std::uint32_t>{0xFFFFFFFEu, 0xFFFFFFFFu, 1u, 2u}));
  dut.OnCommandDatagram(Command(0, {1.0f, 0.0f, 0.0f}), 4 * kTick_s);
  dut.Step(4 * kTick_s, kTick_s, out);
  EXPECT_EQ(DecodeStatus(out).echo_host_sequence, 0u);
  EXPECT_TRUE(dut.host_timed_out());
  EXPECT_EQ(dut.counters().commands_out_of_order, 1u);
  config.first_status_sequence = 0;
  EXPECT_THROW(MockGrabController(config, ScriptParams{}), std::invalid_argument);
}

TEST(MockGrabControllerTest, RejectsBadCommandsAndReportsIt) {
  MockGrabController dut(MockControllerConfig{}, ScriptParams{});
  StatusBytes out{};
  CommandBytes bad = Command(1, {1.0f, 0.0f, 0.0f});
  bad[20] ^= std::byte{1};
  EXPECT_EQ(dut.OnCommandDatagram(bad, 0.0), FrameError::kBadChecksum);
  dut.Step(0.0, kTick_s, out);
  EXPECT_NE(DecodeStatus(out).controller_flags & controller_flags::kCommandRejected, 0);
  dut.Step(kTick_s, kTick_s, out);
  EXPECT_EQ(DecodeStatus(out).controller_flags & controller_flags::kCommandRejected, 0);
  EXPECT_EQ(dut.frame_counters().Get(FrameError::kBadChecksum), 1u);
}

TEST(MockGrabControllerTest, StopsAtTheWorkspaceFaces) {
  ScriptParams script;
  script.kind = ScriptKind::kPinchAndStretch;
  script.stretch_D_m = {0.19, 0.0, 0.0};  // target beyond x = 0.2 m for the pressed fingers
  script.fabric_point_D_m = {0.05, 0.0, 0.0};
  MockGrabController dut(MockControllerConfig{}, script);
  StatusBytes out{};
  bool limit_seen = false;
  for (int k = 0; k < 20000; ++k) {
    dut.Step(k * kTick_s, kTick_s, out);
    const StatusFrame f = DecodeStatus(out);
    ASSERT_LE(std::abs(f.manipulators[0].p_D_m.x()), 0.2f);
    limit_seen |= (f.manipulators[0].flags & manipulator_flags::kWorkspaceLimit) != 0;
  }
  EXPECT_TRUE(limit_seen);
  EXPECT_NEAR(dut.finger(Manipulator::kThumb).p_D_m.x(), 0.2, 1e-6);
}

TEST(MockGrabControllerTest, InvalidConfigThrows) {
  MockControllerConfig config;
  config.finger.mass_kg = 0.0;
  EXPECT_THROW(MockGrabController(config, ScriptParams{}), std::invalid_argument);
  ScriptParams script;
  script.kind = ScriptKind::kPlayback;  // without a trajectory
  EXPECT_THROW(MockGrabController(MockControllerConfig{}, script), std::invalid_argument);
}

TEST(MockGrabControllerTest, WarmedUpStepDoesNotAllocate) {
  if (!testing::AllocationCountingSupported()) GTEST_SKIP() << "allocation counting unavailable";
  ScriptParams script;
  script.kind = ScriptKind::kRub;
  MockGrabController dut(MockControllerConfig{}, script);
  StatusBytes out{};
  for (int k = 0; k < 100; ++k) {
    dut.OnCommandDatagram(Command(static_cast<std::uint32_t>(k + 1), {0.5f, 0.0f, 0.0f}), k * kTick_s);
    dut.Step(k * kTick_s, kTick_s, out);
  }
  const CommandBytes next = Command(101, {0.5f, 0.0f, 0.0f});
  testing::AllocationCounter counter;
  dut.OnCommandDatagram(next, 100 * kTick_s);
  dut.Step(100 * kTick_s, kTick_s, out);
  EXPECT_EQ(counter.count(), 0);
}

}  // namespace
}  // namespace haptex::device
