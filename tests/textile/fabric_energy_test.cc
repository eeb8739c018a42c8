#include "libs/textile/fabric_energy.h"

#include <gtest/gtest.h>

#include "libs/textile/anchor_spring_force.h"
#include "libs/textile/fabric_forces.h"
#include "libs/textile/kes_material.h"
#include "libs/textile/validation.h"
#include "tests/textile/textile_test_util.h"

namespace haptex::textile {
namespace {

// Conservative forces only (no damping, no drag): the force is minus the energy's gradient.
FabricModel ConservativeModel() {
  ModelOptions o;
  o.damping = {0.0, 0.0, 0.0};
  o.drag.linear_N_s_per_m3 = 0.0;
  o.drag.quadratic_coefficient = 0.0;
  return BuildFabricModel(MaterialFromKes(testing::CompositeDenim()), {0.1, 0.1, 6, 6}, o);
}

// Deformed in tension, compression, shear and bending, with anchors pulling.
FabricState Deformed(const FabricModel& model) {
  FabricState s = MakeRestState(model);
  validation::Perturb(&s, 0.003, 0.0, 11);
  s.v_W_m_per_s.setZero();
  s.anchor_stiffness_N_per_m[4] = 30.0;
  s.anchor_W_m.segment<3>(12) = s.x(4) + Eigen::Vector3d(0.002, -0.001, 0.003);
  return s;
}

TEST(FabricEnergyTest, ForcesAreMinusTheGradientOfTheEnergy) {
  const FabricModel model = ConservativeModel();
  const FabricState s = Deformed(model);
  Eigen::VectorXd f = Eigen::VectorXd::Zero(3 * model.num_particles);
  ForceSink sink;
  sink.force_N = &f;
  AccumulateForces(model, s, &sink);
  AddAnchorSpringForces(model, s, &sink);
  constexpr double kStep_m = 1e-7;
  for (int i = 0; i < 3 * model.num_particles; ++i) {
    FabricState plus = s, minus = s;
    plus.x_W_m[i] += kStep_m;
    minus.x_W_m[i] -= kStep_m;
    const double gradient = (PotentialEnergy(model, plus) - PotentialEnergy(model, minus)) / (2.0 * kStep_m);
    EXPECT_NEAR(-gradient, f[i], 1e-5 + 1e-5 * std::abs(f[i])) << "coordinate " << i;
  }
}

TEST(FabricEnergyTest, FlatClothAtRestHasOnlyGravitysEnergy) {
  const FabricModel model = ConservativeModel();
  FabricState s = MakeRestState(model);
  const double lift_m = 0.5;
  for (int p = 0; p < model.num_particles; ++p) s.x_W_m[3 * p + 2] = lift_m;
  const double weight_N = model.mass_kg.sum() * 9.81;
  EXPECT_NEAR(PotentialEnergy(model, s), weight_N * lift_m, 1e-12);
  s.v(0) = Eigen::Vector3d(1.0, 0, 0);
  EXPECT_NEAR(TotalEnergy(model, s) - PotentialEnergy(model, s), 0.5 * model.mass_kg[0], 1e-15);
}

}  // namespace
}  // namespace haptex::textile
