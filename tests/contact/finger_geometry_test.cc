#include "libs/contact/finger_geometry.h"

#include <gtest/gtest.h>

namespace haptex::contact {
namespace {

TEST(FingerGeometryTest, CapsuleSegmentAlongDistalAxis) {
  FingerPose pose;
  pose.p_W_m = {1, 2, 3};
  pose.R_WF = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Segment s = CapsuleSegment({0.008, 0.012}, pose);
  EXPECT_TRUE(s.a_W.isApprox(Eigen::Vector3d(1, 2 - 0.006, 3)));
  EXPECT_TRUE(s.b_W.isApprox(Eigen::Vector3d(1, 2 + 0.006, 3)));
}

TEST(FingerGeometryTest, QueryCapsuleDepthNormalSurface) {
  const Segment s{{-0.006, 0, 0}, {0.006, 0, 0}};
  const SurfaceQuery q = QueryCapsule(s, 0.008, {0.003, 0, -0.005}, Eigen::Vector3d::UnitZ());
  EXPECT_NEAR(q.depth_m, 0.003, 1e-12);
  EXPECT_TRUE(q.normal_W.isApprox(Eigen::Vector3d(0, 0, -1)));
  EXPECT_TRUE(q.surface_W.isApprox(Eigen::Vector3d(0.003, 0, -0.008)));
  // Beyond the end cap the sphere part answers.
  const SurfaceQuery cap = QueryCapsule(s, 0.008, {0.016, 0, 0}, Eigen::Vector3d::UnitZ());
  EXPECT_NEAR(cap.depth_m, -0.002, 1e-12);
  // On the axis the fallback normal is used.
  const SurfaceQuery axis = QueryCapsule(s, 0.008, {0, 0, 0}, Eigen::Vector3d::UnitY());
  EXPECT_TRUE(axis.normal_W.isApprox(Eigen::Vector3d::UnitY()));
  EXPECT_NEAR(axis.depth_m, 0.008, 1e-12);
}

TEST(FingerGeometryTest, ClosestPointsBetweenSegments) {
  Eigen::Vector3d a, b;
  ClosestPointsBetweenSegments({{-1, 0, 0}, {1, 0, 0}}, {{0, -1, 1}, {0, 1, 1}}, &a, &b);
  EXPECT_TRUE(a.isApprox(Eigen::Vector3d(0, 0, 0)));
  EXPECT_TRUE(b.isApprox(Eigen::Vector3d(0, 0, 1)));
  // Parallel segments, and degenerate (point) segments.
  ClosestPointsBetweenSegments({{0, 0, 0}, {1, 0, 0}}, {{0.5, 1, 0}, {2, 1, 0}}, &a, &b);
  EXPECT_NEAR((a - b).norm(), 1.0, 1e-12);
  ClosestPointsBetweenSegments({{0, 0, 0}, {0, 0, 0}}, {{1, 1, 0}, {1, 1, 0}}, &a, &b);
  EXPECT_NEAR((a - b).norm(), std::sqrt(2.0), 1e-12);
}

TEST(FingerGeometryTest, PoseFacingIsARotationWithThePadOnTheNormal) {
  const FingerPose pose = PoseFacing({1, 2, 3}, {0, 0, -2}, {1, 0, 0.5});
  EXPECT_TRUE(pose.p_W_m.isApprox(Eigen::Vector3d(1, 2, 3)));
  EXPECT_TRUE((pose.R_WF.transpose() * pose.R_WF).isApprox(Eigen::Matrix3d::Identity(), 1e-12));
  EXPECT_NEAR(pose.R_WF.determinant(), 1.0, 1e-12);
  EXPECT_TRUE(pose.R_WF.col(2).isApprox(Eigen::Vector3d(0, 0, -1)));  // pad faces the normal
  EXPECT_TRUE(pose.R_WF.col(0).isApprox(Eigen::Vector3d(1, 0, 0)));   // distal, normal part removed
}

}  // namespace
}  // namespace haptex::contact
