#include "libs/tactile/fft.h"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

namespace haptex::tactile {
namespace {

TEST(FftTest, NextPowerOfTwo) {
  EXPECT_EQ(NextPowerOfTwo(1), 1u);
  EXPECT_EQ(NextPowerOfTwo(5), 8u);
  EXPECT_EQ(NextPowerOfTwo(64), 64u);
}

TEST(FftTest, SinusoidLandsInItsBin) {
  for (const std::size_t n : {std::size_t{16}, std::size_t{12}}) {  // radix-2 and direct paths
    std::vector<std::complex<double>> x(n);
    for (std::size_t i = 0; i < n; ++i)
      x[i] = std::cos(2.0 * std::numbers::pi * 3.0 * static_cast<double>(i) / static_cast<double>(n));
    Dft1d(x.data(), n, 1, false);
    for (std::size_t k = 0; k < n; ++k) {
      const double expected = (k == 3 || k == n - 3) ? static_cast<double>(n) / 2.0 : 0.0;
      EXPECT_NEAR(std::abs(x[k]), expected, 1e-9) << "n=" << n << " k=" << k;
    }
  }
}

TEST(FftTest, TwoDimensionalRoundTrip) {
  ComplexGrid g(8, 6);
  for (Eigen::Index i = 0; i < g.size(); ++i)
    g(i) = std::complex<double>(std::sin(0.3 * static_cast<double>(i)), 0.1 * static_cast<double>(i));
  const ComplexGrid original = g;
  Dft2d(&g, false);
  Dft2d(&g, true);
  EXPECT_LT((g - original).abs().maxCoeff(), 1e-12);
}

}  // namespace
}  // namespace haptex::tactile
