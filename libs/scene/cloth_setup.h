#pragma once
// A scene's cloth as the physics core wants it: grid, placement in the world frame, fixed
// particles, material, model and step options, and its loads over time.

#include <vector>

#include "haptex/v1/scene.pb.h"
#include "libs/scene/scene_loader.h"
#include "libs/textile/fabric_model.h"
#include "libs/textile/fabric_state.h"
#include "libs/textile/grid_mesh.h"
#include "libs/textile/kes_material.h"
#include "libs/textile/step_options.h"

namespace haptex::scene {

struct ClothSetup {
  textile::FabricMaterial material;
  textile::GridSpec grid;
  textile::Placement placement;
  textile::ModelOptions model_options;
  textile::StepOptions step_options;
  std::vector<int> fixed_particles;
};

/// Scene defaults (scene.proto) applied; the world frame of common.proto: z up, x along the stand
/// bar (warp), the top-left corner at -width/2 on the bar, the fabric hanging along -z (weft),
/// or lying in the z = 0 plane along +y for MOUNTING_FLAT_LEDGE.
/// @throws std::invalid_argument when the fabric data cannot be turned into material laws.
ClothSetup MakeClothSetup(const LoadedScene& scene);

/// A model and a rest state with the scene's fixed particles.
struct ClothInstance {
  textile::FabricModel model;
  textile::FabricState state;
};
ClothInstance MakeClothInstance(const ClothSetup& setup);

/// Sets the scene's loads at time t (ramps in and out) into state->external_force_W_N.
class SceneLoads {
 public:
  SceneLoads(const v1::Scene& scene, const textile::FabricModel& model);
  void Apply(double t_s, textile::FabricState* state) const;
  /// The total load factor of load i at time t (0..1).
  static double Factor(const v1::Load& load, double t_s);

 private:
  const textile::FabricModel& model_;
  std::vector<v1::Load> loads_;
  std::vector<int> bottom_edge_;
};

}  // namespace haptex::scene
