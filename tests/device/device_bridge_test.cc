#include "libs/device/device_bridge.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>

#include "tests/support/allocation_counter.h"

namespace haptex::device {
namespace {

constexpr double kTick_s = 2e-4;
using StatusBytes = std::array<std::byte, kStatusFrameSize>;
using CommandBytes = std::array<std::byte, kCommandFrameSize>;

DeviceBridgeConfig FastConfig() {
  DeviceBridgeConfig c;
  c.safety.startup_ramp_s = 0.002;
  return c;
}

StatusBytes Status(std::uint32_t sequence, double t_s, const Eigen::Vector3f& thumb_D_m = {0.01f, -0.02f, 0.0f},
                   std::uint16_t flags = manipulator_flags::kCalibrated, std::uint32_t echo_host_sequence = 0) {
  StatusFrame f;
  f.sequence = sequence;
  f.echo_host_sequence = echo_host_sequence;
  f.controller_time_ns = static_cast<std::uint64_t>(std::llround(t_s * 1e9));
  f.manipulators[0].p_D_m = thumb_D_m;
  f.manipulators[0].flags = flags;
  f.manipulators[1].p_D_m = {0.01f, 0.02f, 0.0f};
  f.manipulators[1].flags = flags;
  StatusBytes b{};
  EncodeStatusFrame(f, b);
  return b;
}

CommandFrame Decode(const CommandBytes& bytes) {
  CommandFrame c;
  EXPECT_EQ(DecodeCommandFrame(bytes, GrabValueLimits{}, &c), FrameError::kNone);
  return c;
}

ForceModel ConstantForce(const Eigen::Vector3d& force_W_N) {
  ForceModel m;
  m.force0_W_N = force_W_N;
  m.ttl_s = 0.010;
  return m;
}

TEST(DeviceBridgeTest, NoControllerMeansLostAndZeroForce) {
  auto dut = std::make_unique<DeviceBridge>(FastConfig());
  dut->SetForceModel(Manipulator::kThumb, ConstantForce({1.0, 0.0, 0.0}), 0.0,
                     dut->finger_state(Manipulator::kThumb).controller_sequence);
  CommandBytes out{};
  dut->Tick(0.0, kTick_s, out);
  const CommandFrame c = Decode(out);
  EXPECT_TRUE(dut->device_lost());
  EXPECT_EQ(c.manipulators[0].force_D_N, Eigen::Vector3f::Zero());
  EXPECT_EQ(c.manipulators[0].flags & command_flags::kForceEnable, 0);
  EXPECT_EQ(c.sequence, 1u);
}

TEST(DeviceBridgeTest, CountsRejectedFramesAndIgnoresOldOnes) {
  auto dut = std::make_unique<DeviceBridge>(FastConfig());
  StatusBytes good = Status(10, 0.001);
  EXPECT_EQ(dut->OnStatusDatagram(good, 0.001), FrameError::kNone);
  StatusBytes bad = good;
  bad[40] ^= std::byte{4};
  EXPECT_EQ(dut->OnStatusDatagram(bad, 0.0012), FrameError::kBadChecksum);
  EXPECT_EQ(dut->OnStatusDatagram(std::span(good).first(20), 0.0013), FrameError::kTooShort);
  // sequence 9 after 10: valid but out of order, ignored
  EXPECT_EQ(dut->OnStatusDatagram(Status(9, 0.0008, {0.05f, 0.0f, 0.0f}), 0.0014), FrameError::kNone);
  EXPECT_EQ(dut->counters().status_out_of_order, 1u);
  EXPECT_EQ(dut->finger_state(Manipulator::kThumb).controller_sequence, 10u);
  EXPECT_EQ(dut->frame_counters().accepted(), 2u);
  EXPECT_EQ(dut->frame_counters().Get(FrameError::kBadChecksum), 1u);
  EXPECT_EQ(dut->frame_counters().TotalRejected(), 2u);
}

// A status with sequence 0 is never sent (0 means "none"): the bridge ignores it, even as its
// first frame, and orders frames across the wrap from 2^32 - 1 to 1.
TEST(DeviceBridgeTest, IgnoresSequenceZeroAndOrdersAcrossTheWrap) {
  auto dut = std::make_unique<DeviceBridge>(FastConfig());
  EXPECT_EQ(dut->OnStatusDatagram(Status(0, 0.001), 0.001), FrameError::kNone);
  EXPECT_EQ(dut->counters().status_out_of_order, 1u);
  EXPECT_EQ(dut->finger_state(Manipulator::kThumb).controller_sequence, 0u);
  dut->OnStatusDatagram(Status(0xFFFFFFFFu, 0.0012), 0.0012);
  dut->OnStatusDatagram(Status(0, 0.0014), 0.0014);
  dut->OnStatusDatagram(Status(1, 0.0016), 0.0016);
  EXPECT_EQ(dut->counters().status_out_of_order, 2u);
  EXPECT_EQ(dut->finger_state(Manipulator::kThumb).controller_sequence, 1u);
  CommandBytes out{};
  dut->Tick(0.0016, kTick_s, out);
  EXPECT_EQ(Decode(out).echo_controller_sequence, 1u);
}

TEST(DeviceBridgeTest, MapsPosesAndForcesBetweenDeviceAndWorldFrames) {
  DeviceBridgeConfig config = FastConfig();
  config.X_WD = Eigen::Translation3d(0.0, 0.0, -0.1) * Eigen::AngleAxisd(std::numbers::pi, Eigen::Vector3d::UnitZ());
  auto dut = std::make_unique<DeviceBridge>(config);
  dut->SetForceModel(Manipulator::kThumb, ConstantForce({1.0, 2.0, 3.0}), 0.0,
                     dut->finger_state(Manipulator::kThumb).controller_sequence);
  CommandBytes out{};
  for (int k = 1; k <= 100; ++k) {
    const double t = k * kTick_s;
    dut->OnStatusDatagram(Status(static_cast<std::uint32_t>(k), t), t);
    dut->SetForceModel(Manipulator::kThumb, ConstantForce({1.0, 2.0, 3.0}), t,
                       dut->finger_state(Manipulator::kThumb).controller_sequence);
    dut->Tick(t, kTick_s, out);
  }
  const FingerState& s = dut->finger_state(Manipulator::kThumb);
  EXPECT_TRUE(s.p_W_m.isApprox(Eigen::Vector3d(-0.01, 0.02, -0.1), 1e-6));
  // world force (1, 2, 3) is (-1, -2, 3) in D
  const CommandFrame c = Decode(out);
  EXPECT_TRUE(c.manipulators[0].force_D_N.isApprox(Eigen::Vector3f(-1.0f, -2.0f, 3.0f), 1e-5f));
  EXPECT_NE(c.manipulators[0].flags & command_flags::kForceEnable, 0);
  EXPECT_EQ(c.echo_controller_sequence, 100u);
  EXPECT_EQ(c.manipulators[1].force_D_N, Eigen::Vector3f::Zero());  // index has no model
}

// The controller streams at 5 kHz; ForceModels stop arriving at t0. The force holds for 10 ms,
// ramps down, and is exactly zero at every tick from t0 + 20 ms on.
TEST(DeviceBridgeTest, WatchdogZeroesForceWithinTwentyMilliseconds) {
  auto dut = std::make_unique<DeviceBridge>(FastConfig());
  CommandBytes out{};
  const Eigen::Vector3d force_W_N(0.0, 8.0, -6.0);
  double t0 = 0.0;
  double previous_N = 0.0;
  for (int k = 1; k <= 1500; ++k) {
    const double t = k * kTick_s;
    dut->OnStatusDatagram(Status(static_cast<std::uint32_t>(k), t), t);
    if (t <= 0.1) {
      if (k % 5 == 0) {  // models at 1 kHz
        dut->SetForceModel(Manipulator::kThumb, ConstantForce(force_W_N), t,
                           dut->finger_state(Manipulator::kThumb).controller_sequence);
        t0 = t;
      }
    }
    dut->Tick(t, kTick_s, out);
    const CommandFrame c = Decode(out);
    const double age = t - t0;
    if (t > 0.05 && age <= 0.010 + 1e-9) {
      EXPECT_NEAR((c.manipulators[0].force_D_N.cast<double>() - force_W_N).norm(), 0.0, 1e-5) << t;
    }
    if (age >= 0.020 - 1e-9) {
      ASSERT_EQ(c.manipulators[0].force_D_N, Eigen::Vector3f::Zero()) << "age " << age;
      EXPECT_NE(c.manipulators[0].flags & command_flags::kRamping, 0);
    }
    // the ramp-out is continuous: no step to zero, at most |F| per stale_ramp_s
    const double norm = c.manipulators[0].force_D_N.cast<double>().norm();
    if (t > 0.1) {
      EXPECT_LE(previous_N - norm, force_W_N.norm() * kTick_s / 0.010 + 1e-5) << t;
    }
    previous_N = norm;
  }
  EXPECT_GT(dut->safety(Manipulator::kThumb).counters().watchdog_zero_steps, 0u);
}

TEST(DeviceBridgeTest, ControllerSilenceMeansDeviceLostThenRampsBackIn) {
  auto dut = std::make_unique<DeviceBridge>(FastConfig());
  CommandBytes out{};
  std::uint32_t seq = 0;
  auto run = [&](double from, double to, bool controller_talks) {
    for (double t = from; t < to - 1e-9; t += kTick_s) {
      if (controller_talks) dut->OnStatusDatagram(Status(++seq, t), t);
      dut->SetForceModel(Manipulator::kThumb, ConstantForce({3.0, 0.0, 0.0}), t,
                         dut->finger_state(Manipulator::kThumb).controller_sequence);
      dut->Tick(t, kTick_s, out);
    }
  };
  run(0.0, 0.05, true);
  EXPECT_FALSE(dut->device_lost());
  EXPECT_NEAR(dut->last_force_W_N(Manipulator::kThumb).x(), 3.0, 1e-9);
  run(0.05, 0.0995, false);  // < 50 ms of silence
  EXPECT_FALSE(dut->device_lost());
  run(0.0995, 0.11, false);
  EXPECT_TRUE(dut->device_lost());
  EXPECT_EQ(dut->last_force_W_N(Manipulator::kThumb), Eigen::Vector3d::Zero());
  EXPECT_EQ(dut->counters().device_lost_events, 1u);
  // the controller restarts with a lower sequence: accepted, force ramps in again
  seq = 0;
  dut->OnStatusDatagram(Status(++seq, 0.11), 0.11);
  dut->Tick(0.11, kTick_s, out);
  EXPECT_FALSE(dut->device_lost());
  const double first = dut->last_force_W_N(Manipulator::kThumb).x();
  EXPECT_GT(first, 0.0);
  EXPECT_LT(first, 3.0);
}

// A controller that echoes a command sequence the bridge never sent took another host's command:
// force off at once, counted, and back (over the start-up ramp) only after its echoes have been the
// bridge's own for foreign_echo_hold_s.
TEST(DeviceBridgeTest, AForeignEchoIsAFaultUntilTheEchoesAreOursAgain) {
  DeviceBridgeConfig config = FastConfig();
  config.foreign_echo_hold_s = 0.05;
  auto dut = std::make_unique<DeviceBridge>(config);
  CommandBytes out{};
  std::uint32_t seq = 0, ours = 0;
  auto run = [&](double from, double to, bool foreign) {
    for (double t = from; t < to - 1e-9; t += kTick_s) {
      const std::uint32_t echo = foreign ? ours + 1000 : ours;
      dut->OnStatusDatagram(Status(++seq, t, {0.01f, -0.02f, 0.0f}, manipulator_flags::kCalibrated, echo), t);
      dut->SetForceModel(Manipulator::kThumb, ConstantForce({3.0, 0.0, 0.0}), t,
                         dut->finger_state(Manipulator::kThumb).controller_sequence);
      dut->Tick(t, kTick_s, out);
      ours = Decode(out).sequence;
    }
  };
  run(0.0, 0.05, false);
  EXPECT_NEAR(dut->last_force_W_N(Manipulator::kThumb).x(), 3.0, 1e-9);
  EXPECT_EQ(dut->counters().foreign_echoes, 0u) << "its own echoes are not foreign";
  run(0.05, 0.05 + kTick_s, true);
  EXPECT_TRUE(dut->foreign_commander());
  EXPECT_EQ(dut->last_force_W_N(Manipulator::kThumb), Eigen::Vector3d::Zero()) << "force off in the same tick";
  EXPECT_FALSE(Decode(out).manipulators[0].flags & command_flags::kForceEnable);
  run(0.05 + kTick_s, 0.08, true);
  EXPECT_EQ(dut->counters().foreign_echo_events, 1u);
  EXPECT_EQ(dut->counters().foreign_echoes, 150u);
  run(0.08, 0.125, false);  // ours again, not yet for the hold time
  EXPECT_TRUE(dut->foreign_commander());
  EXPECT_EQ(dut->last_force_W_N(Manipulator::kThumb), Eigen::Vector3d::Zero());
  run(0.125, 0.1305, false);
  EXPECT_FALSE(dut->foreign_commander());
  const double resumed = dut->last_force_W_N(Manipulator::kThumb).x();
  EXPECT_GT(resumed, 0.0);
  EXPECT_LT(resumed, 3.0) << "ramps in, no step back to the old force";
}

// A bridge fed a constant thumb force model and a fresh status datagram every tick (sampled on
// the controller's clock when it arrives; by default echoing no command, a controller that tells
// nothing of what it holds).
class ConstantForceBridge {
 public:
  ConstantForceBridge(const DeviceBridgeConfig& config, double force_N)
      : dut_(std::make_unique<DeviceBridge>(config)), force_N_(force_N) {}
  /// One tick `dt_s` after the last; returns the commanded thumb force along x [N]. The status
  /// read before it was sampled `status_age_s` earlier and carries `controller_flags`.
  double Tick(double dt_s, double status_age_s = 0.0, std::uint16_t controller_flags = 0, bool model = true) {
    t_ += dt_s;
    StatusFrame f;
    f.sequence = ++seq_;
    f.controller_flags = controller_flags;
    f.echo_host_sequence = echo_ ? last_command_ : 0;
    f.controller_time_ns = static_cast<std::uint64_t>(std::llround((t_ - status_age_s) * 1e9));
    for (ManipulatorStatus& m : f.manipulators) m.flags = manipulator_flags::kCalibrated;
    f.manipulators[0].p_D_m = {0.01f, -0.02f, 0.0f};
    f.manipulators[1].p_D_m = {0.01f, 0.02f, 0.0f};
    StatusBytes status{};
    EncodeStatusFrame(f, status);
    dut_->OnStatusDatagram(status, t_);
    if (model) {
      dut_->SetForceModel(Manipulator::kThumb, ConstantForce({force_N_, 0.0, 0.0}), t_,
                          dut_->finger_state(Manipulator::kThumb).controller_sequence);
    }
    dut_->Tick(t_, dt_s, out_);
    last_command_ = Decode(out_).sequence;
    return dut_->last_force_W_N(Manipulator::kThumb).x();
  }
  /// From now on statuses echo the bridge's last command, as a real controller's do.
  void EchoCommands() { echo_ = true; }
  const DeviceBridge& dut() const { return *dut_; }
  /// After a forced zero: over `ticks` ticks the force rises from zero by at most force / ramp_s
  /// per second (never a jump) and is back at full force.
  void ExpectRampsBackIn(double ramp_s, int ticks) {
    double previous = 0.0;
    for (int k = 0; k < ticks; ++k) {
      const double f = Tick(kTick_s);
      EXPECT_LE(f, previous + force_N_ * kTick_s / ramp_s + 1e-9) << "tick " << k;
      previous = f;
    }
    EXPECT_NEAR(previous, force_N_, 1e-9) << "not back at full force " << ramp_s << " s after";
  }

