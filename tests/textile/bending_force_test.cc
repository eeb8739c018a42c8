#include "libs/textile/bending_force.h"

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "libs/textile/fabric_state.h"
#include "libs/textile/kes_material.h"
#include "tests/textile/force_jacobian_check.h"

namespace haptex::textile {
namespace {

TEST(BendingForceTest, ConstantJacobianMatchesFiniteDifferences) {
  const FabricModel model = BuildFabricModel(MaterialFromKes(testing::CompositeDenim()), {0.03, 0.02, 4, 3});
  FabricState s = MakeRestState(model);
  testing::Perturb(&s, 1e-3, 0.1, 3);
  Eigen::VectorXd f;
  Eigen::MatrixXd jx, jv, jx_rest, jv_rest;
  testing::DenseForceAndJacobians(model, AddBendingForces, s.x_W_m, s.v_W_m_per_s, &f, &jx, &jv);
  const FabricState rest = MakeRestState(model);
  testing::DenseForceAndJacobians(model, AddBendingForces, rest.x_W_m, rest.v_W_m_per_s, &f, &jx_rest, &jv_rest);
  EXPECT_EQ(jx, jx_rest);  // constant
  const auto fdx = testing::FiniteDifferenceJacobian(model, AddBendingForces, s.x_W_m, s.v_W_m_per_s, false, 1e-6);
  const auto fdv = testing::FiniteDifferenceJacobian(model, AddBendingForces, s.x_W_m, s.v_W_m_per_s, true, 1e-6);
  testing::ExpectJacobianNear(jx, fdx, 1e-6, "df/dx");
  testing::ExpectJacobianNear(jv, fdv, 1e-6, "df/dv");
}

TEST(BendingForceTest, RigidMotionGivesNoForce) {
  const FabricModel model = BuildFabricModel(MaterialFromKes(testing::CompositeDenim()), {0.05, 0.04, 5, 4});
  FabricState s = MakeRestState(model);
  const Eigen::Matrix3d rot = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  for (int p = 0; p < model.num_particles; ++p) s.x(p) = rot * s.x(p) + Eigen::Vector3d(1, 2, 3);
  Eigen::VectorXd f = Eigen::VectorXd::Zero(3 * model.num_particles);
  ForceSink sink;
  sink.force_N = &f;
  AddBendingForces(model, s.x_W_m, s.v_W_m_per_s, &sink);
  EXPECT_LT(f.cwiseAbs().maxCoeff(), 1e-12);
}

}  // namespace
}  // namespace haptex::textile
