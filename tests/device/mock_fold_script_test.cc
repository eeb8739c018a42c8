// The mock user's fold script (ScriptKind::kFold, paper section 5.4): pinch, turn the pinch about
// the index so the fabric below it wraps the index, let go with the thumb, withdraw the index.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <stdexcept>

#include "libs/device/mock_script.h"
#include "tests/support/allocation_counter.h"

namespace haptex::device {
namespace {

constexpr std::size_t kThumb = 0;
constexpr std::size_t kIndex = 1;
constexpr double kTick_s = 2e-4;  // the controller's 5 kHz

// launch/scenes/fold.textproto as haptex-mock-grab maps it: W = D, the hanging fabric's centre,
// the thumb on the user's side (+y), so the normal points along -y and the fold turns about +x.
ScriptParams FoldScene() {
  ScriptParams p;
  p.kind = ScriptKind::kFold;
  p.fabric_point_D_m = {0.0, 0.0, -0.05};
  p.fabric_normal_D = {0.0, -1.0, 0.0};
  p.speed_m_per_s = 0.05;
  p.hold_s = 0.5;
  p.press_depth_m = 2.0 / 300.0;  // squeeze 2 N over the user's 300 N/m grip
  p.pad_offset_m = {0.008, 0.008};
  p.fold_angle_rad = 130.0 * std::numbers::pi / 180.0;
  p.Validate();
  return p;
}

// The first and last script time of a phase, sampled at the controller's rate.
struct Span {
  double first_s = -1.0, last_s = -1.0;
};
Span PhaseSpan(const ScriptParams& p, FoldPhase phase) {
  Span s;
  for (double t = 0.0; t <= FoldDuration(p) + 0.1; t += kTick_s) {
    if (FoldPhaseAt(p, t) != phase) continue;
    if (s.first_s < 0.0) s.first_s = t;
    s.last_s = t;
  }
  return s;
}

// The angle of `v` about +x from the thumb's side (+y), towards up (+z).
double AngleAboutX(const Eigen::Vector3d& v) { return std::atan2(v.z(), v.y()); }

TEST(FoldScriptTest, PhasesComeInOrderAndEndAtRest) {
  const ScriptParams p = FoldScene();
  int expected = 0;
  for (double t = 0.0; t <= FoldDuration(p) + 0.5; t += kTick_s) {
    const int phase = static_cast<int>(FoldPhaseAt(p, t));
    ASSERT_GE(phase, expected) << FoldPhaseName(FoldPhaseAt(p, t)) << " came back at t " << t;
    ASSERT_LE(phase, expected + 1) << "skipped to " << FoldPhaseName(FoldPhaseAt(p, t)) << " at t " << t;
    expected = phase;
  }
  EXPECT_EQ(FoldPhaseAt(p, FoldDuration(p) + 1e-9), FoldPhase::kDone);
  const FingerTargets end = EvaluateScript(p, FoldDuration(p) + 1.0);
  EXPECT_EQ(end.v_D_m_per_s[kThumb], Eigen::Vector3d::Zero());
  EXPECT_EQ(end.v_D_m_per_s[kIndex], Eigen::Vector3d::Zero());
  EXPECT_STREQ(FoldPhaseName(FoldPhase::kLetGo), "let_go");
}

// No step longer than the speed allows, velocities the positions' derivative, all finite.
TEST(FoldScriptTest, TrajectoryIsContinuousWithBoundedSpeed) {
  const ScriptParams p = FoldScene();
  FingerTargets previous = EvaluateScript(p, 0.0);
  for (double t = kTick_s; t <= FoldDuration(p) + 0.5; t += kTick_s) {
    const FingerTargets now = EvaluateScript(p, t);
    const FingerTargets later = EvaluateScript(p, t + 1e-6);
    for (std::size_t i = 0; i < kManipulatorCount; ++i) {
      ASSERT_TRUE(now.p_D_m[i].allFinite() && now.v_D_m_per_s[i].allFinite()) << "t " << t;
      ASSERT_LE((now.p_D_m[i] - previous.p_D_m[i]).norm(), p.speed_m_per_s * kTick_s * (1.0 + 1e-6))
          << "jump at t " << t << " finger " << i;
      ASSERT_LE(now.v_D_m_per_s[i].norm(), p.speed_m_per_s * (1.0 + 1e-6)) << "t " << t;
      const Eigen::Vector3d numeric = (later.p_D_m[i] - now.p_D_m[i]) / 1e-6;
      ASSERT_LT((numeric - now.v_D_m_per_s[i]).norm(), 1e-3) << "t " << t << " finger " << i;
    }
    previous = now;
  }
}

// While folding the pinch is kept: the fingers' aims stay as far apart as when they squeezed, and
// the pair turns by the fold angle about the index's axis with the thumb rising over the index,
// rising by the arc the fabric wraps. The index's aim circles the pivot at the press depth, so
// that a squeezed index stays on the pivot.
TEST(FoldScriptTest, TheFoldTurnsThePinchAboutTheIndexWithTheThumbRising) {
  const ScriptParams p = FoldScene();
  const Span fold = PhaseSpan(p, FoldPhase::kFold);
  ASSERT_GT(fold.first_s, 0.0);
  const FingerTargets start = EvaluateScript(p, fold.first_s);
  const double distance_m = (start.p_D_m[kThumb] - start.p_D_m[kIndex]).norm();
  const Eigen::Vector3d pivot = p.fabric_point_D_m + p.pad_offset_m[kIndex] * p.fabric_normal_D;
  double highest_thumb_z = -1.0, highest_pivot_z = pivot.z();
  for (double t = fold.first_s; t <= fold.last_s; t += kTick_s) {
    const FingerTargets now = EvaluateScript(p, t);
    ASSERT_NEAR((now.p_D_m[kThumb] - now.p_D_m[kIndex]).norm(), distance_m, 1e-9) << "t " << t;
    // the pivot rises with the pair by the thumb's radius times the angle turned so far
    const double turned =
        AngleAboutX(now.p_D_m[kThumb] - now.p_D_m[kIndex]) - AngleAboutX(start.p_D_m[kThumb] - start.p_D_m[kIndex]);
    const Eigen::Vector3d lifted = pivot + p.pad_offset_m[kThumb] * turned * Eigen::Vector3d::UnitZ();
    ASSERT_NEAR((now.p_D_m[kIndex] - lifted).norm(), p.press_depth_m, 1e-9) << "t " << t;
    ASSERT_NEAR(now.p_D_m[kThumb].x(), 0.0, 1e-12);  // about the distal axis, x
    highest_thumb_z = std::max(highest_thumb_z, now.p_D_m[kThumb].z() - (lifted.z() - pivot.z()));
    highest_pivot_z = std::max(highest_pivot_z, lifted.z());
  }
  const FingerTargets end = EvaluateScript(p, fold.last_s);
  EXPECT_NEAR(
      AngleAboutX(end.p_D_m[kThumb] - end.p_D_m[kIndex]) - AngleAboutX(start.p_D_m[kThumb] - start.p_D_m[kIndex]),
      p.fold_angle_rad, 1e-9);
  EXPECT_NEAR(highest_pivot_z - pivot.z(), p.pad_offset_m[kThumb] * p.fold_angle_rad, 1e-9);
  // over the top of the index: straight above the pivot at a quarter turn
  EXPECT_NEAR(highest_thumb_z, pivot.z() + (start.p_D_m[kThumb] - pivot).norm(), 1e-6);
}

// The thumb opens along the middle of its side the fabric leaves free: away from the index and
// out of the pinch; the index holds still meanwhile, then leaves downwards and back while the
// thumb goes back to its own side of the fabric.
TEST(FoldScriptTest, TheThumbLetsGoThenTheIndexWithdraws) {
  const ScriptParams p = FoldScene();
  const Span let_go = PhaseSpan(p, FoldPhase::kLetGo);
  const FingerTargets folded = EvaluateScript(p, let_go.first_s);
  const FingerTargets open = EvaluateScript(p, let_go.last_s);
  const Eigen::Vector3d move = open.p_D_m[kThumb] - folded.p_D_m[kThumb];
  EXPECT_NEAR(move.norm(), p.press_depth_m + p.rest_gap_m, 1e-9);
  EXPECT_NEAR(AngleAboutX(move), 0.5 * p.fold_angle_rad, 1e-9);
  EXPECT_TRUE(open.p_D_m[kIndex].isApprox(folded.p_D_m[kIndex], 1e-12));
  double last_distance = 0.0;
  for (double t = let_go.first_s; t <= let_go.last_s; t += kTick_s) {
    const FingerTargets now = EvaluateScript(p, t);
    const double distance = (now.p_D_m[kThumb] - now.p_D_m[kIndex]).norm();
    ASSERT_GE(distance, last_distance - 1e-12) << "t " << t;
    last_distance = distance;
  }
  const FingerTargets end = EvaluateScript(p, FoldDuration(p));
  const Eigen::Vector3d withdrawn = end.p_D_m[kIndex] - open.p_D_m[kIndex];
  EXPECT_LT(withdrawn.z(), -0.01);
  EXPECT_GT(withdrawn.dot(p.fabric_normal_D), 0.01);
  const Eigen::Vector3d thumb_back = end.p_D_m[kThumb] - open.p_D_m[kThumb];
  EXPECT_TRUE(thumb_back.isApprox(-(p.press_depth_m + p.rest_gap_m) * p.fabric_normal_D, 1e-12))
      << thumb_back.transpose();
}

TEST(FoldScriptTest, ValidateRefusesWhatCannotFold) {
  ScriptParams p = FoldScene();
  p.fold_angle_rad = 3.5;
  EXPECT_THROW(p.Validate(), std::invalid_argument);
  p = FoldScene();
  p.up_D = p.fabric_normal_D;  // a fabric lying flat under the fingers: no axis across them
  EXPECT_THROW(p.Validate(), std::invalid_argument);
  EXPECT_EQ(ScriptKindFromName("fold"), ScriptKind::kFold);
}

TEST(FoldScriptTest, EvaluatingAllocatesNothing) {
  if (!testing::AllocationCountingSupported()) GTEST_SKIP() << "allocation counting unavailable";
  const ScriptParams p = FoldScene();
  double sum = 0.0;
  testing::AllocationCounter counter;
  for (double t = 0.0; t < FoldDuration(p); t += 0.01) {
    sum += EvaluateScript(p, t).p_D_m[kThumb].z() + static_cast<double>(FoldPhaseAt(p, t));
  }
  EXPECT_EQ(counter.count(), 0);
  EXPECT_TRUE(std::isfinite(sum));
}

}  // namespace
}  // namespace haptex::device