 private:
  std::unique_ptr<DeviceBridge> dut_;
  double force_N_;
  CommandBytes out_{};
  std::uint32_t seq_ = 0, last_command_ = 0;
  bool echo_ = false;
  double t_ = 0.0;
};

// The host stalled 5 ms and the controller never answers a command sent after it (it echoes
// none): it may have zeroed force by now, though its timeout flag has not reached us. The bridge
// waits gap_confirm_window_s for the answer, then disarms, and the force ramps in from zero
// (fully armed before the stall: over resume_ramp_s, 5 ms), never jumping back.
TEST(DeviceBridgeTest, OwnTickGapWithoutTheControllersAnswerDisarms) {
  DeviceBridgeConfig config = FastConfig();
  config.safety.startup_ramp_s = 0.010;
  ConstantForceBridge bridge(config, 3.0);
  for (int k = 0; k < 100; ++k) bridge.Tick(kTick_s);
  ASSERT_NEAR(bridge.Tick(kTick_s), 3.0, 1e-9);
  EXPECT_NEAR(bridge.Tick(0.0035), 3.0, 1e-9) << "a gap shorter than the threshold keeps the force";
  EXPECT_NEAR(bridge.Tick(0.005), 3.0, 1e-9) << "the tick after a 5 ms gap waits for the controller";
  const int window_ticks = static_cast<int>(std::lround(config.gap_confirm_window_s / kTick_s));
  int waited = 1;
  while (bridge.Tick(kTick_s) != 0.0 && waited < 100) ++waited;
  EXPECT_EQ(waited, window_ticks) << "disarmed when the window ran out";
  EXPECT_EQ(bridge.dut().counters().tick_gap_disarms, 1u);
  EXPECT_EQ(bridge.dut().counters().tick_gaps_held, 0u);
  bridge.ExpectRampsBackIn(config.safety.resume_ramp_s, 60);
  config.disarm_after_tick_gap_s = 0.0;
  EXPECT_THROW(DeviceBridge{config}, std::invalid_argument);
  config = FastConfig();
  config.gap_confirm_window_s = 0.0;
  EXPECT_THROW(DeviceBridge{config}, std::invalid_argument);
}

// With the scene's half-second start-up ramp, a disarmed stall of a running bridge resumes over
// the short resume ramp (the device is still held where the force was), from zero.
// The scene's half-second start-up ramp and a 20 ms resume ramp.
DeviceBridgeConfig SlowStartConfig() {
  DeviceBridgeConfig config = FastConfig();
  config.safety.startup_ramp_s = 0.5;
  config.safety.resume_ramp_s = 0.02;
  return config;
}

TEST(DeviceBridgeTest, OwnTickGapWhileArmedResumesOverTheShortRamp) {
  const DeviceBridgeConfig config = SlowStartConfig();
  ConstantForceBridge bridge(config, 2.0);
  for (int k = 0; k < 2600; ++k) bridge.Tick(kTick_s);
  ASSERT_NEAR(bridge.Tick(kTick_s), 2.0, 1e-9);
  bridge.Tick(0.005);
  int waited = 0;
  while (bridge.Tick(kTick_s) != 0.0 && waited < 100) ++waited;
  EXPECT_EQ(bridge.dut().counters().tick_gap_disarms, 1u);
  bridge.ExpectRampsBackIn(config.safety.resume_ramp_s, 100);
}

// local_contact (or the whole host) paused: the models fall silent and the watchdog takes the
// force to zero by 20 ms. When models come back within resume_within_s, the force resumes over the
// short ramp as after a link interruption; a squeezing user's fingers would close through the
// fabric over the start-up ramp. Each cut is counted once.
TEST(DeviceBridgeTest, ModelsSilentForAPauseCutThenResumeOverTheShortRamp) {
  const DeviceBridgeConfig config = SlowStartConfig();
  ConstantForceBridge bridge(config, 2.0);
  for (int k = 0; k < 2600; ++k) bridge.Tick(kTick_s);
  ASSERT_NEAR(bridge.Tick(kTick_s), 2.0, 1e-9);
  double last = 0.0;
  for (int k = 0; k < 150; ++k) last = bridge.Tick(kTick_s, 0.0, 0, /*model=*/false);  // 30 ms
  EXPECT_EQ(last, 0.0);
  EXPECT_EQ(bridge.dut().counters().stale_model_cuts, 1u);
  EXPECT_EQ(bridge.dut().counters().tick_gap_disarms, 0u);
  bridge.ExpectRampsBackIn(config.safety.resume_ramp_s, 100);
  // a silence that keeps the force at zero for longer than resume_within_s: the start-up ramp
  for (int k = 0; k < 100 + 600; ++k) bridge.Tick(kTick_s, 0.0, 0, /*model=*/false);  // 20 + 120 ms
  EXPECT_EQ(bridge.dut().counters().stale_model_cuts, 2u);
  for (int k = 0; k < 100; ++k) last = bridge.Tick(kTick_s);
  EXPECT_NEAR(last, 2.0 * 100 * kTick_s / config.safety.startup_ramp_s, 1e-6);
}

// The host stalled, and the controller answers the first command sent after the gap without
// HOST_TIMEOUT: the device held the force all along, so the bridge goes on from it (no cut for
// the user's fingers to fall in through). HOST_TIMEOUT on the newest status at the gap, or on a
// status before the answer, disarms, and the force ramps in from zero.
TEST(DeviceBridgeTest, TickGapTheControllerHeldThroughKeepsTheForce) {
  DeviceBridgeConfig config = FastConfig();
  config.safety.startup_ramp_s = 0.010;
  ConstantForceBridge bridge(config, 3.0);
  bridge.EchoCommands();
  for (int k = 0; k < 100; ++k) bridge.Tick(kTick_s);
  ASSERT_NEAR(bridge.Tick(kTick_s), 3.0, 1e-9);

  // the newest status is 2 ms old (the controller stalled too); the next one answers
  EXPECT_NEAR(bridge.Tick(0.0045, 0.002), 3.0, 1e-9);
  EXPECT_NEAR(bridge.Tick(kTick_s), 3.0, 1e-9);
  EXPECT_EQ(bridge.dut().counters().tick_gaps_held, 1u);
  EXPECT_EQ(bridge.dut().counters().tick_gap_disarms, 0u);
  for (int k = 0; k < 20; ++k) EXPECT_NEAR(bridge.Tick(kTick_s), 3.0, 1e-9);

  EXPECT_EQ(bridge.Tick(0.006, 0.0, controller_flags::kHostTimeout), 0.0) << "the controller says it timed out";
  EXPECT_EQ(bridge.dut().counters().tick_gap_disarms, 1u);
  bridge.ExpectRampsBackIn(config.safety.resume_ramp_s, 60);

  // it timed out in the last moment before we woke: the flag comes with the status after the gap
  EXPECT_NEAR(bridge.Tick(0.0049), 3.0, 1e-9);
  EXPECT_EQ(bridge.Tick(kTick_s, 0.0, controller_flags::kHostTimeout), 0.0);
  EXPECT_EQ(bridge.dut().counters().tick_gap_disarms, 2u);
  EXPECT_EQ(bridge.dut().counters().tick_gaps_held, 1u);
  bridge.ExpectRampsBackIn(config.safety.resume_ramp_s, 60);
}

// docs/grab-protocol.md section 7.2: what the controller's flags make the bridge do. EMERGENCY_STOP
// and a cleared CALIBRATED cut the force at once (FORCE_ENABLE clear, RAMPING clear) and it comes
// back over the start-up ramp; HOST_TIMEOUT of an armed bridge cuts it too and it comes back over
// the short resume ramp. Every ramp starts from zero: no step back to the old force.
TEST(DeviceBridgeTest, ControllerFlagsCutForceAndItRampsInFromZero) {
  DeviceBridgeConfig config = FastConfig();
  config.safety.startup_ramp_s = 0.05;
  auto dut = std::make_unique<DeviceBridge>(config);
  constexpr double kForce_N = 3.0;
  CommandBytes out{};
  std::uint32_t seq = 0;
  double t = 0.0;
  struct Tick {
    double force_N;
    std::uint16_t flags;
  };
  const auto tick = [&](std::uint16_t controller_flags, std::uint16_t thumb_flags) {
    t += kTick_s;
    StatusFrame f;
    f.sequence = ++seq;
    f.controller_flags = controller_flags;
    f.controller_time_ns = static_cast<std::uint64_t>(std::llround(t * 1e9));
    f.manipulators[0].p_D_m = {0.01f, 0.02f, 0.0f};
    f.manipulators[0].flags = thumb_flags;
    f.manipulators[1].p_D_m = {0.01f, -0.02f, 0.0f};
    f.manipulators[1].flags = manipulator_flags::kCalibrated;
    StatusBytes b{};
    EncodeStatusFrame(f, b);
    dut->OnStatusDatagram(b, t);
    dut->SetForceModel(Manipulator::kThumb, ConstantForce({kForce_N, 0.0, 0.0}), t,
                       dut->finger_state(Manipulator::kThumb).controller_sequence);
    dut->Tick(t, kTick_s, out);
    const CommandFrame c = Decode(out);
    return Tick{c.manipulators[0].force_D_N.x(), c.manipulators[0].flags};
  };
  const auto run_armed = [&] {
    for (int k = 0; k < 400; ++k) tick(0, manipulator_flags::kCalibrated);
    ASSERT_NEAR(tick(0, manipulator_flags::kCalibrated).force_N, kForce_N, 1e-5);
  };
  // a cut lasting `ticks`, then the ramp back from zero over `ramp_s`
  const auto expect_cut_then_ramp = [&](std::uint16_t controller_flags, std::uint16_t thumb_flags, int ticks,
                                        double ramp_s, const char* what) {
    for (int k = 0; k < ticks; ++k) {
      const Tick cut = tick(controller_flags, thumb_flags);
      EXPECT_EQ(cut.force_N, 0.0) << what;
      EXPECT_EQ(cut.flags & (command_flags::kForceEnable | command_flags::kRamping), 0) << what;
    }
    double previous = 0.0;
    const int ramp_ticks = static_cast<int>(std::lround(ramp_s / kTick_s));
    for (int k = 0; k < ramp_ticks; ++k) {
      const Tick in = tick(0, manipulator_flags::kCalibrated);
      EXPECT_NE(in.flags & command_flags::kForceEnable, 0) << what;
      EXPECT_GT(in.force_N, previous) << what << " tick " << k;
      EXPECT_LE(in.force_N, previous + kForce_N * kTick_s / ramp_s + 1e-5) << what << " tick " << k;
      if (k + 1 < ramp_ticks) {
        EXPECT_NE(in.flags & command_flags::kRamping, 0) << what << " tick " << k;
      }
      previous = in.force_N;
    }
    EXPECT_NEAR(previous, kForce_N, 1e-5) << what;
    EXPECT_EQ(tick(0, manipulator_flags::kCalibrated).flags & command_flags::kRamping, 0) << what;
  };
  run_armed();
  expect_cut_then_ramp(controller_flags::kEmergencyStop, manipulator_flags::kCalibrated, 50,
                       config.safety.startup_ramp_s, "emergency stop");
  run_armed();
  expect_cut_then_ramp(0, 0, 50, config.safety.startup_ramp_s, "calibration lost");
  run_armed();
  expect_cut_then_ramp(controller_flags::kHostTimeout, manipulator_flags::kCalibrated, 10, config.safety.resume_ramp_s,
                       "host timeout");
  // a host timeout longer than resume_within_s (100 ms) ramps in over the start-up ramp
  run_armed();
  expect_cut_then_ramp(controller_flags::kHostTimeout, manipulator_flags::kCalibrated, 600,
                       config.safety.startup_ramp_s, "long host timeout");
}

TEST(DeviceBridgeTest, NonFiniteForceModelGivesZeroForceAndIsCounted) {
  auto dut = std::make_unique<DeviceBridge>(FastConfig());
  CommandBytes out{};
  ForceModel broken;
  broken.stiffness_W_N_per_m(1, 1) = std::numeric_limits<double>::quiet_NaN();
  for (int k = 1; k <= 100; ++k) {
    const double t = k * kTick_s;
    dut->OnStatusDatagram(Status(static_cast<std::uint32_t>(k), t), t);
    dut->SetForceModel(Manipulator::kThumb, k < 50 ? ConstantForce({0.2, 0.0, 0.0}) : broken, t,
                       dut->finger_state(Manipulator::kThumb).controller_sequence);
    dut->Tick(t, kTick_s, out);
  }
  const CommandFrame c = Decode(out);  // the frame is still valid: finite and encodable
  EXPECT_EQ(c.manipulators[0].force_D_N, Eigen::Vector3f::Zero());
  EXPECT_EQ(dut->safety(Manipulator::kThumb).counters().non_finite, 51u);
}

TEST(DeviceBridgeTest, UncalibratedFingerGetsNoForce) {
  auto dut = std::make_unique<DeviceBridge>(FastConfig());
  CommandBytes out{};
  for (int k = 1; k <= 100; ++k) {
    const double t = k * kTick_s;
    dut->OnStatusDatagram(Status(static_cast<std::uint32_t>(k), t, {0.0f, 0.0f, 0.0f}, 0), t);
    dut->SetForceModel(Manipulator::kThumb, ConstantForce({3.0, 0.0, 0.0}), t,
                       dut->finger_state(Manipulator::kThumb).controller_sequence);
    dut->Tick(t, kTick_s, out);
  }
  EXPECT_FALSE(dut->finger_state(Manipulator::kThumb).valid);
  EXPECT_EQ(Decode(out).manipulators[0].force_D_N, Eigen::Vector3f::Zero());
}

TEST(DeviceBridgeTest, ShutdownCommandsZeroWithTheShutdownFlag) {
  auto dut = std::make_unique<DeviceBridge>(FastConfig());
  CommandBytes out{};
  for (int k = 1; k <= 100; ++k) {
    const double t = k * kTick_s;
    dut->OnStatusDatagram(Status(static_cast<std::uint32_t>(k), t), t);
    dut->SetForceModel(Manipulator::kThumb, ConstantForce({0.3, 0.0, 0.0}), t,
                       dut->finger_state(Manipulator::kThumb).controller_sequence);
    dut->Tick(t, kTick_s, out);
  }
  ASSERT_NE(Decode(out).manipulators[0].force_D_N, Eigen::Vector3f::Zero());
  dut->RequestShutdown();
  dut->Tick(0.0202, kTick_s, out);
  const CommandFrame c = Decode(out);
  EXPECT_EQ(c.host_flags & host_flags::kShutdown, host_flags::kShutdown);
  EXPECT_EQ(c.manipulators[0].force_D_N, Eigen::Vector3f::Zero());
  EXPECT_EQ(c.manipulators[0].flags & command_flags::kForceEnable, 0);
}

TEST(DeviceBridgeTest, MeasuresMotionToForceLatencyAndRoundTrip) {
  auto dut = std::make_unique<DeviceBridge>(FastConfig());
  CommandBytes out{};
  for (int k = 1; k <= 1000; ++k) {
    const double t = k * kTick_s;
    StatusFrame f;
    f.sequence = static_cast<std::uint32_t>(k);
    f.controller_time_ns = static_cast<std::uint64_t>(k) * 200000u;
    // echo the command of the previous period's second tick (sent at t - 70 us)
    f.echo_host_sequence = k > 1 ? static_cast<std::uint32_t>(2 * (k - 1)) : 0;
    f.manipulators[0].flags = manipulator_flags::kCalibrated;
    StatusBytes b{};
    EncodeStatusFrame(f, b);
    dut->OnStatusDatagram(b, t);
    dut->Tick(t + 30e-6, kTick_s, out);   // force leaves 30 us after the packet arrived
    dut->Tick(t + 130e-6, kTick_s, out);  // a second tick from the same packet: not a new sample
  }
  const LatencyTracker& m2f = dut->motion_to_force_latency();
  EXPECT_EQ(m2f.count(), 1000u);
  EXPECT_NEAR(m2f.p50_s(), 31e-6, 1.01e-6);
  EXPECT_NEAR(m2f.max_s(), 30e-6, 1e-9);
  const LatencyTracker& rtt = dut->link_round_trip();
  EXPECT_EQ(rtt.count(), 999u);
  EXPECT_NEAR(rtt.max_s(), 70e-6, 1e-9);
  EXPECT_NEAR(rtt.p50_s(), 71e-6, 1.01e-6);
}

TEST(DeviceBridgeTest, InvalidConfigThrows) {
  DeviceBridgeConfig config;
  config.device_lost_after_s = 0.0;
  EXPECT_THROW(DeviceBridge{config}, std::invalid_argument);
  config = DeviceBridgeConfig{};
  config.X_WD.linear() *= 2.0;
  try {
    DeviceBridge dut(config);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("X_WD"), std::string::npos) << e.what();
  }
  config = DeviceBridgeConfig{};
  config.safety.peak_force_N = 30.0;
  EXPECT_THROW(DeviceBridge{config}, std::invalid_argument);
}

TEST(DeviceBridgeTest, WarmedUpTickDoesNotAllocate) {
  if (!testing::AllocationCountingSupported()) GTEST_SKIP() << "allocation counting unavailable";
  auto dut = std::make_unique<DeviceBridge>(FastConfig());
  CommandBytes out{};
  ForceModel model;
  model.stiffness_W_N_per_m = -1250.0 * Eigen::Matrix3d::Identity();
  for (int k = 1; k <= 100; ++k) {
    const double t = k * kTick_s;
    dut->OnStatusDatagram(Status(static_cast<std::uint32_t>(k), t), t);
    dut->SetForceModel(Manipulator::kThumb, model, t, dut->finger_state(Manipulator::kThumb).controller_sequence);
    dut->Tick(t, kTick_s, out);
  }
  const StatusBytes next = Status(101, 101 * kTick_s);
  testing::AllocationCounter counter;
  dut->OnStatusDatagram(next, 101 * kTick_s);
  dut->SetForceModel(Manipulator::kIndex, model, 101 * kTick_s, 101);
  dut->Tick(101 * kTick_s, kTick_s, out);
  EXPECT_EQ(counter.count(), 0);
}

}  // namespace
// A 5 kHz controller and models at 1 kHz answering the frame of `lag_s` ago, as a haptic link
// with that round trip delivers them.
class DelayedModelBridge {
 public:
  DelayedModelBridge() : dut_(std::make_unique<DeviceBridge>(FastConfig())) {}
  /// Runs until `until_s`; returns the largest thumb force commanded in the last `tail_s`.
  double Run(double until_s, double lag_s, double tail_s = 0.05) {
    double tail_max_N = 0.0;
    const auto lag_ticks = static_cast<std::uint32_t>(std::lround(lag_s / kTick_s));
    for (; t_ < until_s - 1e-12; t_ += kTick_s) {
      ++seq_;
      dut_->OnStatusDatagram(Status(seq_, t_), t_);
      if (seq_ % 5 == 0 && seq_ > lag_ticks) {
        dut_->SetForceModel(Manipulator::kThumb, ConstantForce({1.0, 0.0, 0.0}), t_, seq_ - lag_ticks);
      }
      dut_->Tick(t_, kTick_s, out_);
      if (t_ > until_s - tail_s) tail_max_N = std::max(tail_max_N, dut_->last_force_W_N(Manipulator::kThumb).norm());
    }
    return tail_max_N;
  }
  DeviceBridge& dut() { return *dut_; }
  double t_s() const { return t_; }

