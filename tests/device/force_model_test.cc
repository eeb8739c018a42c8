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

  EXPECT_TRUE(EvaluateForceModel(model, model.x0_W_m).isApprox(model.force0_W_N));
  const Eigen::Vector3d dx(0.001, -0.002, 0.0005);
  const Eigen::Vector3d expected = model.force0_W_N + model.stiffness_W_N_per_m * dx;
  EXPECT_TRUE(EvaluateForceModel(model, model.x0_W_m + dx).isApprox(expected, 1e-12));
}

TEST(ForceModelTest, WallLinearisationPushesOut) {
  // a wall of 1.25 N/mm with normal +z, linearised at a point 2 mm inside it
  const double k = 1250.0;
  const Eigen::Vector3d n = Eigen::Vector3d::UnitZ();
  ForceModel model;
  model.x0_W_m = {0.0, 0.0, -0.002};
  model.force0_W_N = k * 0.002 * n;
  model.stiffness_W_N_per_m = -k * n * n.transpose();
  EXPECT_NEAR(EvaluateForceModel(model, {0.0, 0.0, -0.001}).z(), 1.25, 1e-12);
  EXPECT_NEAR(EvaluateForceModel(model, {0.003, 0.0, -0.002}).x(), 0.0, 1e-12);
}

TEST(ForceModelTest, PropagatesNonFiniteForTheSafetyStage) {
  ForceModel model;
  model.force0_W_N.x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(EvaluateForceModel(model, Eigen::Vector3d::Zero()).allFinite());
}

}  // namespace
}  // namespace haptex::device
