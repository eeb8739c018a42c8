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
