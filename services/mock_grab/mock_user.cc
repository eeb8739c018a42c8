#include "services/mock_grab/mock_user.h"

#include <stdexcept>

#include "libs/device/trajectory_csv.h"
#include "libs/scene/scene_device.h"

namespace haptex::mock_grab {

device::ScriptParams MockUser(const v1::Scene& scene, const std::string& script_name, const std::string& playback_csv,
                              const device::MockControllerConfig& controller) {
  device::ScriptParams script = scene::MockScriptFromScene(scene, controller);
  if (!script_name.empty()) script.kind = device::ScriptKindFromName(script_name);
  if (script.kind == device::ScriptKind::kPlayback) {
    const std::string path = playback_csv.empty() ? scene.device().mock().user().playback_csv() : playback_csv;
    if (path.empty()) throw std::invalid_argument("the playback script needs --playback-csv FILE");
    script.trajectory = device::LoadTrajectoryCsv(path);
  }
  script.Validate();
  return script;
}

}  // namespace haptex::mock_grab
