#include "libs/contact/coulomb_friction.h"

#include <gtest/gtest.h>

namespace haptex::contact {
namespace {

const FrictionCoefficients kMu{0.4, 0.2};

TEST(CoulombFrictionTest, SticksBelowStaticLimit) {
  // k = 100 N/m, F_N = 1 N: sticks up to 4 mm of spring.
  const StickSlipResult r = UpdateStickSlip({0, 0, 0}, {0.0039, 0, 0}, 100.0, 1.0, kMu, false);
  EXPECT_FALSE(r.sliding);
  EXPECT_EQ(r.held_W, Eigen::Vector3d(0, 0, 0));
  EXPECT_NEAR(r.tangential_N, 0.39, 1e-12);
}

TEST(CoulombFrictionTest, SlipsAboveStaticLimitToDynamicForce) {
  const StickSlipResult r = UpdateStickSlip({0, 0, 0}, {0.0041, 0, 0}, 100.0, 1.0, kMu, false);
  EXPECT_TRUE(r.sliding);
  EXPECT_NEAR(r.tangential_N, 0.2, 1e-12);
  EXPECT_NEAR((Eigen::Vector3d(0.0041, 0, 0) - r.held_W).norm() * 100.0, 0.2, 1e-12);
}

TEST(CoulombFrictionTest, KeepsSlidingAboveDynamicLimitAndSticksBelow) {
  StickSlipResult r = UpdateStickSlip({0, 0, 0}, {0.0025, 0, 0}, 100.0, 1.0, kMu, true);
  EXPECT_TRUE(r.sliding);
  r = UpdateStickSlip({0, 0, 0}, {0.0015, 0, 0}, 100.0, 1.0, kMu, true);
  EXPECT_FALSE(r.sliding);
}

TEST(CoulombFrictionTest, StoppedSlideSticksDespiteRounding) {
  StickSlipResult r = UpdateStickSlip({0, 0, 0}, {0.0123456789, 0, 0}, 100.0, 1.0, kMu, false);
  ASSERT_TRUE(r.sliding);
  r = UpdateStickSlip(r.held_W, {0.0123456789, 0, 0}, 100.0, 1.0, kMu, true);
  EXPECT_FALSE(r.sliding);
}

TEST(CoulombFrictionTest, NoNormalForceMeansNoFriction) {
  const StickSlipResult r = UpdateStickSlip({0, 0, 0}, {0.01, 0, 0}, 100.0, 0.0, kMu, false);
  EXPECT_EQ(r.held_W, Eigen::Vector3d(0.01, 0, 0));
  EXPECT_EQ(r.tangential_N, 0.0);
}

TEST(CoulombFrictionTest, ZeroMuAlwaysSlidesWithoutForce) {
  const StickSlipResult r = UpdateStickSlip({0, 0, 0}, {1e-6, 0, 0}, 100.0, 1.0, {0.0, 0.0}, false);
  EXPECT_TRUE(r.sliding);
  EXPECT_NEAR(r.tangential_N, 0.0, 1e-15);
}

}  // namespace
}  // namespace haptex::contact
