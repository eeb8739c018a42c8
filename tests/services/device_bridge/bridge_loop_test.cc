// BridgeLoop in process against the mock controller's loop (MockGrabLoop), the two exchanging
// GRAB datagrams directly: the StatusFrames move the fingers and the FingerStates the bridge sends,
// the ForceModels it receives reach the controller as commanded force after the start-up ramp,
// Control holds force at zero, strangers and malformed models are counted; and no allocation in
// its warmed-up tick.

#include "services/device_bridge/bridge_loop.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "libs/codec/message_conversion.h"
#include "services/mock_grab/mock_grab_loop.h"
#include "tests/support/allocation_counter.h"
#include "tests/support/captured_outbox.h"
#include "tests/support/wrap_envelope.h"

namespace haptex::device_bridge {
namespace {

using V = Eigen::Vector3d;
constexpr services::PeerId kLocal = 0, kGlobal = 1;
constexpr double kDt = 0.0002;

v1::ForceModel ThumbForce(double force_z_N, v1::Finger finger = v1::FINGER_THUMB, int stiffness_values = 9) {
  v1::ForceModel model;
  v1::FingerForceModel* m = model.add_fingers();
  m->set_finger(finger);
  m->mutable_f0_w_n()->set_z(force_z_N);
  for (int i = 0; i < stiffness_values; ++i) m->add_stiffness_w_n_per_m(0.0);
  m->set_ttl_s(0.010);
  return model;
}

// The tests command constant forces: a constant force field does work on the finger it moves,
// which the passivity controller damps (it has its own tests), so it is off here.
BridgeLoopConfig ConstantForceConfig() {
  BridgeLoopConfig config;
  config.bridge.passivity.enabled = false;
  return config;
}

class BridgeLoopTest : public ::testing::Test {
 protected:
  BridgeLoopTest()
      : health_("device_bridge"),
        mock_health_("mock_grab"),
        bridge_(ConstantForceConfig(), {kLocal, kGlobal, std::nullopt}, &health_),
        mock_(device::MockControllerConfig{}, device::ScriptParams{}, nullptr, 0, &mock_health_) {}

  // One 5 kHz period of both: the controller steps and reports, the bridge reads, computes and
  // commands, the controller reads the command. A ForceModel, when given, arrives this tick. The
  // bridge is told `bridge_dt_s` passed since its last tick (longer: it stalled).
  void Tick(services::Outbox& out, const v1::ForceModel* model = nullptr, double bridge_dt_s = kDt) {
    const double t = tick_ * kDt;
    mock_.Update(t, kDt);
    bridge_.ReadController(mock_.status(), t, t, true);
    if (model != nullptr) {
      // computed from the newest finger states, as local_contact does
      v1::ForceModel answered = *model;
      answered.set_based_on_controller_sequence(
          bridge_.bridge().finger_state(device::Manipulator::kThumb).controller_sequence);
      bridge_.Read(haptex::testing::WrapEnvelope(answered, ++sequence_), t);
    }
    bridge_.Update(t, bridge_dt_s);
    bridge_.Write(out);
    mock_.ReadHost(bridge_.command(), t, true);
    ++tick_;
  }
  double CommandedThumbZ() const {
    return mock_.controller().finger(device::Manipulator::kThumb).commanded_force_D_N.z();
  }

