#include "libs/tactile/height_map.h"

#include <limits>
#include <stdexcept>

#include <gtest/gtest.h>

namespace haptex::tactile {
namespace {

TEST(HeightMapTest, RejectsBadInput) {
  EXPECT_THROW(HeightMap(Eigen::ArrayXXd::Zero(1, 5), 1e-5), std::invalid_argument);
  EXPECT_THROW(HeightMap(Eigen::ArrayXXd::Zero(4, 4), 0.0), std::invalid_argument);
  Eigen::ArrayXXd h = Eigen::ArrayXXd::Zero(4, 4);
  h(1, 2) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(HeightMap(h, 1e-5), std::invalid_argument);
}

TEST(HeightMapTest, StatisticsOfASquareWave) {
  Eigen::ArrayXXd h(4, 2);
  h << 1, 1, -1, -1, 1, 1, -1, -1;  // +-1 around 0: MAD = RMS = 1
  HeightMap dut(h + 10.0, 1e-5);
  EXPECT_DOUBLE_EQ(dut.MeanUm(), 10.0);
  EXPECT_DOUBLE_EQ(dut.MeanAbsoluteDeviationUm(), 1.0);
  EXPECT_DOUBLE_EQ(dut.RmsDeviationUm(), 1.0);
  dut.ScaleDeviation(3.0);
  EXPECT_DOUBLE_EQ(dut.MeanAbsoluteDeviationUm(), 3.0);
  EXPECT_DOUBLE_EQ(dut.MeanUm(), 10.0);
}

TEST(HeightMapTest, BilinearSamplingAndClampedBorder) {
  Eigen::ArrayXXd h(2, 2);
  h << 0, 2, 4, 6;  // h(0,0)=0 h(0,1)=2 h(1,0)=4 h(1,1)=6
  const HeightMap dut(h, 1e-3);
  EXPECT_DOUBLE_EQ(dut.SampleUm(0.5e-3, 0.5e-3), 3.0);
  EXPECT_DOUBLE_EQ(dut.SampleUm(1e-3, 0.0), 4.0);
  EXPECT_DOUBLE_EQ(dut.SampleUm(5e-3, -5e-3), 4.0);
  EXPECT_DOUBLE_EQ(dut.extent_x_m(), 1e-3);
}

}  // namespace
}  // namespace haptex::tactile
