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

/// How long the bridge applies a ForceModel after receiving it: local_contact sends this as the
/// models' ttl, and the bridge caps every ttl with it.
double ForceModelStaleS(const v1::Scene& scene);

/// The mock user's grip target when the scene gives none [N].
inline constexpr double kDefaultSqueezeForceN = 2.0;

/// The mock controller's user: the scene's fabric and fingers in D, and the scene's mock user
/// script (kind, touch point, speed, squeeze, stretch, rub, hold) where given. Frame D = W (the
/// bridge runs with DeviceBridgeConfig::X_WD = identity), so the geometry is W's: the thumb is on
/// the front of the fabric, the user's side (+y for a hanging fabric, above a flat one).
device::ScriptParams MockScriptFromScene(const v1::Scene& scene, const device::MockControllerConfig& controller);

/// The script kind a scene names.
device::ScriptKind ScriptKindFromScene(v1::MockUserScript::Kind kind);

}  // namespace haptex::scene
