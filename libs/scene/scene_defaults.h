#pragma once
// The scene's values where a field is 0 (proto3: not given): one place for the defaults that the
// loader's checks and the services both apply.

#include <algorithm>

#include "haptex/v1/scene.pb.h"

namespace haptex::scene {

inline double OrDefault(double value, double fallback) { return value > 0 ? value : fallback; }

/// Cloth size along warp and weft [m] (default 0.20) and particles per row and column (default 41).
inline double ClothWidthM(const v1::ClothGeometry& c) { return OrDefault(c.width_m(), 0.20); }
inline double ClothHeightM(const v1::ClothGeometry& c) { return OrDefault(c.height_m(), 0.20); }
inline int ClothParticlesU(const v1::ClothGeometry& c) { return c.particles_u() > 0 ? static_cast<int>(c.particles_u()) : 41; }
inline int ClothParticlesV(const v1::ClothGeometry& c) { return c.particles_v() > 0 ? static_cast<int>(c.particles_v()) : 41; }

/// How far the farthest-reaching finger's surface lies from its centre [m]: radius (default 8 mm)
/// plus half the capsule (default 12 mm), the largest over the scene's fingers; 0 without fingers.
inline double FingerReachM(const v1::Scene& scene) {
  double reach_m = 0.0;
  for (const v1::FingerSpec& f : scene.fingers()) {
    reach_m = std::max(reach_m, OrDefault(f.radius_m(), 0.008) + 0.5 * OrDefault(f.length_m(), 0.012));
  }
  return reach_m;
}

/// The local patch's margin beyond the fingers' reach [m] (model.patch_radius_m, default 15 mm).
inline double PatchMarginM(const v1::Scene& scene) { return OrDefault(scene.model().patch_radius_m(), 0.015); }

}  // namespace haptex::scene
