#include "libs/contact/coulomb_friction.h"

#include <algorithm>

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

// The finger-level cone: a pad pressed along -z (normal resultant +z, 1 N) with friction springs.
TEST(CoulombFingerConeTest, SplitsTheFingerForceAlongTheNormalResultant) {
  const FingerConeLoad load = FingerCone({0, 0, 1.0}, {0.3, 0.0, 0.1});
  EXPECT_NEAR(load.normal_N, 0.9, 1e-12);
  EXPECT_NEAR(load.tangential_N, 0.3, 1e-12);
}

// Anchors with their own F^T/F^N ratios: a lightly loaded rim (ratio 1.0) pre-loaded against the
// rub and a centre (ratio 0.3) with the rub. The shared coefficient puts the finger on the cone.
TEST(CoulombSharedSlipTest, PutsTheFingerOnTheCone) {
  const Eigen::Vector3d normal_resultant(0, 0, 1.0);
  Eigen::Matrix3Xd springs(3, 3);
  springs.col(0) << 0.05, 0.0, 0.0;   // rim, F^N 0.05 N
  springs.col(1) << -0.05, 0.0, 0.0;  // opposite rim, F^N 0.05 N
  springs.col(2) << 0.0, 0.27, 0.0;   // centre, F^N 0.9 N
  Eigen::VectorXd ratio(3);
  ratio << 1.0, 1.0, 0.3;
  for (double mu : {0.1, 0.2, 0.25}) {
    const double shared = SharedSlipCoefficient(normal_resultant, springs, ratio, mu);
    Eigen::Vector3d friction = Eigen::Vector3d::Zero();
    for (int i = 0; i < 3; ++i) friction += std::min(1.0, shared / ratio[i]) * springs.col(i);
    const FingerConeLoad load = FingerCone(normal_resultant, friction);
    EXPECT_NEAR(load.tangential_N, mu * load.normal_N, 1e-9) << "mu " << mu;
    EXPECT_LE(load.tangential_N, mu * load.normal_N) << "errs to the inside, mu " << mu;
  }
}

TEST(CoulombSharedSlipTest, InsideTheConeNothingMovesAndZeroMuReleases) {
  const Eigen::Vector3d normal_resultant(0, 0, 1.0);
  Eigen::Matrix3Xd springs(3, 1);
  springs.col(0) << 0.1, 0.0, 0.0;
  Eigen::VectorXd ratio(1);
  ratio << 0.1;
  EXPECT_EQ(SharedSlipCoefficient(normal_resultant, springs, ratio, 0.4), 0.1);
  EXPECT_EQ(SharedSlipCoefficient(normal_resultant, springs, ratio, 0.0), 0.0);
}

// Equal anchors: the finger-level law is the per-contact law.
TEST(CoulombSharedSlipTest, UniformAnchorsSlideLikeOneContact) {
  const Eigen::Vector3d normal_resultant(0, 0, 2.0);
  Eigen::Matrix3Xd springs(3, 2);
  springs.col(0) << 0.5, 0.0, 0.0;
  springs.col(1) << 0.5, 0.0, 0.0;
  Eigen::VectorXd ratio(2);
  ratio << 0.5, 0.5;
  EXPECT_NEAR(SharedSlipCoefficient(normal_resultant, springs, ratio, 0.2), 0.2, 1e-9);
}

}  // namespace
}  // namespace haptex::contact
