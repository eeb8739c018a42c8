#include "services/local_contact/contact_config.h"

#include <array>

#include "libs/contact/haptic_step_options.h"

namespace haptex::local_contact {
namespace {

double Or(double v, double fallback) { return v > 0 ? v : fallback; }

}  // namespace

contact::ContactOptions ContactOptionsFromScene(const scene::LoadedScene& loaded) {
  const v1::Scene& sc = loaded.scene;
  contact::ContactOptions o;
  for (const v1::FingerSpec& f : sc.fingers()) {
    contact::FingerShape shape;
    shape.radius_m = Or(f.radius_m(), 0.008);
    shape.length_m = f.shape() == v1::FingerSpec::SHAPE_SPHERE ? 0.0 : Or(f.length_m(), 0.012);
    if (f.finger() == v1::FINGER_THUMB) o.thumb = shape;
    if (f.finger() == v1::FINGER_INDEX) o.index = shape;
  }
  const v1::Fabric& fabric = loaded.fabric;
  double mu_s = 0.4, mu_d = 0.2;
  if (fabric.has_finger_friction() && fabric.finger_friction().mu_static() > 0) {
    mu_s = fabric.finger_friction().mu_static();
    mu_d = fabric.finger_friction().mu_dynamic();
  }
  const v1::FrictionSpec& fr = sc.friction();
  o.finger_fabric = {Or(fr.finger_fabric_mu_static(), mu_s), Or(fr.finger_fabric_mu_dynamic(), mu_d)};
  o.finger_finger = {Or(fr.finger_finger_mu_static(), 0.8), Or(fr.finger_finger_mu_dynamic(), 0.6)};
  o.fabric_half_thickness_m = 0.5 * Or(fabric.thickness_mm() * 1e-3, 0.0006);
  contact::ValidateContactOptions(o);
  return o;
}

std::array<bool, 2> SceneFingers(const scene::LoadedScene& loaded) {
  std::array<bool, 2> present{false, false};
  for (const v1::FingerSpec& f : loaded.scene.fingers()) {
    if (f.finger() == v1::FINGER_THUMB) present[0] = true;
    if (f.finger() == v1::FINGER_INDEX) present[1] = true;
  }
  return present;
}

textile::StepOptions LocalStepOptions(const scene::LoadedScene& loaded, double local_hz) {
  textile::StepOptions step = contact::HapticPatchStepOptions(1.0 / local_hz);
  const v1::ModelOptions& m = loaded.scene.model();
  if (m.local_cg_tolerance() > 0) step.cg_tolerance = m.local_cg_tolerance();
  if (m.local_cg_max_iterations() > 0) step.cg_max_iterations = static_cast<int>(m.local_cg_max_iterations());
  if (m.local_integrator() == v1::ModelOptions::INTEGRATOR_SEMI_IMPLICIT) {
    step.method = textile::Integrator::kSymplecticEuler;
    step.max_substeps = 2000;
  }
  return step;
}

}  // namespace haptex::local_contact
