#include "libs/netsim/random_stream.h"

#include <gtest/gtest.h>

#include <cmath>

namespace haptex::netsim {
namespace {

TEST(RandomStreamTest, SameSeedAndStreamRepeat) {
  RandomStream a(42, 3), b(42, 3);
  for (int i = 0; i < 1000; ++i) ASSERT_EQ(a.Uniform01(), b.Uniform01());
  for (int i = 0; i < 1000; ++i) ASSERT_EQ(a.StandardNormal(), b.StandardNormal());
}

TEST(RandomStreamTest, StreamsOfOneSeedAndSeedsDiffer) {
  RandomStream a(42, 1), b(42, 2), c(43, 1);
  int same_ab = 0, same_ac = 0;
  for (int i = 0; i < 1000; ++i) {
    const double x = a.Uniform01();
    same_ab += x == b.Uniform01();
    same_ac += x == c.Uniform01();
  }
  EXPECT_EQ(same_ab, 0);
  EXPECT_EQ(same_ac, 0);
}

TEST(RandomStreamTest, UniformAndNormalMomentsWithinSamplingBounds) {
  constexpr int kN = 200000;
  RandomStream dut(7, 1);
  double sum = 0, sum_sq = 0;
  for (int i = 0; i < kN; ++i) {
    const double u = dut.Uniform01();
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    sum += u;
    sum_sq += u * u;
  }
  // mean 1/2 with sd 1/sqrt(12 N); variance 1/12
  EXPECT_NEAR(sum / kN, 0.5, 5.0 / std::sqrt(12.0 * kN));
  EXPECT_NEAR(sum_sq / kN - (sum / kN) * (sum / kN), 1.0 / 12.0, 0.002);

  sum = sum_sq = 0;
  for (int i = 0; i < kN; ++i) {
    const double z = dut.StandardNormal();
    sum += z;
    sum_sq += z * z;
  }
  EXPECT_NEAR(sum / kN, 0.0, 5.0 / std::sqrt(kN));
  // sd of the sample variance of a normal: sqrt(2 / N)
  EXPECT_NEAR(sum_sq / kN, 1.0, 5.0 * std::sqrt(2.0 / kN));
}

}  // namespace
}  // namespace haptex::netsim