 private:
  std::unique_ptr<DeviceBridge> dut_;
  double t_ = kTick_s;
  std::uint32_t seq_ = 0;
  CommandBytes out_{};
};

TEST(DeviceBridgeTest, ModelsOlderThanTheLimitAreRefusedUntilTheLinkRecovers) {
  DelayedModelBridge bridge;
  const double limit_s = bridge.dut().config().max_model_age_s;
  // a 50 ms round trip is rendered
  EXPECT_NEAR(bridge.Run(0.5, 0.05), 1.0, 1e-6);
  EXPECT_FALSE(bridge.dut().link_too_slow());
  EXPECT_NEAR(bridge.dut().haptic_round_trip_estimate_s(), 0.05, 1e-3);
  // twice the limit: refused, and the force goes to zero within the watchdog's ramp
  const double slow_from_s = bridge.t_s();
  bridge.Run(slow_from_s + 2.0 * limit_s, 2.0 * limit_s);
  EXPECT_TRUE(bridge.dut().link_too_slow());
  EXPECT_EQ(bridge.Run(bridge.t_s() + 0.3, 2.0 * limit_s, 0.3), 0.0) << "a too slow link still pushed";
  EXPECT_EQ(bridge.dut().counters().slow_link_events, 1u);
  EXPECT_GT(bridge.dut().counters().slow_link_ticks, 0u);
  // fast again: not before recover_after_s of young models, then rendered again
  const double fast_from_s = bridge.t_s();
  const double recover_s = bridge.dut().config().recover_after_s;
  EXPECT_EQ(bridge.Run(fast_from_s + recover_s - 0.05, 0.05, recover_s - 0.1), 0.0) << "no hysteresis";
  EXPECT_NEAR(bridge.Run(fast_from_s + recover_s + 0.2, 0.05), 1.0, 1e-6);
  EXPECT_FALSE(bridge.dut().link_too_slow());
  EXPECT_EQ(bridge.dut().counters().slow_link_events, 1u);
}

