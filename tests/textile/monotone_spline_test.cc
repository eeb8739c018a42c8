#include "libs/textile/monotone_spline.h"

#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>

namespace haptex::textile {
namespace {

TEST(MonotoneSplineTest, InterpolatesKnots) {
  const MonotoneSpline dut({0.0, 1.0, 2.0, 4.0}, {0.0, 0.5, 3.0, 3.5});
  EXPECT_DOUBLE_EQ(dut.Value(0.0), 0.0);
  EXPECT_DOUBLE_EQ(dut.Value(1.0), 0.5);
  EXPECT_DOUBLE_EQ(dut.Value(2.0), 3.0);
  EXPECT_DOUBLE_EQ(dut.Value(4.0), 3.5);
}

TEST(MonotoneSplineTest, StaysMonotoneOnSteepData) {
  // Data that makes an ordinary cubic spline overshoot.
  const MonotoneSpline dut({0.0, 1.0, 2.0, 3.0, 4.0}, {0.0, 0.0, 0.0, 10.0, 10.0});
  double prev = dut.Value(-1.0);
  for (double x = -1.0; x <= 5.0; x += 0.001) {
    const double y = dut.Value(x);
    EXPECT_GE(y, prev - 1e-12) << "x=" << x;
    EXPECT_GE(dut.Slope(x), -1e-12) << "x=" << x;
    EXPECT_LE(y, 10.0 + 1e-12);
    prev = y;
  }
}

TEST(MonotoneSplineTest, ReproducesALine) {
  const MonotoneSpline dut({0.0, 0.5, 2.0}, {1.0, 2.0, 5.0});
  for (double x = -1.0; x < 3.0; x += 0.1) {
    EXPECT_NEAR(dut.Value(x), 1.0 + 2.0 * x, 1e-12);
    EXPECT_NEAR(dut.Slope(x), 2.0, 1e-12);
  }
}

TEST(MonotoneSplineTest, SlopeMatchesFiniteDifference) {
  const MonotoneSpline dut({0.0, 0.01, 0.03, 0.06}, {0.0, 1.0, 10.0, 60.0});
  for (double x = 0.001; x < 0.07; x += 0.0037) {
    const double h = 1e-7;
    EXPECT_NEAR(dut.Slope(x), (dut.Value(x + h) - dut.Value(x - h)) / (2 * h), 1e-3 * (1 + dut.Slope(x)));
  }
}

TEST(MonotoneSplineTest, ExtrapolatesLinearly) {
  const MonotoneSpline dut({0.0, 1.0, 2.0}, {0.0, 1.0, 4.0});
  const double end_slope = dut.Slope(2.0);
  EXPECT_NEAR(dut.Value(3.0), 4.0 + end_slope, 1e-12);
  EXPECT_NEAR(dut.Slope(10.0), end_slope, 1e-12);
}

TEST(MonotoneSplineTest, RejectsBadKnots) {
  EXPECT_THROW(MonotoneSpline({0.0}, {0.0}), std::invalid_argument);
  EXPECT_THROW(MonotoneSpline({0.0, 0.0}, {0.0, 1.0}), std::invalid_argument);
  EXPECT_THROW(MonotoneSpline({0.0, 1.0}, {1.0, 0.0}), std::invalid_argument);
  EXPECT_THROW(MonotoneSpline({0.0, 1.0}, {0.0, std::nan("")}), std::invalid_argument);
}

}  // namespace
}  // namespace haptex::textile
