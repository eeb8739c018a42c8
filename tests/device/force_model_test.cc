#include "libs/device/force_model.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace haptex::device {
namespace {

TEST(ForceModelTest, AffineInPosition) {
  ForceModel model;
  model.force0_W_N = {1.0, -2.0, 0.5};
  model.stiffness_W_N_per_m << -1000.0, 0.0, 0.0, 0.0, -500.0, 10.0, 0.0, 0.0, -1250.0;
  model.x0_W_m = {0.01, 0.02, -0.03};

  EXPECT_TRUE(EvaluateForceModel(model, model.x0_W_m, model.other_x0_W_m).isApprox(model.force0_W_N));
  const Eigen::Vector3d dx(0.001, -0.002, 0.0005);
  const Eigen::Vector3d expected = model.force0_W_N + model.stiffness_W_N_per_m * dx;
  EXPECT_TRUE(EvaluateForceModel(model, model.x0_W_m + dx, model.other_x0_W_m).isApprox(expected, 1e-12));
}

TEST(ForceModelTest, WallLinearisationPushesOut) {
  // a wall of 1.25 N/mm with normal +z, linearised at a point 2 mm inside it
  const double k = 1250.0;
  const Eigen::Vector3d n = Eigen::Vector3d::UnitZ();
  ForceModel model;
  model.x0_W_m = {0.0, 0.0, -0.002};
  model.force0_W_N = k * 0.002 * n;
  model.stiffness_W_N_per_m = -k * n * n.transpose();
  EXPECT_NEAR(EvaluateForceModel(model, {0.0, 0.0, -0.001}, model.other_x0_W_m).z(), 1.25, 1e-12);
  EXPECT_NEAR(EvaluateForceModel(model, {0.003, 0.0, -0.002}, model.other_x0_W_m).x(), 0.0, 1e-12);
}

TEST(ForceModelTest, PropagatesNonFiniteForTheSafetyStage) {
  ForceModel model;
  model.force0_W_N.x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(EvaluateForceModel(model, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()).allFinite());
}

TEST(ForceModelTest, FrictionConeHoldsTheExtrapolationAcrossTheNormal) {
  // a finger stuck on cloth (normal +y on the finger, mu 0.4), F0 at the cone's edge; the stuck
  // contact's tangential stiffness extrapolated 2 mm along x would hold it with 3 N
  ForceModel model;
  model.force0_W_N = {0.6, 1.5, 0.0};
  model.stiffness_W_N_per_m = -1500.0 * Eigen::Matrix3d::Identity();
  model.friction_cone_axis_W = Eigen::Vector3d::UnitY();
  model.friction_cone_mu = 0.4;
  EXPECT_TRUE(EvaluateForceModel(model, model.x0_W_m, model.other_x0_W_m).isApprox(model.force0_W_N, 1e-12))
      << "F0 itself is inside the cone";
  const Eigen::Vector3d slid = EvaluateForceModel(model, {-0.002, 0.0, 0.0}, model.other_x0_W_m);
  EXPECT_NEAR(slid.y(), 1.5, 1e-12) << "the normal part stays";
  EXPECT_NEAR(std::hypot(slid.x(), slid.z()), 0.4 * 1.5, 1e-12) << "the tangential part at mu times it";
  EXPECT_GT(slid.x(), 0.0);
  // pressed deeper as it slides: the cone grows with the normal force
  const Eigen::Vector3d deeper = EvaluateForceModel(model, {-0.0008, -0.0002, 0.0}, model.other_x0_W_m);
  EXPECT_NEAR(deeper.y(), 1.5 + 0.3, 1e-12);
  EXPECT_NEAR(deeper.x(), 0.4 * 1.8, 1e-12);
  // without a cone the same model holds it far harder
  model.friction_cone_mu = 0.0;
  EXPECT_GT(EvaluateForceModel(model, {-0.002, 0.0, 0.0}, model.other_x0_W_m).x(), 2.0);
}

TEST(ForceModelTest, ABadFrictionConeNeverAddsForce) {
  ForceModel model;
  model.force0_W_N = {0.6, 1.5, 0.0};
  model.stiffness_W_N_per_m = -1500.0 * Eigen::Matrix3d::Identity();
  const Eigen::Vector3d p(-0.002, 0.001, 0.0005);
  const Eigen::Vector3d without = EvaluateForceModel(model, p, model.other_x0_W_m);
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3d& axis : {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0, 1e6, 0), Eigen::Vector3d(nan, 1, 0),
                                      Eigen::Vector3d(0, -1, 0), Eigen::Vector3d(1, 0, 0)}) {
    for (double mu : {0.0, -1.0, 0.4, inf, nan}) {
      model.friction_cone_axis_W = axis;
      model.friction_cone_mu = mu;
      const Eigen::Vector3d f = EvaluateForceModel(model, p, model.other_x0_W_m);
      ASSERT_TRUE(f.allFinite()) << axis.transpose() << " mu " << mu;
      EXPECT_LE(f.norm(), without.norm() + 1e-12) << axis.transpose() << " mu " << mu;
    }
  }
  // an axis the force points away from (the finger pulled off): no tangential force at all
  model.friction_cone_axis_W = {0.0, -1.0, 0.0};
  model.friction_cone_mu = 0.4;
  const Eigen::Vector3d f = EvaluateForceModel(model, p, model.other_x0_W_m);
  EXPECT_NEAR(std::hypot(f.x(), f.z()), 0.0, 1e-12);
}

}  // namespace
TEST(ForceModelTest, CrossTermFollowsTheOtherFinger) {
  // a pinch: the thumb's force grows as the index finger presses the cloth towards it
  ForceModel model;
  model.force0_W_N = {0.0, 0.0, 2.0};
  model.cross_stiffness_W_N_per_m = -500.0 * Eigen::Matrix3d::Identity();
  model.other_x0_W_m = {0.0, 0.0, 0.01};
  const Eigen::Vector3d at_rest = EvaluateForceModel(model, Eigen::Vector3d::Zero(), model.other_x0_W_m);
  const Eigen::Vector3d pressed = EvaluateForceModel(model, Eigen::Vector3d::Zero(), {0.0, 0.0, 0.009});
  EXPECT_NEAR(at_rest.z(), 2.0, 1e-12);
  EXPECT_NEAR(pressed.z(), 2.5, 1e-12);
}

