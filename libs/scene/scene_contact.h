#pragma once
// A scene's fingers, friction and fabric as the contact core's options, and the local patch's
// step: contact::ContactOptions owns every default, the scene overrides what it gives.

#include <array>

#include "haptex/v1/scene.pb.h"
#include "libs/contact/contact_options.h"
#include "libs/scene/scene_loader.h"
#include "libs/textile/step_options.h"

namespace haptex::scene {

/// Fingers (shape), friction (the scene's, else the fabric's fingertip friction, else
/// ContactOptions'), half the fabric's thickness (ContactOptions' when unknown).
/// @throws std::invalid_argument when the result is not valid.
contact::ContactOptions ContactOptionsFromScene(const LoadedScene& scene);

/// Which fingers the scene simulates (index 0 thumb, 1 index).
std::array<bool, 2> SceneFingers(const v1::Scene& scene);

/// The local integrator at `local_hz`: contact::HapticPatchStepOptions with the scene's
/// local_cg_tolerance and local_cg_max_iterations where set (or the scene's semi-implicit
/// choice): the haptic budget rules.
textile::StepOptions LocalStepOptions(const v1::Scene& scene, double local_hz);

}  // namespace haptex::scene
