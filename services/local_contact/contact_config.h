#pragma once
// The scene's fingers, friction and fabric as contact-model options, and the local patch's step.

#include "libs/contact/contact_options.h"
#include "libs/scene/scene_loader.h"
#include "libs/textile/step_options.h"

namespace haptex::local_contact {

/// Fingers (shape, radius, length), friction (scene, else the fabric's fingertip friction, else
/// 0.4/0.2 and 0.8/0.6) and half the fabric's thickness (0.3 mm when unknown).
/// @throws std::invalid_argument when the result is not valid.
contact::ContactOptions ContactOptionsFromScene(const scene::LoadedScene& scene);

/// Which fingers the scene simulates (index 0 thumb, 1 index).
std::array<bool, 2> SceneFingers(const scene::LoadedScene& scene);

/// The local integrator at `local_hz`: contact::HapticPatchStepOptions with the scene's
/// local_cg_tolerance and local_cg_max_iterations where set (or the scene's semi-implicit
/// choice): the haptic budget rules.
textile::StepOptions LocalStepOptions(const scene::LoadedScene& scene, double local_hz);

}  // namespace haptex::local_contact
