// local_contact's configuration from the scene: the haptic step and its dials.

#include "services/local_contact/contact_config.h"

#include <gtest/gtest.h>

#include "libs/contact/haptic_step_options.h"
#include "tests/scene/scene_test_support.h"

namespace haptex::local_contact {
namespace {

scene::LoadedScene Scene(const std::string& model) {
  const scene::FabricDatabase db(scene::testing::TestDataDir() + "/fabrics");
  return scene::ParseScene("name: \"x\"\nfabric { database_name: \"test_cotton\" }\n" + model, "t", db);
}

TEST(ContactConfigTest, LocalStepIsTheHapticStepAtTheLocalRate) {
  const textile::StepOptions step = LocalStepOptions(Scene(""), 2000.0);
  const textile::StepOptions haptic = contact::HapticPatchStepOptions(0.0005);
  EXPECT_EQ(step.method, textile::Integrator::kImplicitEuler);
  EXPECT_DOUBLE_EQ(step.dt_s, 0.0005);
  EXPECT_EQ(step.preconditioner, textile::Preconditioner::kGaussSeidel);
  EXPECT_EQ(step.preconditioner, haptic.preconditioner);
  EXPECT_DOUBLE_EQ(step.ssor_omega, haptic.ssor_omega);
  EXPECT_DOUBLE_EQ(step.cg_tolerance, haptic.cg_tolerance);
  EXPECT_EQ(step.cg_max_iterations, haptic.cg_max_iterations);
  EXPECT_NO_THROW(textile::ValidateStepOptions(step));
}

TEST(ContactConfigTest, SceneDialsSetTheLocalSolve) {
  const textile::StepOptions step =
      LocalStepOptions(Scene("model { local_cg_tolerance: 1e-3 local_cg_max_iterations: 20 }\n"), 1000.0);
  EXPECT_DOUBLE_EQ(step.cg_tolerance, 1e-3);
  EXPECT_EQ(step.cg_max_iterations, 20);
  EXPECT_EQ(step.preconditioner, textile::Preconditioner::kGaussSeidel);
}

TEST(ContactConfigTest, SemiImplicitChoiceIsKept) {
  const textile::StepOptions step =
      LocalStepOptions(Scene("model { local_integrator: INTEGRATOR_SEMI_IMPLICIT }\n"), 1000.0);
  EXPECT_EQ(step.method, textile::Integrator::kSymplecticEuler);
}

}  // namespace
}  // namespace haptex::local_contact
