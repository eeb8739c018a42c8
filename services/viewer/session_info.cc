#include "services/viewer/session_info.h"

#include <stdexcept>
#include <vector>

#include <nlohmann/json.hpp>

#include "libs/codec/message_conversion.h"
#include "libs/scene/cloth_setup.h"
#include "libs/scene/scene_defaults.h"

namespace haptex::viewer {
namespace {

// where the stand holds the cloth; none when the scene's fabric does not load (the page then
// draws no stand, and the services say why)
std::vector<int> FixedParticles(const scene::LoadedScene& loaded) {
  try {
    return scene::MakeClothSetup(loaded).fixed_particles;
  } catch (const std::invalid_argument&) {
    return {};
  }
}

}  // namespace

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
      {"fixed_particles", FixedParticles(loaded)},
      {"frame_hz", scene::ClothFrameHz(s)},
  };
  if (!recording_url.empty()) session["recording"] = std::string(recording_url);
  // dump() escapes every string, so scene text cannot break out of the document
  return session.dump(1, ' ', true, nlohmann::json::error_handler_t::replace);
}

}  // namespace haptex::viewer
