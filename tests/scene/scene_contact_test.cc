// The contact core's options from a scene: the haptic step and its dials.

#include "libs/scene/scene_contact.h"

#include <gtest/gtest.h>

#include "libs/contact/haptic_step_options.h"
#include "tests/scene/scene_test_support.h"

namespace haptex::scene {
namespace {

LoadedScene Scene(const std::string& model) {
  const FabricDatabase db(testing::TestDataDir() + "/fabrics");
  return ParseScene("name: \"x\"\nfabric { database_name: \"test_cotton\" }\n" + model, "t", db);
}

TEST(SceneContactTest, LocalStepIsTheHapticStepAtTheLocalRate) {
  const textile::StepOptions step = LocalStepOptions(Scene("").scene, 2000.0);
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

TEST(SceneContactTest, SceneDialsSetTheLocalSolve) {
  const textile::StepOptions step =
      LocalStepOptions(Scene("model { local_cg_tolerance: 1e-3 local_cg_max_iterations: 20 }\n").scene, 1000.0);
  EXPECT_DOUBLE_EQ(step.cg_tolerance, 1e-3);
  EXPECT_EQ(step.cg_max_iterations, 20);
  EXPECT_EQ(step.preconditioner, textile::Preconditioner::kGaussSeidel);
}

TEST(SceneContactTest, SemiImplicitChoiceIsKept) {
  const textile::StepOptions step =
      LocalStepOptions(Scene("model { local_integrator: INTEGRATOR_SEMI_IMPLICIT }\n").scene, 1000.0);
  EXPECT_EQ(step.method, textile::Integrator::kSymplecticEuler);
  EXPECT_EQ(LocalStepOptions(Scene("").scene, 1000.0).method, textile::Integrator::kImplicitEuler);
}

}  // namespace
}  // namespace haptex::scene