TEST(DeviceBridgeTest, ARoundTripJustUnderTheLimitIsRenderedWithoutFlapping) {
  DelayedModelBridge bridge;
  const double lag_s = 0.95 * bridge.dut().config().max_model_age_s;
  EXPECT_NEAR(bridge.Run(1.0, lag_s), 1.0, 1e-6);
  EXPECT_EQ(bridge.dut().counters().slow_link_events, 0u);
  EXPECT_EQ(bridge.dut().counters().slow_link_ticks, 0u);
}

TEST(DeviceBridgeTest, ModelsAnsweringNoKnownFrameAreRefusedAndCounted) {
  auto dut = std::make_unique<DeviceBridge>(FastConfig());
  CommandBytes out{};
  for (int k = 1; k <= 500; ++k) {
    const double t = k * kTick_s;
    dut->OnStatusDatagram(Status(static_cast<std::uint32_t>(k), t), t);
    // a stale or forged basis: a frame the controller has not sent yet
    dut->SetForceModel(Manipulator::kThumb, ConstantForce({1.0, 0.0, 0.0}), t, 1'000'000);
    dut->Tick(t, kTick_s, out);
    ASSERT_EQ(dut->last_force_W_N(Manipulator::kThumb).norm(), 0.0);
  }
  EXPECT_EQ(dut->counters().models_unknown_basis, 500u);
}

TEST(DeviceBridgeTest, EndToEndLatencyIsTheRoundTripPlusTheWaitForTheNextTick) {
  DelayedModelBridge bridge;
  bridge.Run(1.0, 0.02);
  const LatencyTracker& e2e = bridge.dut().motion_to_force_end_to_end();
  ASSERT_GT(e2e.count(), 100u);
  EXPECT_GE(e2e.Percentile(0.5), 0.02 - 1e-6);
  EXPECT_LE(e2e.Percentile(0.5), 0.02 + 2 * kTick_s + 1e-4);
}

}  // namespace haptex::device
