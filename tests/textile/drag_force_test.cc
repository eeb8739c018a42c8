#include "libs/textile/drag_force.h"

#include <gtest/gtest.h>

#include "libs/textile/fabric_state.h"
#include "libs/textile/kes_material.h"
#include "tests/textile/force_jacobian_check.h"

namespace haptex::textile {
namespace {

TEST(DragForceTest, VelocityJacobianMatchesFiniteDifferences) {
  const FabricModel model = BuildFabricModel(MaterialFromKes(testing::CompositeDenim()), {0.03, 0.02, 4, 3});
  FabricState s = MakeRestState(model);
  testing::Perturb(&s, 1e-3, 0.5, 5);
  Eigen::VectorXd f;
  Eigen::MatrixXd jx, jv;
  testing::DenseForceAndJacobians(model, AddDragForces, s.x_W_m, s.v_W_m_per_s, &f, &jx, &jv);
  const auto fdv = testing::FiniteDifferenceJacobian(model, AddDragForces, s.x_W_m, s.v_W_m_per_s, true, 1e-7);
  testing::ExpectJacobianNear(jv, fdv, 1e-5, "df/dv");
}

TEST(DragForceTest, QuadraticDragOpposesNormalMotion) {
  ModelOptions o;
  o.drag.linear_N_s_per_m3 = 0.0;
  const FabricModel model = BuildFabricModel(MaterialFromKes(testing::CompositeDenim()), {0.1, 0.1, 3, 3}, o);
  FabricState s = MakeRestState(model);
  for (int p = 0; p < model.num_particles; ++p) s.v(p) = Eigen::Vector3d(0, 0, 2.0);
  Eigen::VectorXd f = Eigen::VectorXd::Zero(3 * model.num_particles);
  ForceSink sink;
  sink.force_N = &f;
  AddDragForces(model, s.x_W_m, s.v_W_m_per_s, &sink);
  double fz = 0.0;
  for (int p = 0; p < model.num_particles; ++p) fz += f[3 * p + 2];
  EXPECT_NEAR(fz, -0.5 * 1.2 * 1.5 * 0.01 * 4.0, 1e-12);
}

}  // namespace
}  // namespace haptex::textile
