#include "libs/scene/scene_device.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "libs/codec/message_conversion.h"
#include "libs/scene/scene_contact.h"
#include "libs/scene/scene_defaults.h"
#include "libs/scene/scene_loader.h"

namespace haptex::scene {
namespace {

// ScriptParams::Validate's bound.
constexpr double kMaxRubFrequencyHz = 20.0;

}  // namespace

Eigen::Isometry3d DeviceFrameInWorld(const v1::DeviceSpec& d, const Eigen::Isometry3d& fallback) {
  Eigen::Isometry3d X_WD = fallback;
  if (d.has_q_wd()) {
    const Eigen::Quaterniond q_WD(d.q_wd().w(), d.q_wd().x(), d.q_wd().y(), d.q_wd().z());
    const double norm = q_WD.norm();
    if (!std::isfinite(norm) || !(std::abs(norm - 1.0) <= kQuaternionNormTolerance)) {
      throw std::invalid_argument("device.q_wd must be a unit quaternion (|q| within 1e-3 of 1), got |q| = " +
                                  std::to_string(norm));
    }
    X_WD.linear() = q_WD.normalized().toRotationMatrix();
  }
  if (d.has_d_origin_w_m()) X_WD.translation() = codec::ToEigen(d.d_origin_w_m());
  return X_WD;
}

device::DeviceBridgeConfig BridgeConfigFromScene(const v1::Scene& scene) {
  device::DeviceBridgeConfig config;
  const v1::DeviceSpec& d = scene.device();
  config.safety.peak_force_N = OrDefault(d.peak_force_n(), config.safety.peak_force_N);
  config.safety.continuous_force_N = OrDefault(d.continuous_force_n(), config.safety.continuous_force_N);
  config.safety.stale_after_s = OrDefault(d.force_model_stale_s(), config.safety.stale_after_s);
  config.safety.stale_ramp_s = OrDefault(d.watchdog_ramp_s(), config.safety.stale_ramp_s);
  config.device_lost_after_s = OrDefault(d.controller_lost_s(), config.device_lost_after_s);
  config.max_model_age_s = OrDefault(d.max_model_age_s(), config.max_model_age_s);
  if (d.disable_passivity_control()) config.passivity.enabled = false;
  config.X_WD = DeviceFrameInWorld(d, config.X_WD);
  config.Validate();
  return config;
}

double ForceModelStaleS(const v1::Scene& scene) { return BridgeConfigFromScene(scene).safety.stale_after_s; }

device::ScriptKind ScriptKindFromScene(v1::MockUserScript::Kind kind) {
  switch (kind) {
    case v1::MockUserScript::KIND_APPROACH_AND_TOUCH:
      return device::ScriptKind::kApproachAndTouch;
    case v1::MockUserScript::KIND_GRASP_AND_SQUEEZE:
      return device::ScriptKind::kGraspAndSqueeze;
    case v1::MockUserScript::KIND_PINCH_AND_STRETCH:
      return device::ScriptKind::kPinchAndStretch;
    case v1::MockUserScript::KIND_RUB:
      return device::ScriptKind::kRub;
    case v1::MockUserScript::KIND_LIFT:
      return device::ScriptKind::kLift;
    case v1::MockUserScript::KIND_PLAYBACK:
      return device::ScriptKind::kPlayback;
    case v1::MockUserScript::KIND_DEMO:
      return device::ScriptKind::kDemo;
    case v1::MockUserScript::KIND_FOLD:
      return device::ScriptKind::kFold;
    default:
      return device::ScriptKind::kIdle;
  }
}

device::ScriptParams MockScriptFromScene(const v1::Scene& scene, const device::MockControllerConfig& controller) {
  device::ScriptParams script;
  // the user acts in W; the controller's script is in D, where the bridge reads it through X_WD
  const Eigen::Isometry3d X_DW = DeviceFrameInWorld(scene.device(), Eigen::Isometry3d::Identity()).inverse();
  const Eigen::Matrix3d R_DW = X_DW.linear();
  const v1::ClothGeometry& cloth = scene.cloth();
  const Eigen::Vector3d stand_W = codec::ToEigen(cloth.stand_position_w_m());
  const double height_m = ClothHeightM(cloth);
  const bool flat = cloth.mounting() == v1::ClothGeometry::MOUNTING_FLAT_LEDGE;
  // the fabric's normal points from the thumb's side to the index's side
  script.fabric_normal_D = R_DW * (flat ? Eigen::Vector3d(0, 0, -1) : Eigen::Vector3d(0, -1, 0));
  // default touch point: the fabric's centre at rest (cloth_setup.h)
  script.fabric_point_D_m =
      X_DW * (stand_W + (flat ? Eigen::Vector3d(0, height_m / 2, 0) : Eigen::Vector3d(0, 0, -height_m / 2)));
  // stretch and rub run along W's x (the bar, in the fabric at rest), lift along W's up
  script.rub_direction_D = R_DW * Eigen::Vector3d::UnitX();
  script.up_D = R_DW * Eigen::Vector3d::UnitZ();
  script.stretch_D_m = R_DW * Eigen::Vector3d(script.stretch_D_m.norm(), 0, 0);

  bool has_thumb = false, has_index = false;
  for (const v1::FingerSpec& f : scene.fingers()) {
    const int slot = codec::FingerSlot(f.finger());
    if (slot < 0) continue;
    (slot == codec::kThumbSlot ? has_thumb : has_index) = true;
    const auto manipulator = slot == codec::kThumbSlot ? device::Manipulator::kThumb : device::Manipulator::kIndex;
    script.pad_offset_m[static_cast<std::size_t>(manipulator)] = FingerShapeFromScene(f).radius_m;
  }
  if (has_index && !has_thumb) script.touch_finger = device::Manipulator::kIndex;

  if (!scene.device().has_mock()) return script;
  const v1::MockUserScript& user = scene.device().mock().user();
  script.kind = ScriptKindFromScene(user.kind());
  if (user.has_touch_point_w_m()) script.fabric_point_D_m = X_DW * codec::ToEigen(user.touch_point_w_m());
  const double squeeze_N = OrDefault(user.squeeze_force_n(), kDefaultSqueezeForceN);
  const double stretch_m = OrDefault(user.stretch_m(), script.stretch_D_m.norm());
  script.speed_m_per_s = OrDefault(user.speed_m_per_s(), script.speed_m_per_s);
  script.hold_s = OrDefault(user.hold_s(), script.hold_s);
  // the user moves at this speed through each phase (kDemo: the peak speed of every move)
  script.approach_duration_s = script.rest_gap_m / script.speed_m_per_s;
  script.stretch_duration_s = stretch_m / OrDefault(user.stretch_speed_m_per_s(), script.speed_m_per_s);
  script.lift_duration_s = script.lift_height_m / script.speed_m_per_s;
  // the user aims beyond the fabric so that its grip spring pulls with the squeeze force
  script.press_depth_m = squeeze_N / controller.finger.user_stiffness_N_per_m;
  script.stretch_D_m = R_DW * Eigen::Vector3d(stretch_m, 0, 0);
  script.rub_amplitude_m = OrDefault(user.rub_amplitude_m(), script.rub_amplitude_m);
  if (user.fold_angle_deg() != 0.0) script.fold_angle_rad = user.fold_angle_deg() * std::numbers::pi / 180.0;
  // A speed the scene gives is the rub's peak speed too: friction is judged at the speed a person
  // strokes with (paper Fig. 9), and the core's 2 Hz over 1 cm is a brisk 13 cm/s.
  if (user.speed_m_per_s() > 0.0 && script.rub_amplitude_m > 0.0) {
    script.rub_frequency_Hz =
        std::min(kMaxRubFrequencyHz, script.speed_m_per_s / (2.0 * std::numbers::pi * script.rub_amplitude_m));
  }
  return script;
}

}  // namespace haptex::scene
