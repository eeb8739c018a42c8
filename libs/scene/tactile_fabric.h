#pragma once
// A fabric's virtual tactile surface: a height map from its weave (pattern, pitches, yarn size)
// scaled to its measured roughness (KES SMD), or a grey image; reduced to a periodic tile that
// the real-time renderer only looks up (libs/tactile).

#include <string>

#include "haptex/v1/fabric.pb.h"
#include "haptex/v1/scene.pb.h"
#include "libs/tactile/height_map.h"
#include "libs/tactile/periodic_tile.h"
#include "libs/tactile/pin_renderer.h"
#include "libs/tactile/weave_surface.h"

namespace haptex::scene {

/// Values given by hand, replacing (or supplying) the fabric's own. 0 / empty: use the fabric's.
struct TactileSurfaceOverrides {
  std::string pattern;  // plain, twill or satin
  double warp_pitch_mm = 0;
  double weft_pitch_mm = 0;
  double yarn_diameter_mm = 0;
  double smd_um = 0;
  std::string image_path;     // a PGM height image instead of a weave
  double image_pixel_um = 0;  // its pixel size
};

/// The scene's tactile surface (tactile.surface) under the values given by hand: a value given by
/// hand wins, else the scene's, else (0 / empty) the fabric's.
TactileSurfaceOverrides WithSceneSurface(const v1::TactileSurface& scene_surface, TactileSurfaceOverrides by_hand);

/// Weave parameters from the fabric and the overrides. Throws std::invalid_argument listing every
/// value that neither gives (nothing is made up).
tactile::WeaveParams TactileWeave(const v1::Fabric& fabric, const TactileSurfaceOverrides& overrides);

struct VirtualFabric {
  tactile::HeightMap height_map;
  tactile::PeriodicTile tile;
};

/// The height map (weave or image, scaled to the SMD) and its periodic tile.
VirtualFabric BuildVirtualFabric(const v1::Fabric& fabric, const TactileSurfaceOverrides& overrides);

/// The renderer's configuration: tactile::RendererConfig's, with the scene's display rate where
/// given.
tactile::RendererConfig RendererConfigFromScene(const v1::Scene& scene);

}  // namespace haptex::scene
