#include "services/device_bridge/device_bridge_codec.h"

#include <gtest/gtest.h>

#include <cmath>

namespace haptex::device_bridge {
namespace {

TEST(DeviceBridgeCodecTest, FingersMapBothWaysAndUnknownIsRefused) {
  device::Manipulator m{};
  ASSERT_TRUE(ToManipulator(v1::FINGER_THUMB, &m));
  EXPECT_EQ(m, device::Manipulator::kThumb);
  ASSERT_TRUE(ToManipulator(v1::FINGER_INDEX, &m));
  EXPECT_EQ(m, device::Manipulator::kIndex);
  EXPECT_FALSE(ToManipulator(v1::FINGER_UNSPECIFIED, &m));
  EXPECT_EQ(ToFinger(device::Manipulator::kIndex), v1::FINGER_INDEX);
}

TEST(DeviceBridgeCodecTest, ForceModelKeepsEveryValueRowMajor) {
  v1::FingerForceModel in;
  in.mutable_f0_w_n()->set_z(1.5);
  in.mutable_x0_w_m()->set_y(0.01);
  for (int i = 0; i < 9; ++i) in.add_stiffness_w_n_per_m(i);
  in.set_ttl_s(0.004);
  in.mutable_friction_cone_axis_w()->set_y(-1.0);
  in.set_friction_cone_mu(0.4);
  const device::ForceModel out = ToForceModel(in);
  EXPECT_EQ(out.friction_cone_axis_W, Eigen::Vector3d(0.0, -1.0, 0.0));
  EXPECT_EQ(out.friction_cone_mu, 0.4);
  EXPECT_EQ(out.force0_W_N.z(), 1.5);
  EXPECT_EQ(out.x0_W_m.y(), 0.01);
  EXPECT_EQ(out.stiffness_W_N_per_m(1, 2), 5.0);
  EXPECT_EQ(out.ttl_s, 0.004);
  // NaN passes through: the safety stage, not the parser, zeroes it
  in.mutable_f0_w_n()->set_x(std::nan(""));
  EXPECT_TRUE(std::isnan(ToForceModel(in).force0_W_N.x()));
  EXPECT_TRUE(IsWellFormed(in));
  in.clear_stiffness_w_n_per_m();
  EXPECT_TRUE(IsWellFormed(in));  // no stiffness: a constant force
  in.add_stiffness_w_n_per_m(1.0);
  EXPECT_FALSE(IsWellFormed(in));  // 1 value: malformed, refused by the bridge
}

}  // namespace
}  // namespace haptex::device_bridge
