// One source of defaults: a scene that gives nothing but its fabric yields exactly the cores' own
// option structs (every default lives in the core; the scene layer only overrides what a scene
// gives), and the scene layer's own values (rates, margin) are the documented ones.

#include "libs/scene/scene_defaults.h"

#include <gtest/gtest.h>

#include "libs/contact/haptic_step_options.h"
#include "libs/scene/cloth_setup.h"
#include "libs/scene/scene_contact.h"
#include "libs/scene/scene_device.h"
#include "libs/scene/scene_loader.h"
#include "libs/scene/tactile_fabric.h"
#include "tests/support/test_paths.h"

namespace haptex::scene {
namespace {

// A database fabric without thickness or fingertip friction, so that nothing fabric-specific
// overrides a contact default.
LoadedScene EmptyScene(const std::string& more = "") {
  const FabricDatabase db(haptex::testing::SourceDir() + "/data/fabrics");
  return ParseScene("name: \"empty\"\nfabric { database_name: \"wang2011_black_denim_11oz\" }\n" + more, "empty", db);
}

void ExpectSameShape(const contact::FingerShape& a, const contact::FingerShape& b) {
  EXPECT_EQ(a.radius_m, b.radius_m);
  EXPECT_EQ(a.length_m, b.length_m);
}

TEST(SceneDefaultsTest, EmptySceneGivesTheContactCoreDefaults) {
  const LoadedScene loaded =
      EmptyScene("fingers { finger: FINGER_THUMB }\nfingers { finger: FINGER_INDEX }\ndevice { mock {} }\n");
  ASSERT_FALSE(loaded.fabric.has_finger_friction());
  ASSERT_EQ(loaded.fabric.thickness_mm(), 0.0);
  const contact::ContactOptions core;
  const contact::ContactOptions o = ContactOptionsFromScene(loaded);
  ExpectSameShape(o.thumb, core.thumb);
  ExpectSameShape(o.index, core.index);
  EXPECT_EQ(o.fabric_half_thickness_m, core.fabric_half_thickness_m);
  EXPECT_EQ(o.finger_fabric.mu_static, core.finger_fabric.mu_static);
  EXPECT_EQ(o.finger_fabric.mu_dynamic, core.finger_fabric.mu_dynamic);
  EXPECT_EQ(o.finger_finger.mu_static, core.finger_finger.mu_static);
  EXPECT_EQ(o.finger_finger.mu_dynamic, core.finger_finger.mu_dynamic);
  EXPECT_EQ(FingerReachM(loaded.scene), core.thumb.radius_m + 0.5 * core.thumb.length_m);

  const textile::StepOptions local = LocalStepOptions(loaded.scene, LocalRateHz(loaded.scene));
  const textile::StepOptions haptic = contact::HapticPatchStepOptions(1.0 / kDefaultLocalHz);
  EXPECT_EQ(local.dt_s, haptic.dt_s);
  EXPECT_EQ(local.cg_tolerance, haptic.cg_tolerance);
  EXPECT_EQ(local.cg_max_iterations, haptic.cg_max_iterations);
  EXPECT_EQ(local.preconditioner, haptic.preconditioner);
}

TEST(SceneDefaultsTest, EmptySceneGivesTheTextileCoreDefaults) {
  const ClothSetup setup = MakeClothSetup(EmptyScene());
  const textile::GridSpec grid;
  EXPECT_EQ(setup.grid.length_warp_m, grid.length_warp_m);
  EXPECT_EQ(setup.grid.width_weft_m, grid.width_weft_m);
  EXPECT_EQ(setup.grid.particles_warp, grid.particles_warp);
  EXPECT_EQ(setup.grid.particles_weft, grid.particles_weft);
  const textile::StepOptions step;
  EXPECT_EQ(setup.step_options.method, step.method);
  EXPECT_EQ(setup.step_options.dt_s, 1.0 / kDefaultGlobalHz);
  EXPECT_EQ(setup.step_options.dt_s, step.dt_s);
  EXPECT_EQ(setup.step_options.cg_tolerance, step.cg_tolerance);
  EXPECT_EQ(setup.step_options.cg_max_iterations, step.cg_max_iterations);
  EXPECT_EQ(setup.step_options.preconditioner, step.preconditioner);
  EXPECT_EQ(setup.step_options.substeps, step.substeps);
  const textile::ModelOptions model;
  EXPECT_EQ(setup.model_options.drag.linear_N_s_per_m3, model.drag.linear_N_s_per_m3);
  EXPECT_EQ(setup.model_options.drag.quadratic_coefficient, model.drag.quadratic_coefficient);
  EXPECT_EQ(setup.model_options.gravity_m_per_s2, model.gravity_m_per_s2);
}

TEST(SceneDefaultsTest, EmptySceneGivesTheDeviceCoreDefaults) {
  const device::DeviceBridgeConfig core;
  const device::DeviceBridgeConfig c = BridgeConfigFromScene(EmptyScene().scene);
  EXPECT_EQ(c.safety.peak_force_N, core.safety.peak_force_N);
  EXPECT_EQ(c.safety.continuous_force_N, core.safety.continuous_force_N);
  EXPECT_EQ(c.safety.stale_after_s, core.safety.stale_after_s);
  EXPECT_EQ(c.safety.stale_ramp_s, core.safety.stale_ramp_s);
  EXPECT_EQ(c.device_lost_after_s, core.device_lost_after_s);
  EXPECT_TRUE(c.X_WD.isApprox(core.X_WD, 0.0)) << "D = W unless the scene places the device";
  // local_contact's ForceModel ttl is the bridge's staleness limit
  EXPECT_EQ(ForceModelStaleS(EmptyScene().scene), core.safety.stale_after_s);

  const device::ScriptParams user_core;
  const device::ScriptParams user =
      MockScriptFromScene(EmptyScene("device { mock { user { kind: KIND_DEMO } } }\n").scene, {});
  EXPECT_EQ(user.speed_m_per_s, user_core.speed_m_per_s);
  EXPECT_EQ(user.hold_s, user_core.hold_s);
  EXPECT_EQ(user.rub_amplitude_m, user_core.rub_amplitude_m);
  EXPECT_EQ(user.stretch_D_m, user_core.stretch_D_m);
  EXPECT_EQ(user.press_depth_m, kDefaultSqueezeForceN / device::MockControllerConfig{}.finger.user_stiffness_N_per_m);
}

TEST(SceneDefaultsTest, EmptySceneGivesTheTactileCoreDefaultsAndTheDocumentedRates) {
  EXPECT_EQ(RendererConfigFromScene(EmptyScene().scene).display_rate_hz, tactile::RendererConfig{}.display_rate_hz);
  const v1::Scene scene = EmptyScene().scene;
  EXPECT_EQ(GlobalRateHz(scene), 100.0);
  EXPECT_EQ(LocalRateHz(scene), 1000.0);
  EXPECT_EQ(FingerStatesToLocalHz(scene), LocalRateHz(scene));
  EXPECT_EQ(FingerStatesToGlobalHz(scene), GlobalRateHz(scene));
  EXPECT_EQ(ClothFrameHz(scene), 30.0);
  EXPECT_EQ(PatchMarginM(scene), 0.015);
}

}  // namespace
}  // namespace haptex::scene
