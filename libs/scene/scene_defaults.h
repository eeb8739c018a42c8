#pragma once
// The scene's values where a field is 0 (proto3: not given), for the loader's checks and the
// services alike. Where a core has the concept, the core's option struct owns the default
// (contact::FingerShape, textile::GridSpec, ...) and the scene layer fills from it; the rest
// (rates, the patch margin) are the scene layer's own and named here.

#include <algorithm>
#include <cstdint>
#include <numbers>
#include <string>

#include "haptex/v1/scene.pb.h"
#include "libs/contact/finger_geometry.h"
#include "libs/textile/fabric_model.h"
#include "libs/textile/grid_mesh.h"
#include "libs/textile/step_options.h"

namespace haptex::scene {

inline double OrDefault(double value, double fallback) { return value > 0 ? value : fallback; }

/// The scene's integrator, else `fallback` (the step options' own default).
inline textile::Integrator IntegratorOr(v1::ModelOptions::Integrator integrator, textile::Integrator fallback) {
  switch (integrator) {
    case v1::ModelOptions::INTEGRATOR_IMPLICIT_EULER:
      return textile::Integrator::kImplicitEuler;
    case v1::ModelOptions::INTEGRATOR_SEMI_IMPLICIT:
      return textile::Integrator::kSymplecticEuler;
    case v1::ModelOptions::INTEGRATOR_BDF2:
      return textile::Integrator::kBdf2;
    default:
      return fallback;
  }
}

/// Cloth size along warp and weft [m] and particles per row and column: textile::GridSpec's
/// unless given.
inline double ClothWidthM(const v1::ClothGeometry& c) {
  return OrDefault(c.width_m(), textile::GridSpec{}.length_warp_m);
}
inline double ClothHeightM(const v1::ClothGeometry& c) {
  return OrDefault(c.height_m(), textile::GridSpec{}.width_weft_m);
}
inline int ClothParticlesU(const v1::ClothGeometry& c) {
  return c.particles_u() > 0 ? static_cast<int>(c.particles_u()) : textile::GridSpec{}.particles_warp;
}
inline int ClothParticlesV(const v1::ClothGeometry& c) {
  return c.particles_v() > 0 ? static_cast<int>(c.particles_v()) : textile::GridSpec{}.particles_weft;
}

/// The fabric's warp direction from the grid's u axis [rad]: the scene's degrees, else
/// textile::ModelOptions's (warp along u).
inline double ClothMaterialAngleRad(const v1::ClothGeometry& c) {
  return c.material_angle_deg() != 0.0 ? c.material_angle_deg() * (std::numbers::pi / 180.0)
                                       : textile::ModelOptions{}.material_angle_rad;
}
/// The largest |material_angle_deg| a scene may give: half a turn each way.
inline constexpr double kMaxMaterialAngleDeg = 180.0;

/// A finger's shape: the scene's radius and length where given, else contact::FingerShape's; a
/// sphere has no length.
inline contact::FingerShape FingerShapeFromScene(const v1::FingerSpec& finger) {
  const contact::FingerShape defaults;
  contact::FingerShape shape;
  shape.radius_m = OrDefault(finger.radius_m(), defaults.radius_m);
  shape.length_m =
      finger.shape() == v1::FingerSpec::SHAPE_SPHERE ? 0.0 : OrDefault(finger.length_m(), defaults.length_m);
  return shape;
}

/// How far the farthest-reaching finger's surface lies from its centre [m]: radius plus half the
/// capsule, the largest over the scene's fingers; 0 without fingers.
inline double FingerReachM(const v1::Scene& scene) {
  double reach_m = 0.0;
  for (const v1::FingerSpec& f : scene.fingers()) {
    const contact::FingerShape shape = FingerShapeFromScene(f);
    reach_m = std::max(reach_m, shape.radius_m + 0.5 * shape.length_m);
  }
  return reach_m;
}

/// The local patch's margin beyond the fingers' reach [m] (model.patch_radius_m, default 15 mm).
inline double PatchMarginM(const v1::Scene& scene) { return OrDefault(scene.model().patch_radius_m(), 0.015); }

/// The services' rates (scene.proto's Rates). No core owns them: the loops are the services'.
inline constexpr double kDefaultGlobalHz = 100.0;
inline constexpr double kDefaultLocalHz = 1000.0;
inline constexpr double kDefaultClothFrameHz = 30.0;
inline constexpr double kMaxClothFrameHz = 60.0;
inline double GlobalRateHz(const v1::Scene& scene) { return OrDefault(scene.rates().global_hz(), kDefaultGlobalHz); }
inline double LocalRateHz(const v1::Scene& scene) { return OrDefault(scene.rates().local_hz(), kDefaultLocalHz); }
/// FingerStates to local_contact: the local rate unless given.
inline double FingerStatesToLocalHz(const v1::Scene& scene) {
  return OrDefault(scene.rates().finger_states_to_local_hz(), LocalRateHz(scene));
}
/// FingerStates to global_sim: the global rate unless given.
inline double FingerStatesToGlobalHz(const v1::Scene& scene) {
  return OrDefault(scene.rates().finger_states_to_global_hz(), GlobalRateHz(scene));
}
inline double ClothFrameHz(const v1::Scene& scene) {
  return std::min(kMaxClothFrameHz, OrDefault(scene.rates().cloth_frame_hz(), kDefaultClothFrameHz));
}

/// The viewer's page and WebSocket (scene.proto's ViewerSpec); 8765 is Foxglove's usual port.
inline constexpr std::uint32_t kDefaultViewerPort = 8765;
inline std::uint32_t ViewerPort(const v1::Scene& scene) {
  return scene.viewer().port() != 0 ? scene.viewer().port() : kDefaultViewerPort;
}
inline std::string ViewerBindAddress(const v1::Scene& scene) {
  return scene.viewer().bind_address().empty() ? std::string("127.0.0.1") : scene.viewer().bind_address();
}

}  // namespace haptex::scene
