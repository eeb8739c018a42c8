#include "libs/scene/scene_contact.h"

#include "libs/codec/message_conversion.h"
#include "libs/contact/haptic_step_options.h"
#include "libs/scene/scene_defaults.h"

namespace haptex::scene {

contact::ContactOptions ContactOptionsFromScene(const LoadedScene& loaded) {
  const v1::Scene& sc = loaded.scene;
  contact::ContactOptions o;
  for (const v1::FingerSpec& f : sc.fingers()) {
    const int slot = codec::FingerSlot(f.finger());
    if (slot == codec::kThumbSlot) o.thumb = FingerShapeFromScene(f);
    if (slot == codec::kIndexSlot) o.index = FingerShapeFromScene(f);
  }
  const v1::Fabric& fabric = loaded.fabric;
  contact::FrictionCoefficients finger_fabric = o.finger_fabric;
  if (fabric.has_finger_friction() && fabric.finger_friction().mu_static() > 0) {
    finger_fabric = {fabric.finger_friction().mu_static(), fabric.finger_friction().mu_dynamic()};
  }
  const v1::FrictionSpec& fr = sc.friction();
  o.finger_fabric = {OrDefault(fr.finger_fabric_mu_static(), finger_fabric.mu_static),
                     OrDefault(fr.finger_fabric_mu_dynamic(), finger_fabric.mu_dynamic)};
  o.finger_finger = {OrDefault(fr.finger_finger_mu_static(), o.finger_finger.mu_static),
                     OrDefault(fr.finger_finger_mu_dynamic(), o.finger_finger.mu_dynamic)};
  o.fabric_half_thickness_m = OrDefault(0.5 * fabric.thickness_mm() * 1e-3, o.fabric_half_thickness_m);
  contact::ValidateContactOptions(o);
  return o;
}

std::array<bool, 2> SceneFingers(const v1::Scene& scene) {
  std::array<bool, 2> present{false, false};
  for (const v1::FingerSpec& f : scene.fingers()) {
    const int slot = codec::FingerSlot(f.finger());
    if (slot >= 0) present[static_cast<std::size_t>(slot)] = true;
  }
  return present;
}

textile::StepOptions LocalStepOptions(const v1::Scene& scene, double local_hz) {
  textile::StepOptions step = contact::HapticPatchStepOptions(1.0 / local_hz);
  const v1::ModelOptions& m = scene.model();
  if (m.local_cg_tolerance() > 0) step.cg_tolerance = m.local_cg_tolerance();
  if (m.local_cg_max_iterations() > 0) step.cg_max_iterations = static_cast<int>(m.local_cg_max_iterations());
  step.method = IntegratorOr(m.local_integrator(), step.method);
  if (step.method == textile::Integrator::kSymplecticEuler) step.max_substeps = 2000;
  return step;
}

}  // namespace haptex::scene
