#include "services/viewer/session_info.h"

#include <nlohmann/json.hpp>

#include "libs/codec/message_conversion.h"
#include "libs/scene/scene_defaults.h"
#include "services/viewer/scene_view.h"

namespace haptex::viewer {

std::string SessionJson(const scene::LoadedScene& loaded, std::string_view recording_url) {
  const v1::Scene& s = loaded.scene;
  nlohmann::json fingers = nlohmann::json::array();
  for (const v1::FingerSpec& f : s.fingers()) {
    const contact::FingerShape shape = scene::FingerShapeFromScene(f);
    fingers.push_back(
        {{"finger", codec::FingerName(f.finger())}, {"radius_m", shape.radius_m}, {"length_m", shape.length_m}});
  }
  nlohmann::json session = {
      {"mode", recording_url.empty() ? "live" : "replay"},
      {"scene",
       {{"name", s.name()},
        {"description", s.description()},
        {"cloth",
         {{"width_m", scene::ClothWidthM(s.cloth())},
          {"particles_u", scene::ClothParticlesU(s.cloth())},
          {"particles_v", scene::ClothParticlesV(s.cloth())}}},
        {"fingers", fingers}}},
      {"fixed_particles", StandParticles(loaded)},
      {"frame_hz", scene::ClothFrameHz(s)},
  };
  if (!recording_url.empty()) session["recording"] = std::string(recording_url);
  // dump() escapes every string, so scene text cannot break out of the document
  return session.dump(1, ' ', true, nlohmann::json::error_handler_t::replace);
}

}  // namespace haptex::viewer
