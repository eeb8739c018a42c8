#include "libs/tactile/pin_layout.h"

#include <numbers>

#include <gtest/gtest.h>

namespace haptex::tactile {
namespace {

TEST(PinLayoutTest, SixByFourAtTwoMillimetres) {
  const PinLayout dut;
  EXPECT_EQ(PinLayout::kPinCount, 24);
  const Eigen::Vector2d first = dut.OffsetOnFingerM(PinLayout::Index(0, 0));
  const Eigen::Vector2d last = dut.OffsetOnFingerM(PinLayout::Index(5, 3));
  EXPECT_NEAR((last - first).x(), 10e-3, 1e-12);
  EXPECT_NEAR((last - first).y(), 6e-3, 1e-12);
  EXPECT_NEAR((first + last).norm(), 0.0, 1e-12);  // centred on the touch point
  EXPECT_NEAR((dut.OffsetOnFingerM(PinLayout::Index(1, 0)) - first).norm(), 2e-3, 1e-12);
}

TEST(PinLayoutTest, RotatingTheFingerRotatesTheOffsets) {
  const PinLayout dut;
  const int k = PinLayout::Index(5, 3);
  const Eigen::Vector2d f = dut.OffsetOnFingerM(k);
  const Eigen::Vector2d r = dut.OffsetOnFabricM(k, std::numbers::pi / 2.0);
  EXPECT_NEAR(r.x(), -f.y(), 1e-12);
  EXPECT_NEAR(r.y(), f.x(), 1e-12);
  EXPECT_NEAR(r.norm(), f.norm(), 1e-12);
}

TEST(PinLayoutDeathTest, OutOfRangeIndexIsABug) {
  const PinLayout dut;
  EXPECT_DEATH(dut.OffsetOnFingerM(PinLayout::kPinCount), "");
}

}  // namespace
}  // namespace haptex::tactile
