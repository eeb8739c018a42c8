// The mock user's demo script (ScriptKind::kDemo): touch, pinch, stretch, rub, release.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>

#include "libs/device/mock_grab_controller.h"
#include "libs/device/mock_script.h"
#include "tests/support/allocation_counter.h"

namespace haptex::device {
namespace {

constexpr std::size_t kThumb = 0;
constexpr std::size_t kIndex = 1;
constexpr double kTick_s = 2e-4;  // the controller's 5 kHz

// The demo scene's values (launch/scenes/demo.textproto) as haptex-mock-grab maps them: W = D,
// hanging fabric centre, thumb on the user's side (+y in W), so the normal points along -y.
ScriptParams DemoScene() {
  ScriptParams p;
  p.kind = ScriptKind::kDemo;
  p.fabric_point_D_m = {0.0, 0.0, -0.10};
  p.fabric_normal_D = {0.0, -1.0, 0.0};
  p.speed_m_per_s = 0.05;
  p.hold_s = 0.5;
  p.press_depth_m = 2.0 / 300.0;  // squeeze 2 N over the user's 300 N/m grip
  p.stretch_D_m = {0.01, 0.0, 0.0};
  p.rub_amplitude_m = 0.01;
  p.pad_offset_m = {0.008, 0.008};
  p.Validate();
  return p;
}

// How far finger i's pad is past the fabric plane (negative: a gap), on its own side.
double PadDepth(const ScriptParams& p, std::size_t i, const Eigen::Vector3d& p_D_m) {
  const double side = i == kThumb ? 1.0 : -1.0;  // thumb presses along +n, index along -n
  return side * (p_D_m - p.fabric_point_D_m).dot(p.fabric_normal_D) + p.pad_offset_m[i];
}

class DemoScriptTest : public ::testing::TestWithParam<ScriptParams> {};

// Sampled at the controller's rate: no step longer than the speed allows, velocities bounded by
// the speed and equal to the positions' derivative, everything finite.
TEST_P(DemoScriptTest, TrajectoryIsContinuousWithBoundedSpeed) {
  const ScriptParams p = GetParam();
  const double end_s = DemoDuration(p) + 0.5;
  FingerTargets previous = EvaluateScript(p, 0.0);
  double peak_speed = 0.0;
  for (double t = kTick_s; t <= end_s; t += kTick_s) {
    const FingerTargets now = EvaluateScript(p, t);
    for (std::size_t i = 0; i < kManipulatorCount; ++i) {
      ASSERT_TRUE(now.p_D_m[i].allFinite() && now.v_D_m_per_s[i].allFinite()) << "t " << t;
      const double step_m = (now.p_D_m[i] - previous.p_D_m[i]).norm();
      ASSERT_LE(step_m, p.speed_m_per_s * kTick_s * (1.0 + 1e-6)) << "jump at t " << t << " finger " << i;
      const double speed = now.v_D_m_per_s[i].norm();
      ASSERT_LE(speed, p.speed_m_per_s * (1.0 + 1e-9)) << "t " << t << " finger " << i;
      peak_speed = std::max(peak_speed, speed);
      // velocity against a central difference (the user damper relies on it)
      const double h = 1e-6;
      const Eigen::Vector3d numeric = (EvaluateScript(p, t + h).p_D_m[i] - EvaluateScript(p, t - h).p_D_m[i]) / (2 * h);
      ASSERT_LT((numeric - now.v_D_m_per_s[i]).norm(), 1e-4) << "t " << t << " finger " << i;
    }
    previous = now;
  }
  EXPECT_GT(peak_speed, 0.99 * p.speed_m_per_s);  // the moves do reach the speed
}

// The phases come in order, each once, and each does what it says.
TEST_P(DemoScriptTest, VisitsThePhasesInOrder) {
  const ScriptParams p = GetParam();
  const double end_s = DemoDuration(p);
  int expected = 0;
  double rub_max = 0.0, rub_min = 0.0;
  for (double t = 0.0; t <= end_s + 0.5; t += kTick_s) {
    const DemoPhase phase = DemoPhaseAt(p, t);
    const int index = static_cast<int>(phase);
    ASSERT_GE(index, expected) << DemoPhaseName(phase) << " came back at t " << t;
    // settle and touch are pauses only: without pauses they take no time
    ASSERT_LE(index, expected + (p.hold_s > 0.0 ? 1 : 2)) << "skipped to " << DemoPhaseName(phase) << " at t " << t;
    expected = index;
    const FingerTargets f = EvaluateScript(p, t);
    const double thumb = PadDepth(p, kThumb, f.p_D_m[kThumb]);
    const double index_depth = PadDepth(p, kIndex, f.p_D_m[kIndex]);
    switch (phase) {
      case DemoPhase::kSettle:
      case DemoPhase::kApproach:
        EXPECT_NEAR(index_depth, -p.rest_gap_m, 1e-12) << "the index waits at t " << t;
        break;
      case DemoPhase::kTouch:  // one finger on the fabric
        EXPECT_NEAR(thumb, p.touch_depth_m, 1e-12);
        EXPECT_NEAR(index_depth, -p.rest_gap_m, 1e-12);
        break;
      case DemoPhase::kRub: {
        // still pinched; only the thumb slides, along rub_direction_D
        EXPECT_NEAR(thumb, p.press_depth_m, 1e-12);
        EXPECT_NEAR(index_depth, p.press_depth_m, 1e-12);
        const Eigen::Vector3d slide = f.p_D_m[kThumb] - EvaluateScript(p, 0.0).p_D_m[kThumb] - p.stretch_D_m;
        const double along = slide.dot(p.rub_direction_D);
        rub_max = std::max(rub_max, along);
        rub_min = std::min(rub_min, along);
        break;
      }
      default:
        break;
    }
  }
  EXPECT_EQ(expected, static_cast<int>(DemoPhase::kDone));
  EXPECT_NEAR(rub_max, p.rub_amplitude_m, 1e-8);
  EXPECT_NEAR(rub_min, -p.rub_amplitude_m, 1e-8);
  if (p.hold_s == 0.0) return;

  // the ends of the squeeze and of the stretch (held), just before the next move
  const auto last_of = [&p, end_s](DemoPhase phase) {
    double last = -1.0;
    for (double t = 0.0; t <= end_s; t += 1e-3) {
      if (DemoPhaseAt(p, t) == phase) last = t;
    }
    return EvaluateScript(p, last);
  };
  const FingerTargets pinched = last_of(DemoPhase::kPinch);
  EXPECT_NEAR(PadDepth(p, kThumb, pinched.p_D_m[kThumb]), p.press_depth_m, 1e-12);
  EXPECT_NEAR(PadDepth(p, kIndex, pinched.p_D_m[kIndex]), p.press_depth_m, 1e-12);
  const FingerTargets stretched = last_of(DemoPhase::kStretch);
  for (std::size_t i = 0; i < kManipulatorCount; ++i) {
    EXPECT_TRUE((stretched.p_D_m[i] - pinched.p_D_m[i]).isApprox(p.stretch_D_m, 1e-9)) << i;
  }
}

// At the end both fingers are back at rest, rest_gap_m off the fabric on their own sides.
TEST_P(DemoScriptTest, EndsWithBothFingersRetracted) {
  const ScriptParams p = GetParam();
  const FingerTargets start = EvaluateScript(p, 0.0);
  for (const double after_s : {0.0, 1.0, 100.0}) {
    const FingerTargets end = EvaluateScript(p, DemoDuration(p) + after_s);
    for (std::size_t i = 0; i < kManipulatorCount; ++i) {
      EXPECT_NEAR(PadDepth(p, i, end.p_D_m[i]), -p.rest_gap_m, 1e-12) << i;
      EXPECT_TRUE(end.p_D_m[i].isApprox(start.p_D_m[i], 1e-12)) << i;
      EXPECT_EQ(end.v_D_m_per_s[i], Eigen::Vector3d::Zero()) << i;
    }
  }
  EXPECT_EQ(DemoPhaseAt(p, DemoDuration(p) + 1e-9), DemoPhase::kDone);
}

ScriptParams Defaults() {
  ScriptParams p;
  p.kind = ScriptKind::kDemo;
  return p;
}

ScriptParams Tilted() {
  // an oblique fabric, fast user, no pauses, one rub cycle across the stretch
  ScriptParams p = DemoScene();
  p.fabric_point_D_m = {0.03, 0.02, -0.05};
  p.fabric_normal_D = Eigen::Vector3d(0.3, -1.0, 0.2).normalized();
  p.rub_direction_D = p.fabric_normal_D.unitOrthogonal();
  p.stretch_D_m = 0.01 * p.fabric_normal_D.cross(p.rub_direction_D);  // in the fabric's plane
  p.speed_m_per_s = 0.3;
  p.hold_s = 0.0;
  p.rub_cycles = 1;
  p.pad_offset_m = {0.006, 0.010};
  return p;
}

std::string ParamName(const ::testing::TestParamInfo<ScriptParams>& info) {
  constexpr std::array<const char*, 3> kNames = {"scene", "defaults", "tilted"};
  return kNames.at(info.index);
}

INSTANTIATE_TEST_SUITE_P(Params, DemoScriptTest, ::testing::Values(DemoScene(), Defaults(), Tilted()), ParamName);

TEST(DemoScriptTest, SceneTimings) {
  // at the demo scene's values, in seconds: settle 0.5, approach 1.2 (32 mm at a 0.05 m/s peak),
  // touch 0.5, pinch 1.375 + 0.5, stretch 0.375 + 0.5, rub 3.0 + 0.5 (8 x 10 mm), release
  // 1.375 + 0.5, retract 0.375
  const ScriptParams p = DemoScene();
  EXPECT_NEAR(DemoDuration(p), 10.7, 1e-9);
  EXPECT_EQ(DemoPhaseAt(p, 0.49), DemoPhase::kSettle);
  EXPECT_EQ(DemoPhaseAt(p, 1.69), DemoPhase::kApproach);
  EXPECT_EQ(DemoPhaseAt(p, 1.71), DemoPhase::kTouch);
  EXPECT_EQ(DemoPhaseAt(p, 2.21), DemoPhase::kPinch);
  EXPECT_EQ(DemoPhaseAt(p, 4.09), DemoPhase::kStretch);
  EXPECT_EQ(DemoPhaseAt(p, 4.96), DemoPhase::kRub);
  EXPECT_EQ(DemoPhaseAt(p, 8.46), DemoPhase::kRelease);
  EXPECT_EQ(DemoPhaseAt(p, 10.34), DemoPhase::kRetract);
  EXPECT_EQ(DemoPhaseAt(p, 10.71), DemoPhase::kDone);
  // the thumb is on the user's side (+y in W) and the index behind the fabric
  const FingerTargets start = EvaluateScript(p, 0.0);
  EXPECT_GT(start.p_D_m[kThumb].y(), p.fabric_point_D_m.y());
  EXPECT_LT(start.p_D_m[kIndex].y(), p.fabric_point_D_m.y());
  EXPECT_NEAR(start.p_D_m[kThumb].y(), 0.038, 1e-12);  // rest gap 30 mm + pad offset 8 mm
}

TEST(DemoScriptTest, InvalidDemoParamsThrow) {
  ScriptParams p = Defaults();
  p.speed_m_per_s = 0.0;
  EXPECT_THROW(p.Validate(), std::invalid_argument);
  p = Defaults();
  p.rub_cycles = 0;
  EXPECT_THROW(p.Validate(), std::invalid_argument);
  p = Defaults();
  p.pad_offset_m[kIndex] = -0.001;
  try {
    p.Validate();
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("pad_offset_m"), std::string::npos) << e.what();
  }
}

TEST(DemoScriptTest, EvaluatingDoesNotAllocate) {
  if (!testing::AllocationCountingSupported()) GTEST_SKIP() << "allocation counting unavailable";
  const ScriptParams p = DemoScene();
  double sum = 0.0;
  testing::AllocationCounter counter;
  for (double t = 0.0; t < 12.0; t += 0.01) {
    sum += EvaluateScript(p, t).p_D_m[kThumb].x() + static_cast<double>(DemoPhaseAt(p, t));
  }
  EXPECT_EQ(counter.count(), 0);
  EXPECT_TRUE(std::isfinite(sum));
}

// The whole demo on the mock controller in closed loop with a host that renders the fabric as
// a stiff wall on each finger's side: finite throughout, fingers follow, end at rest, no force.
TEST(DemoScriptTest, MockControllerRunsTheWholeDemoWithoutNaN) {
  const ScriptParams script = DemoScene();
  MockGrabController dut(MockControllerConfig{}, script);
  constexpr double kWall_N_per_m = 1000.0;
  std::array<std::byte, kStatusFrameSize> status{};
  std::array<std::byte, kCommandFrameSize> command{};
  const int ticks = static_cast<int>(std::ceil((DemoDuration(script) + 1.0) / kTick_s));
  double peak_force_N = 0.0;
  for (int k = 0; k < ticks; ++k) {
    const double t = k * kTick_s;
    // host: push each pad back out of the fabric plane
    CommandFrame c;
    c.sequence = static_cast<std::uint32_t>(k + 1);
    for (std::size_t i = 0; i < kManipulatorCount; ++i) {
      const Eigen::Vector3d& p_D = dut.finger(static_cast<Manipulator>(i)).p_D_m;
      const double depth_m = std::max(0.0, PadDepth(script, i, p_D));
      const double outward = i == kThumb ? -1.0 : 1.0;
      const Eigen::Vector3d force_D_N = outward * kWall_N_per_m * depth_m * script.fabric_normal_D;
      c.manipulators[i].force_D_N = force_D_N.cast<float>();
      c.manipulators[i].flags = command_flags::kForceEnable;
      peak_force_N = std::max(peak_force_N, kWall_N_per_m * depth_m);
    }
    EncodeCommandFrame(c, command);
    ASSERT_EQ(dut.OnCommandDatagram(command, t), FrameError::kNone) << "t " << t;
    dut.Step(t, kTick_s, status);

    StatusFrame f;
    ASSERT_EQ(DecodeStatusFrame(status, GrabValueLimits{}, &f), FrameError::kNone) << "t " << t;
    for (std::size_t i = 0; i < kManipulatorCount; ++i) {
      const MockFingerState& s = dut.finger(static_cast<Manipulator>(i));
      ASSERT_TRUE(s.p_D_m.allFinite() && s.v_D_m_per_s.allFinite() && s.applied_force_D_N.allFinite())
          << "t " << t << " finger " << i;
      ASSERT_TRUE(f.manipulators[i].p_D_m.allFinite() && f.manipulators[i].force_D_N.allFinite());
      EXPECT_EQ(s.flags & manipulator_flags::kWorkspaceLimit, 0) << "t " << t;
      // the user follows the script within a few millimetres (the wall holds the pads back)
      EXPECT_LT((s.p_D_m - EvaluateScript(script, t + kTick_s).p_D_m[i]).norm(), 0.01) << "t " << t;
    }
  }
  // the pinch was felt (about the squeeze force, shared between the user spring and the wall)
  EXPECT_GT(peak_force_N, 1.0);
  EXPECT_LT(peak_force_N, 3.0);
  const FingerTargets rest = EvaluateScript(script, 0.0);
  for (std::size_t i = 0; i < kManipulatorCount; ++i) {
    const MockFingerState& s = dut.finger(static_cast<Manipulator>(i));
    EXPECT_LT((s.p_D_m - rest.p_D_m[i]).norm(), 0.5e-3) << i;
    EXPECT_LT(s.applied_force_D_N.norm(), 1e-6) << i;
  }
}

}  // namespace
}  // namespace haptex::device
