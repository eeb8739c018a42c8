#pragma once
// A scene's device as the device core's configuration: the bridge's limits and watchdogs, and the
// mock controller's user. device::DeviceBridgeConfig and device::ScriptParams own every default;
// the scene overrides what it gives.

#include "haptex/v1/scene.pb.h"
#include "libs/device/device_bridge.h"
#include "libs/device/mock_grab_controller.h"
#include "libs/device/mock_script.h"

namespace haptex::scene {

/// The bridge's configuration with the scene's device limits and watchdogs where given.
/// @throws std::invalid_argument when the result is not valid.
device::DeviceBridgeConfig BridgeConfigFromScene(const v1::Scene& scene);

/// X_WD, the pose of the device workspace frame D in W: the scene's d_origin_w_m and q_wd where
/// given (q_wd normalised), `fallback`'s parts where not.
/// @throws std::invalid_argument when q_wd is not a unit quaternion (within 1e-3).
Eigen::Isometry3d DeviceFrameInWorld(const v1::DeviceSpec& device, const Eigen::Isometry3d& fallback);

/// How long the bridge applies a ForceModel after receiving it: local_contact sends this as the
/// models' ttl, and the bridge caps every ttl with it.
double ForceModelStaleS(const v1::Scene& scene);

/// The mock user's grip target when the scene gives none [N].
inline constexpr double kDefaultSqueezeForceN = 2.0;

/// The mock controller's user: the scene's fabric and fingers in D, and the scene's mock user
/// script (kind, touch point, speed, squeeze, stretch, rub, hold) where given. The user acts in W
/// (the thumb on the front of the fabric, the user's side: +y for a hanging fabric, above a flat
/// one) and everything is mapped into D through the inverse of the scene's X_WD
/// (DeviceFrameInWorld), the transform the bridge maps D back into W with.
device::ScriptParams MockScriptFromScene(const v1::Scene& scene, const device::MockControllerConfig& controller);

/// The script kind a scene names.
device::ScriptKind ScriptKindFromScene(v1::MockUserScript::Kind kind);

}  // namespace haptex::scene