  runtime::HealthReporter health_, mock_health_;
  BridgeLoop bridge_;
  mock_grab::MockGrabLoop mock_;
  std::uint64_t tick_ = 0, sequence_ = 0;
};

TEST_F(BridgeLoopTest, FingerStatesFollowTheControllerAtTheirRates) {
  haptex::testing::CapturedOutbox out;
  for (int k = 0; k < 500; ++k) Tick(out);  // 0.1 s
  const auto local = out.Of<v1::FingerStates>(kLocal);
  const auto global = out.Of<v1::FingerStates>(kGlobal);
  EXPECT_EQ(local.size(), 100u);  // 1 kHz
  EXPECT_EQ(global.size(), 10u);  // 100 Hz
  const v1::FingerStates& last = local.back();
  EXPECT_TRUE(last.device_ok());
  EXPECT_GT(last.controller_sequence(), 400u);
  ASSERT_EQ(last.fingers_size(), 2);
  EXPECT_EQ(last.fingers(0).finger(), v1::FINGER_THUMB);
  const V reported = codec::ToEigen(last.fingers(0).position_w_m());
  const V truth = mock_.controller().finger(device::Manipulator::kThumb).p_D_m;  // X_WD = identity
  EXPECT_LT((reported - truth).norm(), 0.001) << "within a few quantisation steps and 1 ms of motion";
}

TEST_F(BridgeLoopTest, ForceModelsReachTheControllerAfterTheRampAndControlHoldsThemAtZero) {
  haptex::testing::CapturedOutbox out;
  out.capture = false;
  const v1::ForceModel one_newton = ThumbForce(1.0);
  for (int k = 0; k < 3000; ++k) Tick(out, k % 5 == 0 ? &one_newton : nullptr);  // 0.6 s: past the 0.5 s ramp
  EXPECT_NEAR(CommandedThumbZ(), 1.0, 1e-3);
  bridge_.OnControl(v1::Control::COMMAND_ZERO_FORCE);
  for (int k = 0; k < 50; ++k) Tick(out, k % 5 == 0 ? &one_newton : nullptr);
  EXPECT_EQ(CommandedThumbZ(), 0.0);
  bridge_.OnControl(v1::Control::COMMAND_ENABLE_FORCE);
  for (int k = 0; k < 3000; ++k) Tick(out, k % 5 == 0 ? &one_newton : nullptr);
  EXPECT_NEAR(CommandedThumbZ(), 1.0, 1e-3);
  // models stop: the watchdog ramps to zero
  for (int k = 0; k < 200; ++k) Tick(out);
  EXPECT_EQ(CommandedThumbZ(), 0.0);
  // shutdown: zero at once, whatever the models say
  for (int k = 0; k < 3000; ++k) Tick(out, k % 5 == 0 ? &one_newton : nullptr);
  bridge_.RequestShutdown();
  Tick(out, &one_newton);
  Tick(out, &one_newton);
  EXPECT_EQ(CommandedThumbZ(), 0.0);
}

// A model asking for more than the device's continuous force (6 N RMS over about 1 s): the safety
// stage holds it down once the mean has filled, and every such tick is counted in Health, as
// are the peak limit's (20 N) for a model beyond the device's peak.
TEST_F(BridgeLoopTest, ForcesTheDeviceCannotGiveAreHeldDownAndCounted) {
  haptex::testing::CapturedOutbox out;
  out.capture = false;
  const auto counter = [this](const std::string& name) -> std::int64_t {
    for (const auto& c : health_.Build(0.0).counters()) {
      if (c.name() == name) return static_cast<std::int64_t>(c.value());
    }
    return -1;
  };
  const v1::ForceModel five_newtons = ThumbForce(5.0);
  for (int k = 0; k < 15000; ++k) Tick(out, k % 5 == 0 ? &five_newtons : nullptr);  // 3 s
  EXPECT_NEAR(CommandedThumbZ(), 5.0, 1e-3) << "within the device's rating: untouched";
  EXPECT_EQ(counter("continuous_limited_ticks"), 0);
  EXPECT_EQ(counter("peak_limited_ticks"), 0);
  const v1::ForceModel nine_newtons = ThumbForce(9.0);
  for (int k = 0; k < 15000; ++k) Tick(out, k % 5 == 0 ? &nine_newtons : nullptr);  // 3 s more
  EXPECT_LT(CommandedThumbZ(), 6.0 + 1e-6) << "held to the continuous force";
  EXPECT_GT(counter("continuous_limited_ticks"), 5000);
  const v1::ForceModel fifty_newtons = ThumbForce(50.0);
  for (int k = 0; k < 50; ++k) Tick(out, k % 5 == 0 ? &fifty_newtons : nullptr);
  EXPECT_EQ(counter("peak_limited_ticks"), 50) << "every tick of the 50 N model";
  EXPECT_LE(CommandedThumbZ(), 6.0 + 1e-6);
}

// The bridge's process stalls while the controller runs on. Shorter than the controller's host
// timeout, the controller holds the last command and says so: the force it applies never drops.
// Longer, it times out; the bridge sees the flag and ramps in again from zero, never jumping.
TEST_F(BridgeLoopTest, ABridgeStallTheControllerHeldThroughDoesNotDropTheForce) {
  haptex::testing::CapturedOutbox out;
  out.capture = false;
  const v1::ForceModel one_newton = ThumbForce(1.0);
  for (int k = 0; k < 3000; ++k) Tick(out, k % 5 == 0 ? &one_newton : nullptr);  // past the start-up ramp
  ASSERT_NEAR(CommandedThumbZ(), 1.0, 1e-3);
  auto stall = [&](int ticks) {
    double lowest_N = CommandedThumbZ();
    for (int k = 0; k < ticks; ++k) {  // the controller steps alone
      mock_.Update(static_cast<double>(tick_) * kDt, kDt);
      lowest_N = std::min(lowest_N, CommandedThumbZ());
      ++tick_;
    }
    return lowest_N;
  };
  // the bridge wakes: reads the newest status, one long tick
  auto catch_up = [&](double stall_s) { Tick(out, &one_newton, stall_s); };

  EXPECT_NEAR(stall(22), 1.0, 1e-3) << "4.4 ms: the controller holds the last command";
  catch_up(0.0046);
  EXPECT_NEAR(CommandedThumbZ(), 1.0, 1e-3) << "the bridge goes on from it";
  for (int k = 0; k < 100; ++k) {
    Tick(out, k % 5 == 0 ? &one_newton : nullptr);
    EXPECT_NEAR(CommandedThumbZ(), 1.0, 1e-3) << "tick " << k << " after the stall";
  }
  EXPECT_EQ(bridge_.bridge().counters().tick_gaps_held, 1u) << "the controller's answer confirmed it held";
  EXPECT_EQ(bridge_.bridge().counters().tick_gap_disarms, 0u);

  EXPECT_EQ(stall(40), 0.0) << "8 ms: the controller timed out";
  catch_up(0.0082);
  EXPECT_EQ(CommandedThumbZ(), 0.0) << "the bridge saw HOST_TIMEOUT: no jump back to 1 N";
  EXPECT_EQ(bridge_.bridge().counters().tick_gap_disarms, 1u);
  // the resumed force (the model's at the proxy and the return spring, at most the resume bound
  // max(1.1 x 1 N, 1 N + 0.3 N)) ramps in over 5 ms
  const double bound_N = 1.3;
  double previous_N = 0.0;
  for (int k = 0; k < 100; ++k) {
    Tick(out, k % 5 == 0 ? &one_newton : nullptr);
    EXPECT_LE(CommandedThumbZ(), previous_N + bound_N * kDt / 0.005 + 1e-6) << "resume ramp, tick " << k;
    EXPECT_LE(CommandedThumbZ(), bound_N + 1e-6) << "tick " << k;
    previous_N = CommandedThumbZ();
  }
  EXPECT_NEAR(CommandedThumbZ(), 1.0, 1e-3);
}

TEST_F(BridgeLoopTest, StrangersAndMalformedModelsAreCounted) {
  haptex::testing::CapturedOutbox out;
  Tick(out);
  bridge_.ReadController(mock_.status(), 0.0, 0.0, false);
  const v1::ForceModel unknown_finger = ThumbForce(1.0, v1::FINGER_UNSPECIFIED);
  const v1::ForceModel three_values = ThumbForce(1.0, v1::FINGER_THUMB, 3);
  Tick(out, &unknown_finger);
  Tick(out, &three_values);
  EXPECT_EQ(bridge_.foreign_frames(), 1u);
  EXPECT_EQ(bridge_.bad_models(), 2u);
  std::uint64_t strangers = 0, rejected = 0;
  for (const auto& c : health_.Build(0.0).counters()) {
    if (c.name() == "status_frames_from_strangers") strangers = c.value();
    if (c.name() == "force_models_rejected") rejected = c.value();
  }
  EXPECT_EQ(strangers, 1u);
  EXPECT_EQ(rejected, 2u);
}

// docs/grab-protocol.md section 6 counts every rejected frame under its reason: each FrameError has
// its own Health counter on both sides (and so in summary.json), and so do out-of-order frames.
TEST_F(BridgeLoopTest, RejectedFramesAreCountedPerReasonOnBothSides) {
  haptex::testing::CapturedOutbox out;
  for (int k = 0; k < 10; ++k) Tick(out);
  std::array<std::byte, device::kStatusFrameSize> corrupt{};
  std::copy(mock_.status().begin(), mock_.status().end(), corrupt.begin());
  corrupt[30] ^= std::byte{1};
  bridge_.ReadController(corrupt, 0.002, 0.002, true);
  bridge_.ReadController(mock_.status().first(10), 0.002, 0.002, true);
  bridge_.ReadController(mock_.status(), 0.002, 0.002, true);  // the same frame again: not newer
  std::array<std::byte, device::kCommandFrameSize> bad_command{};
  std::copy(bridge_.command().begin(), bridge_.command().end(), bad_command.begin());
  bad_command[0] ^= std::byte{1};
  mock_.ReadHost(bad_command, 0.002, true);
  mock_.ReadHost(bridge_.command(), 0.002, true);  // already taken: not newer
  Tick(out);
  mock_.Write(out);
  const auto counter = [](runtime::HealthReporter& health, const std::string& name) -> std::int64_t {
    for (const auto& c : health.Build(0.0).counters()) {
      if (c.name() == name) return static_cast<std::int64_t>(c.value());
    }
    return -1;
  };
  for (std::size_t e = 1; e < device::kFrameErrorCount; ++e) {
    const std::string reason(device::FrameErrorName(static_cast<device::FrameError>(e)));
    EXPECT_GE(counter(health_, "status_frames_rejected_" + reason), 0) << reason;
    EXPECT_GE(counter(mock_health_, "commands_rejected_" + reason), 0) << reason;
  }
  EXPECT_EQ(counter(health_, "status_frames_rejected_bad_checksum"), 1);
  EXPECT_EQ(counter(health_, "status_frames_rejected_too_short"), 1);
  EXPECT_EQ(counter(health_, "status_frames_rejected"), 2);
  EXPECT_EQ(counter(health_, "status_frames_out_of_order"), 1);
  EXPECT_EQ(counter(mock_health_, "commands_rejected_bad_magic"), 1);
  EXPECT_EQ(counter(mock_health_, "commands_out_of_order"), 1);
  // a frame not newer is valid but not taken: not counted as accepted
  EXPECT_EQ(counter(health_, "status_frames_accepted"), 11);
  EXPECT_EQ(counter(mock_health_, "commands_accepted"), 11);
}

TEST_F(BridgeLoopTest, WarmedUpTickDoesNotAllocate) {
  if (!haptex::testing::AllocationCountingSupported()) GTEST_SKIP() << "allocation counting is off in this build";
  haptex::testing::CapturedOutbox out;
  out.capture = false;
  for (int k = 0; k < 1000; ++k) Tick(out);
  v1::ForceModel answered = ThumbForce(1.0);
  answered.set_based_on_controller_sequence(
      bridge_.bridge().finger_state(device::Manipulator::kThumb).controller_sequence);
  const v1::Envelope model = haptex::testing::WrapEnvelope(answered, 1);
  haptex::testing::AllocationCounter counter;
  for (int k = 0; k < 1000; ++k) {
    const double t = static_cast<double>(tick_++) * kDt;
    mock_.Update(t, kDt);
    bridge_.ReadController(mock_.status(), t, t, true);
    bridge_.Read(model, t);
    bridge_.Update(t, kDt);
    bridge_.Write(out);
    mock_.ReadHost(bridge_.command(), t, true);
    mock_.Write(out);
  }
  EXPECT_EQ(counter.count(), 0);
  EXPECT_EQ(out.Count<v1::FingerStates>(), 2u * 200u + 2u * 20u);
}

}  // namespace
}  // namespace haptex::device_bridge
