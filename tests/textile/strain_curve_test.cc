#include "libs/textile/strain_curve.h"

#include <gtest/gtest.h>

namespace haptex::textile {
namespace {

TEST(StrainCurveTest, TensileHasSoftCompressionBranch) {
  const auto dut = StrainCurve::Tensile(MonotoneSpline({0.0, 0.1}, {0.0, 100.0}), 20.0);
  double f = 0, k = 0;
  dut.Evaluate(-0.01, &f, &k);
  EXPECT_DOUBLE_EQ(f, -0.2);
  EXPECT_DOUBLE_EQ(k, 20.0);
  dut.Evaluate(0.05, &f, &k);
  EXPECT_NEAR(f, 50.0, 1e-12);
  EXPECT_NEAR(k, 1000.0, 1e-9);
}

TEST(StrainCurveTest, OddCurveIsAntisymmetric) {
  const auto dut = StrainCurve::Odd(MonotoneSpline({0.0, 0.1, 0.2}, {0.0, 1.0, 4.0}));
  for (double x = 0.0; x < 0.3; x += 0.01) {
    EXPECT_DOUBLE_EQ(dut.Value(-x), -dut.Value(x));
  }
}

TEST(StrainCurveTest, RejectsNegativeCompression) {
  EXPECT_THROW(StrainCurve::Tensile(MonotoneSpline({0.0, 1.0}, {0.0, 1.0}), -1.0), std::invalid_argument);
}

}  // namespace
}  // namespace haptex::textile
