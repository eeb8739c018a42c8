#include "libs/device/mock_script.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace haptex::device {
namespace {

constexpr std::size_t kThumb = 0;
constexpr std::size_t kIndex = 1;

ScriptParams Params(ScriptKind kind) {
  ScriptParams p;
  p.kind = kind;
  if (kind == ScriptKind::kPlayback) {
    p.trajectory = {{0.0, {0.0, -0.02, 0.0}, {0.0, 0.02, 0.0}},
                    {1.0, {0.01, -0.01, 0.0}, {0.0, 0.01, 0.02}},
                    {2.0, {0.01, -0.01, 0.0}, {0.0, 0.01, 0.02}}};
  }
  return p;
}

class EveryScriptTest : public ::testing::TestWithParam<ScriptKind> {};

// Velocities are the time derivatives of positions (the user damper relies on this).
TEST_P(EveryScriptTest, VelocityMatchesPositionDerivative) {
  const ScriptParams p = Params(GetParam());
  p.Validate();
  const double h = 1e-6;
  for (double t = 0.013; t < 4.0; t += 0.0371) {
    const FingerTargets a = EvaluateScript(p, t - h);
    const FingerTargets b = EvaluateScript(p, t + h);
    const FingerTargets m = EvaluateScript(p, t);
    for (std::size_t i = 0; i < kManipulatorCount; ++i) {
      const Eigen::Vector3d numeric = (b.p_D_m[i] - a.p_D_m[i]) / (2 * h);
      EXPECT_LT((numeric - m.v_D_m_per_s[i]).norm(), 1e-4) << "t " << t << " finger " << i;
      EXPECT_TRUE(m.p_D_m[i].allFinite());
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Scripts, EveryScriptTest,
                         ::testing::Values(ScriptKind::kIdle, ScriptKind::kApproachAndTouch,
                                           ScriptKind::kGraspAndSqueeze, ScriptKind::kPinchAndStretch, ScriptKind::kRub,
                                           ScriptKind::kLift, ScriptKind::kPlayback, ScriptKind::kDemo,
                                           ScriptKind::kFold));

TEST(MockScriptTest, FingersStartAtRestOnTheirSides) {
  const FingerTargets t0 = EvaluateScript(Params(ScriptKind::kGraspAndSqueeze), 0.0);
  EXPECT_TRUE(t0.p_D_m[kThumb].isApprox(Eigen::Vector3d(0.0, -0.03, 0.0)));
  EXPECT_TRUE(t0.p_D_m[kIndex].isApprox(Eigen::Vector3d(0.0, 0.03, 0.0)));
  const FingerTargets idle = EvaluateScript(Params(ScriptKind::kIdle), 10.0);
  EXPECT_TRUE(idle.p_D_m[kThumb].isApprox(t0.p_D_m[kThumb]));
  EXPECT_EQ(idle.v_D_m_per_s[kThumb], Eigen::Vector3d::Zero());
}

TEST(MockScriptTest, GraspPressesThroughThePlane) {
  const ScriptParams p = Params(ScriptKind::kGraspAndSqueeze);
  const FingerTargets t = EvaluateScript(p, 5.0);
  EXPECT_NEAR(t.p_D_m[kThumb].y(), p.press_depth_m, 1e-12);   // thumb pushed towards +y
  EXPECT_NEAR(t.p_D_m[kIndex].y(), -p.press_depth_m, 1e-12);  // index towards -y
}

TEST(MockScriptTest, TouchMovesOnlyOneFinger) {
  ScriptParams p = Params(ScriptKind::kApproachAndTouch);
  p.touch_finger = Manipulator::kIndex;
  const FingerTargets t = EvaluateScript(p, 5.0);
  EXPECT_NEAR(t.p_D_m[kThumb].y(), -p.rest_gap_m, 1e-12);
  EXPECT_NEAR(t.p_D_m[kIndex].y(), -p.press_depth_m, 1e-12);
}

TEST(MockScriptTest, StretchLiftAndRubMoveAfterTheGrasp) {
  const double grasped_s = 1.3;
  ScriptParams p = Params(ScriptKind::kPinchAndStretch);
  FingerTargets t = EvaluateScript(p, grasped_s + p.stretch_duration_s + 0.1);
  EXPECT_NEAR(t.p_D_m[kThumb].x(), p.stretch_D_m.x(), 1e-12);
  EXPECT_NEAR(t.p_D_m[kIndex].x(), p.stretch_D_m.x(), 1e-12);

  p = Params(ScriptKind::kLift);
  t = EvaluateScript(p, grasped_s + p.lift_duration_s + 0.1);
  EXPECT_NEAR(t.p_D_m[kThumb].z(), p.lift_height_m, 1e-12);

  p = Params(ScriptKind::kRub);
  t = EvaluateScript(p, grasped_s + 0.125);  // quarter period at 2 Hz: full amplitude
  EXPECT_NEAR(t.p_D_m[kThumb].x(), p.rub_amplitude_m, 1e-9);
  EXPECT_NEAR(t.p_D_m[kIndex].x(), 0.0, 1e-12);
}

// A scene with the index alone (touch_finger) rubs with it: the thumb it does not simulate stays put.
TEST(MockScriptTest, RubStrokesTheTouchFinger) {
  const double grasped_s = 1.3;
  ScriptParams p = Params(ScriptKind::kRub);
  p.touch_finger = Manipulator::kIndex;
  const FingerTargets t = EvaluateScript(p, grasped_s + 0.125);
  EXPECT_NEAR(t.p_D_m[kIndex].x(), p.rub_amplitude_m, 1e-9);
  EXPECT_NEAR(t.p_D_m[kThumb].x(), 0.0, 1e-12);
  EXPECT_NEAR(t.p_D_m[kIndex].y(), -p.press_depth_m, 1e-12) << "still pressing";
}

TEST(MockScriptTest, PlaybackInterpolatesAndHoldsTheEnds) {
  const ScriptParams p = Params(ScriptKind::kPlayback);
  FingerTargets t = EvaluateScript(p, 0.5);
  EXPECT_TRUE(t.p_D_m[kThumb].isApprox(Eigen::Vector3d(0.005, -0.015, 0.0)));
  EXPECT_TRUE(t.v_D_m_per_s[kIndex].isApprox(Eigen::Vector3d(0.0, -0.01, 0.02)));
  t = EvaluateScript(p, 9.0);
  EXPECT_TRUE(t.p_D_m[kIndex].isApprox(Eigen::Vector3d(0.0, 0.01, 0.02)));
  EXPECT_EQ(t.v_D_m_per_s[kIndex], Eigen::Vector3d::Zero());
}

TEST(MockScriptTest, InvalidParamsThrow) {
  ScriptParams p;
  p.fabric_normal_D = {0.0, 2.0, 0.0};
  EXPECT_THROW(p.Validate(), std::invalid_argument);
  p = ScriptParams{};
  p.kind = ScriptKind::kPlayback;
  try {
    p.Validate();
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("trajectory"), std::string::npos) << e.what();
  }
  p = ScriptParams{};
  p.approach_duration_s = 0.0;
  EXPECT_THROW(p.Validate(), std::invalid_argument);
}

}  // namespace
}  // namespace haptex::device
