#include "libs/textile/shear_force.h"

#include <gtest/gtest.h>

#include "libs/textile/fabric_state.h"
#include "libs/textile/kes_material.h"
#include "tests/textile/force_jacobian_check.h"

namespace haptex::textile {
namespace {

TEST(ShearForceTest, JacobianMatchesFiniteDifferencesNearZeroShear) {
  const FabricModel model = BuildFabricModel(MaterialFromKes(testing::CompositeDenim()), {0.03, 0.02, 4, 3});
  FabricState s = MakeRestState(model);
  testing::Perturb(&s, 1e-6, 0.01, 11);
  Eigen::VectorXd f;
  Eigen::MatrixXd jx, jv;
  testing::DenseForceAndJacobians(model, AddShearForces, s.x_W_m, s.v_W_m_per_s, &f, &jx, &jv);
  const auto fdx = testing::FiniteDifferenceJacobian(model, AddShearForces, s.x_W_m, s.v_W_m_per_s, false, 1e-8);
  const auto fdv = testing::FiniteDifferenceJacobian(model, AddShearForces, s.x_W_m, s.v_W_m_per_s, true, 1e-6);
  // The dropped tau-term vanishes with the shear: small deformation, small mismatch.
  testing::ExpectJacobianNear(jx, fdx, 2e-2, "df/dx");
  testing::ExpectJacobianNear(jv, fdv, 1e-6, "df/dv");
}

// gamma = U.V with the yarn vectors of a fabric cut at an angle to the grid: the same Jacobian
// check as on the grid's axes.
TEST(ShearForceTest, JacobianMatchesFiniteDifferencesOnTheBias) {
  ModelOptions options;
  options.material_angle_rad = -0.7;
  const FabricModel model = BuildFabricModel(MaterialFromKes(testing::CompositeDenim()), {0.03, 0.02, 4, 3}, options);
  FabricState s = MakeRestState(model);
  testing::Perturb(&s, 1e-6, 0.01, 13);
  Eigen::VectorXd f;
  Eigen::MatrixXd jx, jv;
  testing::DenseForceAndJacobians(model, AddShearForces, s.x_W_m, s.v_W_m_per_s, &f, &jx, &jv);
  const auto fdx = testing::FiniteDifferenceJacobian(model, AddShearForces, s.x_W_m, s.v_W_m_per_s, false, 1e-8);
  const auto fdv = testing::FiniteDifferenceJacobian(model, AddShearForces, s.x_W_m, s.v_W_m_per_s, true, 1e-6);
  testing::ExpectJacobianNear(jx, fdx, 2e-2, "df/dx");
  testing::ExpectJacobianNear(jv, fdv, 1e-6, "df/dv");
}

TEST(ShearForceTest, SimpleShearGivesKesStiffness) {
  const FabricMaterial material = MaterialFromKes(testing::CompositeDenim());
  const FabricModel model = BuildFabricModel(material, {0.05, 0.05, 3, 3});
  FabricState s = MakeRestState(model);
  const double gamma = 0.01;  // rad: x += gamma * y
  for (int p = 0; p < model.num_particles; ++p) s.x(p).x() += gamma * s.x(p).y();
  Eigen::VectorXd f = Eigen::VectorXd::Zero(3 * model.num_particles);
  ForceSink sink;
  sink.force_N = &f;
  AddShearForces(model, s.x_W_m, s.v_W_m_per_s, &sink);
  // Force on the top edge (v = max) along warp = -tau * edge length.
  double top = 0.0;
  for (int i = 0; i < 3; ++i) top += f[3 * model.mesh.Index(i, 2)];
  EXPECT_NEAR(top, -material.shear.Value(gamma) * 0.05, 1e-6 * std::abs(top));
}

}  // namespace
}  // namespace haptex::textile
