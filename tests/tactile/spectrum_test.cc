#include "libs/tactile/spectrum.h"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

namespace haptex::tactile {
namespace {

TEST(SpectrumTest, EnergyEqualsVarianceAndPeakAtTheGratingFrequency) {
  // 8 periods of 16 pixels along x, 4 along y, on a 128 x 64 map.
  Eigen::ArrayXXd h(128, 64);
  for (int x = 0; x < 128; ++x) {
    for (int y = 0; y < 64; ++y) {
      h(x, y) = 3.0 * std::sin(2.0 * std::numbers::pi * x / 16.0) + 1.0 * std::sin(2.0 * std::numbers::pi * y / 16.0);
    }
  }
  const HeightMap map(h, 10e-6);
  const PowerSpectrum dut = ComputePowerSpectrum(map);
  EXPECT_NEAR(dut.power_um2.sum() / std::pow(map.RmsDeviationUm(), 2), 1.0, 0.05);
  const auto peaks = DominantFrequencies(dut, 2);
  ASSERT_EQ(peaks.size(), 2u);
  const double f = 1.0 / (16 * 10e-6);
  EXPECT_NEAR(peaks[0].x(), f, 1e-6);
  EXPECT_NEAR(peaks[0].y(), 0.0, 1e-6);
  EXPECT_NEAR(peaks[1].x(), 0.0, 1e-6);
  EXPECT_NEAR(peaks[1].y(), f, 1e-6);
}

TEST(SpectrumTest, ImageIsCentred) {
  Eigen::ArrayXXd h = Eigen::ArrayXXd::Zero(8, 8);
  h(3, 3) = 1.0;
  const PowerSpectrum s = ComputePowerSpectrum(HeightMap(h, 1e-5));
  const Eigen::ArrayXXd image = SpectrumImage(s);
  EXPECT_EQ(image.rows(), 8);
  EXPECT_DOUBLE_EQ(image(4, 4), std::log10(std::max(s.power_um2(0, 0), s.power_um2.maxCoeff() * 1e-9)));
}

}  // namespace
}  // namespace haptex::tactile
