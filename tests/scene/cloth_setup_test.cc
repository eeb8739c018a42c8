#include "libs/scene/cloth_setup.h"

#include <cmath>

#include <gtest/gtest.h>

#include "tests/scene/scene_test_support.h"

namespace haptex::scene {
namespace {

LoadedScene Scene(const std::string& extra) {
  const FabricDatabase db(testing::TestDataDir() + "/fabrics");
  return ParseScene("name: \"t\"\nfabric { database_name: \"test_cotton\" }\n" + extra, "t", db);
}

TEST(ClothSetupTest, HangsFromTheTopEdgeInTheWorldFrame) {
  const ClothSetup setup =
      MakeClothSetup(Scene("cloth { width_m: 0.2 height_m: 0.3 particles_u: 5 particles_v: 7 "
                           "stand_position_w_m { z: 1.0 } }"));
  ASSERT_EQ(setup.fixed_particles, (std::vector<int>{0, 1, 2, 3, 4}));
  const ClothInstance cloth = MakeClothInstance(setup);
  EXPECT_TRUE(cloth.state.x(0).isApprox(Eigen::Vector3d(-0.1, 0, 1.0)));
  EXPECT_TRUE(cloth.state.x(34).isApprox(Eigen::Vector3d(0.1, 0, 0.7)));  // bottom right
  EXPECT_EQ(cloth.state.mode[2], textile::ParticleMode::kPrescribed);
  EXPECT_EQ(cloth.state.mode[5], textile::ParticleMode::kFree);
  EXPECT_DOUBLE_EQ(setup.step_options.dt_s, 0.01);  // 1 / default 100 Hz
  EXPECT_EQ(setup.step_options.method, textile::StepOptions{}.method);
}

TEST(ClothSetupTest, FlatLedgeFixesTheRowsOnTheLedge) {
  const ClothSetup setup =
      MakeClothSetup(Scene("cloth { width_m: 0.04 height_m: 0.2 particles_u: 3 particles_v: 11 "
                           "mounting: MOUNTING_FLAT_LEDGE ledge_v_m: 0.04 }"));
  // rows v = 0, 0.02, 0.04 rest on the ledge
  EXPECT_EQ(setup.fixed_particles.size(), 9u);
  const ClothInstance cloth = MakeClothInstance(setup);
  EXPECT_NEAR(cloth.state.x(32)(2), 0.0, 1e-12);  // flat in z = 0
  EXPECT_NEAR(cloth.state.x(32)(1), 0.2, 1e-12);  // along +y
}

TEST(ClothSetupTest, ModelDialsComeFromTheScene) {
  const ClothSetup setup = MakeClothSetup(
      Scene("rates { global_hz: 50 }\nmodel { global_integrator: INTEGRATOR_SEMI_IMPLICIT cg_tolerance: 1e-5 "
            "disable_gravity: true disable_bending: true disable_air_drag: true }"));
  EXPECT_EQ(setup.step_options.method, textile::Integrator::kSymplecticEuler);
  EXPECT_DOUBLE_EQ(setup.step_options.dt_s, 0.02);
  EXPECT_DOUBLE_EQ(setup.step_options.cg_tolerance, 1e-5);
  EXPECT_TRUE(setup.model_options.gravity_m_per_s2.isZero());
  EXPECT_EQ(setup.material.bending_warp_Nm, 0.0);
  EXPECT_EQ(setup.model_options.drag.quadratic_coefficient, 0.0);
}

// Each integrator the scene names; none named is the step options' own default.
TEST(ClothSetupTest, IntegratorComesFromTheSceneElseTheStepOptionsDefault) {
  EXPECT_EQ(MakeClothSetup(Scene("")).step_options.method, textile::StepOptions{}.method);
  EXPECT_EQ(MakeClothSetup(Scene("model { global_integrator: INTEGRATOR_BDF2 newton_max_iterations: 4 }"))
                .step_options.method,
            textile::Integrator::kBdf2);
  EXPECT_EQ(MakeClothSetup(Scene("model { global_integrator: INTEGRATOR_IMPLICIT_EULER }")).step_options.method,
            textile::Integrator::kImplicitEuler);
}

// The scene gives the fabric's cut in degrees; the model takes radians, 0 when not given.
TEST(ClothSetupTest, MaterialAngleReachesTheModel) {
  EXPECT_EQ(MakeClothSetup(Scene("")).model_options.material_angle_rad, 0.0);
  const ClothSetup bias = MakeClothSetup(Scene("cloth { particles_u: 3 particles_v: 3 material_angle_deg: 45 }"));
  EXPECT_DOUBLE_EQ(bias.model_options.material_angle_rad, std::atan(1.0));
  const ClothInstance cloth = MakeClothInstance(bias);
  EXPECT_DOUBLE_EQ(cloth.model.options.material_angle_rad, std::atan(1.0));
}

TEST(SceneLoadsTest, RampsInHoldsAndRampsOut) {
  v1::Load load;
  load.set_start_s(1.0);
  load.set_end_s(3.0);
  load.set_ramp_s(0.5);
  EXPECT_EQ(SceneLoads::Factor(load, 0.9), 0.0);
  EXPECT_DOUBLE_EQ(SceneLoads::Factor(load, 1.25), 0.5);
  EXPECT_EQ(SceneLoads::Factor(load, 2.0), 1.0);
  EXPECT_DOUBLE_EQ(SceneLoads::Factor(load, 2.75), 0.5);
  EXPECT_EQ(SceneLoads::Factor(load, 3.1), 0.0);
}

TEST(SceneLoadsTest, BottomEdgeLoadAddsUpToItsTotal) {
  const LoadedScene scene = Scene(
      "cloth { particles_u: 6 particles_v: 4 }\n"
      "loads { kind: KIND_BOTTOM_EDGE force_w_n { z: -2.4 } }\n"
      "loads { kind: KIND_POINT particle: 0 force_w_n { x: 1 } start_s: 5 }");
  ClothInstance cloth = MakeClothInstance(MakeClothSetup(scene));
  const SceneLoads loads(scene.scene, cloth.model);
  loads.Apply(0.0, &cloth.state);
  Eigen::Vector3d total = Eigen::Vector3d::Zero();
  for (int p = 0; p < cloth.state.num_particles(); ++p) total += cloth.state.external_force_W_N.segment<3>(3 * p);
  EXPECT_TRUE(total.isApprox(Eigen::Vector3d(0, 0, -2.4))) << total.transpose();
  EXPECT_EQ(cloth.state.external_force_W_N.segment<3>(0).norm(), 0.0);  // point load not yet on
  loads.Apply(6.0, &cloth.state);
  EXPECT_DOUBLE_EQ(cloth.state.external_force_W_N(0), 1.0);
}

TEST(SceneLoadsTest, PointLoadOnAMissingParticleIsRefused) {
  const LoadedScene scene = Scene("cloth { particles_u: 3 particles_v: 3 }\nloads { kind: KIND_POINT particle: 8 }");
  ClothInstance cloth = MakeClothInstance(MakeClothSetup(scene));
  v1::Scene bad = scene.scene;
  bad.mutable_loads(0)->set_particle(9);
  EXPECT_THROW(SceneLoads(bad, cloth.model), std::invalid_argument);
  EXPECT_NO_THROW(SceneLoads(scene.scene, cloth.model));
}

}  // namespace
}  // namespace haptex::scene
