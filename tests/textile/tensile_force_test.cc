#include "libs/textile/tensile_force.h"

#include <gtest/gtest.h>
#include <Eigen/Eigenvalues>

#include "libs/textile/fabric_state.h"
#include "libs/textile/kes_material.h"
#include "tests/textile/force_jacobian_check.h"

namespace haptex::textile {
namespace {

TEST(TensileForceTest, ZeroAtRestAndJacobianMatchesFiniteDifferencesUnderTension) {
  const FabricModel model = BuildFabricModel(MaterialFromKes(testing::CompositeDenim()), {0.03, 0.02, 4, 3});
  FabricState s = MakeRestState(model);
  Eigen::VectorXd f;
  Eigen::MatrixXd jx, jv;
  testing::DenseForceAndJacobians(model, AddTensileForces, s.x_W_m, s.v_W_m_per_s, &f, &jx, &jv);
  EXPECT_LT(f.cwiseAbs().maxCoeff(), 1e-12);

  // Stretch by 2 % along warp and 1 % along weft, then perturb: every element in tension.
  for (int p = 0; p < model.num_particles; ++p) {
    s.x(p) = s.x(p).cwiseProduct(Eigen::Vector3d(1.02, 1.01, 1.0));
  }
  // Position Jacobian at zero velocity (damping's position derivative is dropped by design).
  testing::Perturb(&s, 1e-5, 0.0, 7);
  testing::DenseForceAndJacobians(model, AddTensileForces, s.x_W_m, s.v_W_m_per_s, &f, &jx, &jv);
  const auto fdx = testing::FiniteDifferenceJacobian(model, AddTensileForces, s.x_W_m, s.v_W_m_per_s, false, 1e-8);
  testing::ExpectJacobianNear(jx, fdx, 1e-4, "df/dx");
  testing::Perturb(&s, 0.0, 0.01, 8);
  testing::DenseForceAndJacobians(model, AddTensileForces, s.x_W_m, s.v_W_m_per_s, &f, &jx, &jv);
  const auto fdv = testing::FiniteDifferenceJacobian(model, AddTensileForces, s.x_W_m, s.v_W_m_per_s, true, 1e-6);
  testing::ExpectJacobianNear(jv, fdv, 1e-6, "df/dv");
  // Symmetric, as CG needs.
  EXPECT_LT((jx - jx.transpose()).cwiseAbs().maxCoeff(), 1e-9 * jx.cwiseAbs().maxCoeff());
}

// On the bias the warp and weft vectors mix both grid directions: the weights change, the
// Jacobian must still be the exact tangent, in tension and in compression (where the dropped
// transverse term leaves the positive semi-definite part).
TEST(TensileForceTest, JacobianMatchesFiniteDifferencesOnTheBias) {
  ModelOptions options;
  options.material_angle_rad = 0.5;
  const FabricModel model = BuildFabricModel(MaterialFromKes(testing::CompositeDenim()), {0.03, 0.02, 4, 3}, options);
  for (const double scale : {1.02, 0.98}) {
    FabricState s = MakeRestState(model);
    for (int p = 0; p < model.num_particles; ++p) s.x(p) *= scale;
    testing::Perturb(&s, 1e-5, 0.0, 9);
    Eigen::VectorXd f;
    Eigen::MatrixXd jx, jv;
    testing::DenseForceAndJacobians(model, AddTensileForces, s.x_W_m, s.v_W_m_per_s, &f, &jx, &jv);
    const auto fdx = testing::FiniteDifferenceJacobian(model, AddTensileForces, s.x_W_m, s.v_W_m_per_s, false, 1e-8);
    if (scale > 1.0) {
      testing::ExpectJacobianNear(jx, fdx, 1e-4, "df/dx in tension");
    } else {
      // Compression: the transverse term is dropped by design, so this is not the full tangent;
      // what CG relies on is that it stays negative semi-definite.
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(0.5 * (jx + jx.transpose()));
      EXPECT_LE(eig.eigenvalues().maxCoeff(), 1e-9 * jx.cwiseAbs().maxCoeff());
    }
    EXPECT_LT((jx - jx.transpose()).cwiseAbs().maxCoeff(), 1e-9 * jx.cwiseAbs().maxCoeff());
  }
}

TEST(TensileForceTest, UniaxialForceEqualsCurveTimesWidth) {
  const FabricMaterial material = MaterialFromKes(testing::CompositeDenim());
  const FabricModel model = BuildFabricModel(material, {0.1, 0.04, 3, 3});
  FabricState s = MakeRestState(model);
  const double strain = 0.01;
  for (int p = 0; p < model.num_particles; ++p) s.x(p).x() *= 1.0 + strain;
  Eigen::VectorXd f = Eigen::VectorXd::Zero(3 * model.num_particles);
  ForceSink sink;
  sink.force_N = &f;
  AddTensileForces(model, s.x_W_m, s.v_W_m_per_s, &sink);
  double edge_force = 0.0;
  for (int j = 0; j < 3; ++j) edge_force += f[3 * model.mesh.Index(2, j)];
  EXPECT_NEAR(edge_force, -material.tensile_warp.Value(strain) * 0.04, 1e-9);
}

}  // namespace
}  // namespace haptex::textile
