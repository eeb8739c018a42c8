#include "libs/scene/tactile_fabric.h"

#include <stdexcept>

#include "libs/scene/scene_defaults.h"
#include "libs/tactile/grey_image.h"
#include "libs/tactile/periodicity.h"

namespace haptex::scene {
namespace {

double Pick(double override_value, double fabric_value) { return override_value > 0 ? override_value : fabric_value; }

}  // namespace

TactileSurfaceOverrides WithSceneSurface(const v1::TactileSurface& s, TactileSurfaceOverrides o) {
  if (o.pattern.empty()) {
    switch (s.pattern()) {
      case v1::Weave::PATTERN_PLAIN:
        o.pattern = "plain";
        break;
      case v1::Weave::PATTERN_TWILL:
        o.pattern = "twill";
        break;
      case v1::Weave::PATTERN_SATIN:
        o.pattern = "satin";
        break;
      default:
        break;
    }
  }
  o.warp_pitch_mm = Pick(o.warp_pitch_mm, s.warp_pitch_mm());
  o.weft_pitch_mm = Pick(o.weft_pitch_mm, s.weft_pitch_mm());
  o.yarn_diameter_mm = Pick(o.yarn_diameter_mm, s.yarn_diameter_mm());
  o.smd_um = Pick(o.smd_um, s.smd_um());
  return o;
}

tactile::WeaveParams TactileWeave(const v1::Fabric& fabric, const TactileSurfaceOverrides& o) {
  tactile::WeaveParams weave;
  std::string missing;
  auto need = [&](double value, const char* what) {
    if (!(value > 0)) missing += std::string(missing.empty() ? "" : ", ") + what;
    return value;
  };
  std::string pattern = o.pattern;
  if (pattern.empty()) {
    switch (fabric.weave().pattern()) {
      case v1::Weave::PATTERN_PLAIN:
        pattern = "plain";
        break;
      case v1::Weave::PATTERN_TWILL:
        pattern = "twill";
        break;
      case v1::Weave::PATTERN_SATIN:
        pattern = "satin";
        break;
      default:
        break;
    }
  }
  if (pattern == "plain") {
    weave.pattern = tactile::WeavePattern::kPlain;
  } else if (pattern == "twill") {
    weave.pattern = tactile::WeavePattern::kTwill;
  } else if (pattern == "satin") {
    weave.pattern = tactile::WeavePattern::kSatin;
  } else if (pattern.empty()) {
    missing += std::string(missing.empty() ? "" : ", ") + "weave pattern (plain, twill or satin)";
  } else {
    throw std::invalid_argument("unknown weave pattern '" + pattern + "' (plain, twill or satin)");
  }
  weave.warp_pitch_m = need(Pick(o.warp_pitch_mm, fabric.weave().warp_pitch_mm()), "warp pitch") * 1e-3;
  weave.weft_pitch_m = need(Pick(o.weft_pitch_mm, fabric.weave().weft_pitch_mm()), "weft pitch") * 1e-3;
  weave.yarn_diameter_m = need(Pick(o.yarn_diameter_mm, fabric.weave().yarn_diameter_mm()), "yarn diameter") * 1e-3;
  weave.smd_um = need(Pick(o.smd_um, fabric.surface().smd_um()), "roughness SMD");
  if (!missing.empty()) {
    throw std::invalid_argument("fabric '" + fabric.name() + "' lacks " + missing +
                                " for its tactile surface: add them to its database entry (weave, "
                                "surface.smd_um), to the scene (tactile.surface, with their source) or give "
                                "them by hand");
  }
  // 12 pixels per thread on a 256 x 256 grid: about 21 threads, several repeats of any weave
  weave.pixel_size_m = std::min(weave.warp_pitch_m, weave.weft_pitch_m) / 12;
  weave.size_x = weave.size_y = 256;
  return weave;
}

VirtualFabric BuildVirtualFabric(const v1::Fabric& fabric, const TactileSurfaceOverrides& o) {
  if (!o.image_path.empty()) {
    const double smd_um = Pick(o.smd_um, fabric.surface().smd_um());
    if (!(o.image_pixel_um > 0) || !(smd_um > 0)) {
      throw std::invalid_argument("a height image needs its pixel size and the fabric's SMD to scale it");
    }
    // relief: the image's full grey range; SMD is the mean deviation, about a quarter of it
    tactile::GreyImage image;
    try {
      image = tactile::ReadPgmFile(o.image_path);
    } catch (const std::runtime_error& e) {
      throw std::invalid_argument("height image " + o.image_path + ": " + e.what());
    }
    tactile::HeightMap map = tactile::HeightMapFromGreyImage(image, o.image_pixel_um * 1e-6, 4 * smd_um);
    tactile::PeriodicTile tile = tactile::AnalysePeriodicity(map);
    return {std::move(map), std::move(tile)};
  }
  tactile::HeightMap map = tactile::GenerateWeave(TactileWeave(fabric, o));
  tactile::PeriodicTile tile = tactile::AnalysePeriodicity(map);
  return {std::move(map), std::move(tile)};
}

tactile::RendererConfig RendererConfigFromScene(const v1::Scene& scene) {
  tactile::RendererConfig config;
  config.display_rate_hz = OrDefault(scene.tactile().display_rate_hz(), config.display_rate_hz);
  return config;
}

}  // namespace haptex::scene
