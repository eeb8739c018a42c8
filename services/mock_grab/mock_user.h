#pragma once
// The user the mock controller plays: the scene's (scene::MockScriptFromScene), with the kind and
// the playback trajectory the command line may choose instead.

#include <string>

#include "haptex/v1/scene.pb.h"
#include "libs/device/mock_grab_controller.h"
#include "libs/device/mock_script.h"

namespace haptex::mock_grab {

/// `script_name` (empty: the scene's kind) picks the kind; the scene's geometry and user
/// parameters apply either way. The playback kind loads `playback_csv` (empty: the scene's).
/// @throws std::invalid_argument for an unknown kind, a missing or bad trajectory, or an invalid
/// script.
device::ScriptParams MockUser(const v1::Scene& scene, const std::string& script_name, const std::string& playback_csv,
                              const device::MockControllerConfig& controller);

}  // namespace haptex::mock_grab