TEST(ForceModelTest, ExtrapolationIsCappedAtTheModelForcePlusAnAllowance) {
  // a finger far from where the model was taken: the linearisation would ask for 20 N
  ForceModel model;
  model.force0_W_N = {0.0, 0.0, 1.0};
  model.stiffness_W_N_per_m = -1000.0 * Eigen::Matrix3d::Identity();
  const Eigen::Vector3d deep = EvaluateForceModel(model, {0.0, 0.0, -0.02}, Eigen::Vector3d::Zero());
  EXPECT_NEAR(deep.z(), 2.0 + kExtrapolationAllowance_N, 1e-12);
  // the cap holds for any direction of the extrapolation
  const Eigen::Vector3d sideways = EvaluateForceModel(model, {-0.02, 0.0, 0.0}, Eigen::Vector3d::Zero());
  EXPECT_NEAR((sideways - model.force0_W_N).norm(), 1.0 + kExtrapolationAllowance_N, 1e-12);
  // no contact force at the model's pose: at most the allowance
  model.force0_W_N.setZero();
  EXPECT_NEAR(EvaluateForceModel(model, {0.0, 0.0, -0.02}, Eigen::Vector3d::Zero()).norm(), kExtrapolationAllowance_N,
              1e-12);
}

TEST(ForceModelTest, NeverPullsAgainstItsOwnForce) {
  // the finger has left the cloth since the model was taken: the extrapolation would pull it back
  ForceModel model;
  model.force0_W_N = {0.0, 0.0, 1.0};
  model.stiffness_W_N_per_m = -1000.0 * Eigen::Matrix3d::Identity();
  model.stiffness_W_N_per_m(0, 2) = -300.0;  // and push sideways
  const Eigen::Vector3d lifted = EvaluateForceModel(model, {0.0, 0.0, 0.005}, Eigen::Vector3d::Zero());
  EXPECT_GE(lifted.dot(model.force0_W_N), -1e-12);
  EXPECT_NEAR(lifted.z(), 0.0, 1e-12);
  EXPECT_LT(lifted.x(), 0.0) << "the part across F0 stays";
}

}  // namespace haptex::device
