#pragma once
// What the page needs besides the messages, served as /session.json: live or replay (and where the
// recording is), the scene's name, the fingers' capsules and the patch radius, from the scene with
// its defaults resolved (the page knows no defaults of its own).

#include <string>
#include <string_view>

#include "libs/scene/scene_loader.h"

namespace haptex::viewer {

/// `recording_url`: the page's path of the run's MCAP file in replay; empty when live.
std::string SessionJson(const scene::LoadedScene& scene, std::string_view recording_url);

}  // namespace haptex::viewer
