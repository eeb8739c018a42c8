// The device's pose in the scene: X_WD reaches the bridge's configuration, and the mock user is
// mapped into D through its inverse, so the bridge sees the user touch the same points of W
// whatever the device's pose.
#include "libs/scene/scene_device.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>

#include "libs/device/device_bridge.h"
#include "libs/device/mock_grab_controller.h"
#include "libs/scene/scene_loader.h"
#include "tests/support/test_paths.h"

namespace haptex::scene {
namespace {

v1::Scene Scene(const std::string& device) {
  const FabricDatabase db(haptex::testing::SourceDir() + "/data/fabrics");
  return ParseScene(R"(name: "pose" fabric { database_name: "wang2011_black_denim_11oz" }
cloth { width_m: 0.2 height_m: 0.2 }
fingers { finger: FINGER_THUMB radius_m: 0.008 length_m: 0.012 }
fingers { finger: FINGER_INDEX radius_m: 0.008 length_m: 0.012 }
)" + device,
                    "pose", db)
      .scene;
}

// The device turned to face the user (D's +y away from the user: a half turn about z) and set
// 20 mm to the user's side, 30 mm down.
constexpr char kTurned[] = "q_wd { w: 0 z: 1 } d_origin_w_m { x: 0.01 y: 0.02 z: -0.03 }";

TEST(SceneDeviceTest, TheScenesDevicePoseReachesTheBridge) {
  const device::DeviceBridgeConfig c =
      BridgeConfigFromScene(Scene(std::string("device { mock {} ") + kTurned + " }\n"));
  EXPECT_TRUE(c.X_WD.translation().isApprox(Eigen::Vector3d(0.01, 0.02, -0.03)));
  // D's +x is W's -x, D's +y is W's -y, up stays up
  EXPECT_TRUE(c.X_WD.linear().isApprox(Eigen::Vector3d(-1, -1, 1).asDiagonal().toDenseMatrix(), 1e-12));
  // a rotation given to four decimals is normalised into a rigid transform
  const device::DeviceBridgeConfig quarter =
      BridgeConfigFromScene(Scene("device { mock {} q_wd { w: 0.7071 z: 0.7071 } }\n"));
  EXPECT_TRUE((quarter.X_WD.linear() * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitY(), 1e-12));
  EXPECT_NEAR(quarter.X_WD.linear().determinant(), 1.0, 1e-12);
  // a scene that skipped the loader's checks still cannot give a non-rotation
  v1::Scene bad = Scene("device { mock {} }\n");
  bad.mutable_device()->mutable_q_wd()->set_w(2.0);
  EXPECT_THROW(BridgeConfigFromScene(bad), std::invalid_argument);
}

TEST(SceneDeviceTest, TheMockUserIsMappedIntoDThroughTheInverse) {
  const std::string user = "mock { user { kind: KIND_DEMO touch_point_w_m { x: 0.02 y: 0 z: -0.08 } } } ";
  const v1::Scene identity = Scene("device { " + user + "}\n");
  const v1::Scene turned = Scene("device { " + user + kTurned + " }\n");
  const device::ScriptParams a = MockScriptFromScene(identity, {});
  const device::ScriptParams b = MockScriptFromScene(turned, {});
  const Eigen::Isometry3d X_WD = BridgeConfigFromScene(turned).X_WD;
  EXPECT_TRUE(a.fabric_point_D_m.isApprox(Eigen::Vector3d(0.02, 0, -0.08)));
  EXPECT_TRUE((X_WD * b.fabric_point_D_m).isApprox(a.fabric_point_D_m, 1e-12));
  EXPECT_TRUE((X_WD.linear() * b.fabric_normal_D).isApprox(a.fabric_normal_D, 1e-12));
  EXPECT_TRUE((X_WD.linear() * b.stretch_D_m).isApprox(a.stretch_D_m, 1e-12));
  EXPECT_TRUE((X_WD.linear() * b.rub_direction_D).isApprox(a.rub_direction_D, 1e-12));
  EXPECT_TRUE((X_WD.linear() * b.up_D).isApprox(Eigen::Vector3d::UnitZ(), 1e-12));
}

// The rub strokes at the scene's speed (its peak speed), with the index when the scene has only it.
TEST(SceneDeviceTest, TheRubStrokesAtTheScenesSpeedWithTheFingerItHas) {
  v1::Scene index_alone =
      Scene("device { mock { user { kind: KIND_RUB speed_m_per_s: 0.02 rub_amplitude_m: 0.01 } } }\n");
  index_alone.clear_fingers();
  index_alone.add_fingers()->set_finger(v1::FINGER_INDEX);
  const device::ScriptParams rub = MockScriptFromScene(index_alone, {});
  EXPECT_EQ(rub.kind, device::ScriptKind::kRub);
  EXPECT_EQ(rub.touch_finger, device::Manipulator::kIndex);
  EXPECT_NEAR(2.0 * std::numbers::pi * rub.rub_frequency_Hz * rub.rub_amplitude_m, 0.02, 1e-12);
  // without a speed the core's stroke stays
  const device::ScriptParams core_rub = MockScriptFromScene(Scene("device { mock { user { kind: KIND_RUB } } }\n"), {});
  EXPECT_EQ(core_rub.rub_frequency_Hz, device::ScriptParams{}.rub_frequency_Hz);
}

// The pull of a pinch-and-stretch takes its own speed when the scene gives one (a tensile test
// pulls slowly), the approach keeps the user's; without it both move at the user's speed.
TEST(SceneDeviceTest, TheStretchPullsAtItsOwnSpeedWhenTheSceneGivesOne) {
  const device::ScriptParams slow = MockScriptFromScene(
      Scene("device { mock { user { kind: KIND_PINCH_AND_STRETCH speed_m_per_s: 0.01 stretch_m: 0.003 "
            "stretch_speed_m_per_s: 0.002 } } }\n"),
      {});
  EXPECT_NEAR(slow.stretch_duration_s, 1.5, 1e-12);
  EXPECT_NEAR(slow.approach_duration_s, slow.rest_gap_m / 0.01, 1e-12);
  const device::ScriptParams same = MockScriptFromScene(
      Scene("device { mock { user { kind: KIND_PINCH_AND_STRETCH speed_m_per_s: 0.01 stretch_m: 0.003 } } }\n"), {});
  EXPECT_NEAR(same.stretch_duration_s, 0.3, 1e-12);
}

// The demo user on the mock controller, read by the bridge: the fingertips it reports in W are
// the same with the device turned and moved as with D = W, at every phase of the demo.
TEST(SceneDeviceTest, TheDemoTouchesTheSameWorldPointsWhateverTheDevicePose) {
  const std::string user = "mock { user { kind: KIND_DEMO speed_m_per_s: 0.05 hold_s: 0.2 } } ";
  const std::array<v1::Scene, 2> scenes = {Scene("device { " + user + "}\n"),
                                           Scene("device { " + user + kTurned + " }\n")};
  constexpr double kDt_s = 2e-4;
  struct Run {
    std::unique_ptr<device::MockGrabController> mock;
    std::unique_ptr<device::DeviceBridge> bridge;
  };
  std::array<Run, 2> runs;
  for (std::size_t r = 0; r < runs.size(); ++r) {
    runs[r].mock = std::make_unique<device::MockGrabController>(device::MockControllerConfig{},
                                                                MockScriptFromScene(scenes[r], {}));
    runs[r].bridge = std::make_unique<device::DeviceBridge>(BridgeConfigFromScene(scenes[r]));
  }
  std::array<std::byte, device::kStatusFrameSize> status{};
  int compared = 0;
  for (int k = 0; k < 40000; ++k) {  // 8 s: approach, touch, pinch, stretch and rub
    const double t_s = k * kDt_s;
    for (Run& run : runs) {
      run.mock->Step(t_s, kDt_s, status);
      ASSERT_EQ(run.bridge->OnStatusDatagram(status, t_s + kDt_s), device::FrameError::kNone) << t_s;
    }
    if (k % 2500 != 0) continue;
    for (const auto finger : {device::Manipulator::kThumb, device::Manipulator::kIndex}) {
      const device::FingerState& a = runs[0].bridge->finger_state(finger);
      const device::FingerState& b = runs[1].bridge->finger_state(finger);
      ASSERT_TRUE(a.valid && b.valid);
      // two encoder steps (0.032 mm each) of quantisation in differently oriented axes
      EXPECT_LT((a.p_W_m - b.p_W_m).norm(), 1e-4) << "t " << t_s << " finger " << static_cast<int>(finger);
      // the pads face each other through the fabric in W as well
      EXPECT_TRUE((a.q_WF * Eigen::Vector3d::UnitZ()).isApprox(b.q_WF * Eigen::Vector3d::UnitZ(), 1e-6));
      ++compared;
    }
  }
  EXPECT_EQ(compared, 2 * 16);
  // and the thumb is on the user's side (+y in W) of the hanging fabric, the index behind it
  EXPECT_GT(runs[1].bridge->finger_state(device::Manipulator::kThumb).p_W_m.y(), 0.0);
  EXPECT_LT(runs[1].bridge->finger_state(device::Manipulator::kIndex).p_W_m.y(), 0.0);
}

// KIND_FOLD maps to the fold script, its angle from degrees; unset, the script's own default.
TEST(SceneDeviceTest, TheFoldUserTakesItsAngleInDegrees) {
  const device::ScriptParams fold =
      MockScriptFromScene(Scene("device { mock { user { kind: KIND_FOLD fold_angle_deg: 90 } } }\n"), {});
  EXPECT_EQ(fold.kind, device::ScriptKind::kFold);
  EXPECT_NEAR(fold.fold_angle_rad, std::numbers::pi / 2, 1e-12);
  const device::ScriptParams unset = MockScriptFromScene(Scene("device { mock { user { kind: KIND_FOLD } } }\n"), {});
  EXPECT_EQ(unset.fold_angle_rad, device::ScriptParams{}.fold_angle_rad);
}

}  // namespace
}  // namespace haptex::scene
