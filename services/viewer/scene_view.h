#pragma once
// The 3-D scene for Foxglove's 3D panel as one foxglove.SceneUpdate in the world frame W: the cloth
// as a triangle mesh (the local patch coloured) with a clamp at each particle the stand holds, each finger as its
// capsule (a cylinder and two spheres) at the device's pose, and the force on it as an arrow. Built into one reused
// message.

#include <array>
#include <cstdint>
#include <vector>

#include "foxglove/SceneUpdate.pb.h"
#include "haptex/v1/finger_states.pb.h"
#include "haptex/v1/force_model.pb.h"
#include "libs/scene/scene_loader.h"

namespace haptex::viewer {

struct SceneViewConfig {
  struct Finger {
    double radius_m = 0.008, length_m = 0.012;
  };
  std::array<Finger, 2> fingers{};             ///< by codec slot: 0 thumb, 1 index
  std::vector<std::uint32_t> fixed_particles;  ///< where the stand holds the cloth: drawn as clamps
  double arrow_m_per_N = 0.02;                 ///< a 1 N force is drawn 2 cm long
};

/// The grid rectangle of the local patch (ClothFrame's patch_*): i_u in [u_begin, u_end), i_v in
/// [v_begin, v_end); empty when begin = end.
struct PatchGridRect {
  std::uint32_t u_begin = 0, u_end = 0, v_begin = 0, v_end = 0;
  bool Contains(std::uint32_t i_u, std::uint32_t i_v) const {
    return i_u >= u_begin && i_u < u_end && i_v >= v_begin && i_v < v_end;
  }
};

/// Where the stand holds the cloth (the scene's fixed particles); none when the scene's fabric does
/// not load (global_sim refuses such a scene and says why). The page and the SceneUpdate draw both.
std::vector<std::uint32_t> StandParticles(const scene::LoadedScene& scene);

SceneViewConfig SceneViewConfigFromScene(const scene::LoadedScene& scene);

class SceneView {
 public:
  explicit SceneView(const SceneViewConfig& config) : config_(config) {}

  /// `cloth_W_m`: 3 floats per particle of a u x v grid (particle i_u + u i_v); `patch` coloured.
  const foxglove::SceneUpdate& Build(const std::vector<float>& cloth_W_m, std::uint32_t u, std::uint32_t v,
                                     const PatchGridRect& patch, const v1::FingerStates& fingers,
                                     const v1::ForceModel& forces, std::uint64_t time_ns);

 private:
  SceneViewConfig config_;
  foxglove::SceneUpdate update_;
  std::uint32_t indexed_u_ = 0, indexed_v_ = 0;
};

}  // namespace haptex::viewer
