// Anchor springs (finger contact on the fabric): force and Jacobian, and both integrators stay
// stable with contact-stiff springs on light particles.

#include "libs/textile/anchor_spring_force.h"

#include <gtest/gtest.h>

#include "libs/textile/fabric_stepper.h"
#include "tests/textile/fabric_textproto.h"
#include "tests/textile/textile_test_util.h"

namespace haptex::textile {
namespace {

FabricModel SmallModel() {
  return BuildFabricModel(MaterialFromKes(testing::LoadDatabaseFabric("wang2011_black_denim_11oz")),
                          {0.02, 0.02, 5, 5});
}

TEST(AnchorSpringForceTest, ForceAndJacobianMatchFiniteDifferences) {
  const FabricModel model = SmallModel();
  FabricState s = MakeRestState(model);
  s.anchor_stiffness_N_per_m[7] = 250.0;
  s.anchor_W_m.segment<3>(21) += Eigen::Vector3d(0.001, -0.002, 0.003);
  const testing::ForceFn fn = [&](const FabricModel& m, const Eigen::VectorXd& x, const Eigen::VectorXd&,
                                  ForceSink* sink) {
    FabricState t = s;
    t.x_W_m = x;
    AddAnchorSpringForces(m, t, sink);
  };
  Eigen::VectorXd f;
  Eigen::MatrixXd dfdx, dfdv;
  testing::DenseForceAndJacobians(model, fn, s.x_W_m, s.v_W_m_per_s, &f, &dfdx, &dfdv);
  EXPECT_TRUE(f.segment<3>(21).isApprox(250.0 * Eigen::Vector3d(0.001, -0.002, 0.003)));
  EXPECT_NEAR(f.norm(), f.segment<3>(21).norm(), 1e-15);
  const Eigen::MatrixXd fd = testing::FiniteDifferenceJacobian(model, fn, s.x_W_m, s.v_W_m_per_s, false, 1e-7);
  EXPECT_LT((dfdx - fd).cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_NEAR(MaxAnchorStiffnessPerMass(model, s), 250.0 / model.mass_kg[7], 1e-6);
}

class AnchorSpringStabilityTest : public ::testing::TestWithParam<Integrator> {};

TEST_P(AnchorSpringStabilityTest, StiffSpringHoldsParticleStably) {
  const FabricModel model = SmallModel();
  FabricState s = MakeRestState(model);
  for (int p : model.mesh.BorderParticles()) s.Fix(p);
  const int p = model.mesh.Index(2, 2);
  // 2000 N/m on a particle of about 10^-5 kg: omega h = 14 at 1 ms, far beyond explicit limits.
  s.anchor_stiffness_N_per_m[p] = 2000.0;
  s.anchor_W_m.segment<3>(3 * p) = s.x(p) + Eigen::Vector3d(0, 0, 0.002);
  StepOptions opt;
  opt.method = GetParam();
  opt.dt_s = 0.001;
  opt.cg_tolerance = 1e-8;
  opt.max_substeps = 100000;
  FabricStepper stepper(model, opt);
  for (int k = 0; k < 300; ++k) {
    ASSERT_NE(stepper.Step(&s).status, StepStatus::kNanRecovered);
  }
  EXPECT_TRUE(s.x_W_m.allFinite());
  // Pulled up towards the anchor, held back by the fabric: between rest and the anchor.
  EXPECT_GT(s.x(p).z(), 0.0);
  EXPECT_LT(s.x(p).z(), 0.002);
  EXPECT_LT(MaxSpeed(s), 0.05);  // bounded, no blow-up
}

INSTANTIATE_TEST_SUITE_P(Integrators, AnchorSpringStabilityTest,
                         ::testing::Values(Integrator::kImplicitEuler, Integrator::kSymplecticEuler));

}  // namespace
}  // namespace haptex::textile
