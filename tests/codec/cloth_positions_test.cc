// The cloth's positions in a ClothFrame: quantised, as differences; malformed chunks refused whole.
#include "libs/codec/cloth_positions.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

namespace haptex::codec {
namespace {

// A 41-particle row of a draped cloth, 5 mm apart, sagging: positions of the size a scene has.
std::vector<double> Row() {
  std::vector<double> x;
  for (int p = 0; p < 41; ++p) {
    x.insert(x.end(), {-0.1 + 0.005 * p, 0.0301 + 1e-7 * p * p, 0.35 - 0.0004 * std::sin(0.3 * p)});
  }
  return x;
}

TEST(ClothPositionsTest, EveryParticleWithinHalfAStepAndNoErrorAccumulates) {
  const std::vector<double> x = Row();
  v1::ClothFrame frame;
  EncodeClothPositions(x.data(), 41, kClothQuantumM, &frame);
  ASSERT_EQ(frame.position_q_size(), 3 * 41);
  std::vector<float> out(3 * 41);
  ASSERT_EQ(DecodeClothPositions(frame, out.data(), out.size()), 3 * 41);
  for (std::size_t i = 0; i < x.size(); ++i) {
    // half a step, and a float's rounding at 0.35 m (3e-8 m)
    EXPECT_NEAR(out[i], x[i], 0.5 * kClothQuantumM + 4e-8) << i;
  }
}

TEST(ClothPositionsTest, NeighboursTakeTwoBytesWhereAFloatTakesFour) {
  const std::vector<double> x = Row();
  v1::ClothFrame quantised;
  EncodeClothPositions(x.data(), 41, kClothQuantumM, &quantised);
  const std::size_t bytes = quantised.ByteSizeLong();
  EXPECT_LT(bytes, 2 * 3 * 41 + 3 * 3 + 16) << "2 bytes a coordinate; the first particle and the step more";
  EXPECT_LT(static_cast<double>(bytes), 0.6 * 4 * 3 * 41) << "against float positions";
}

TEST(ClothPositionsTest, ReusesTheFieldAndReplacesWhatWasThere) {
  const std::vector<double> x = Row();
  v1::ClothFrame frame;
  EncodeClothPositions(x.data(), 41, kClothQuantumM, &frame);
  EncodeClothPositions(x.data() + 3, 2, 1e-3, &frame);
  ASSERT_EQ(frame.position_q_size(), 6);
  EXPECT_EQ(frame.quantum_m(), 1e-3);
  float out[6];
  ASSERT_EQ(DecodeClothPositions(frame, out, 6), 6);
  EXPECT_NEAR(out[3], x[6], 0.5e-3);
}

TEST(ClothPositionsTest, NonFiniteAndFarPositionsStayInRange) {
  const double inf = std::numeric_limits<double>::infinity();
  const std::vector<double> x = {std::nan(""), 0.01, -inf, 0.02, 1e9, 0.03, -1e9, 0.04, 0.05};
  v1::ClothFrame frame;
  EncodeClothPositions(x.data(), 3, kClothQuantumM, &frame);
  float out[9];
  ASSERT_EQ(DecodeClothPositions(frame, out, 9), 9);
  EXPECT_EQ(out[0], 0.0f) << "the first particle's NaN: 0";
  EXPECT_NEAR(out[3], 0.02, 1e-6);
  EXPECT_NEAR(out[6], -kClothQuantisedLimit * kClothQuantumM, 1e-3) << "clamped";
  EXPECT_NEAR(out[4], kClothQuantisedLimit * kClothQuantumM, 1e-3) << "clamped";
  EXPECT_NEAR(out[2], 0.0, 1e-12) << "-inf sent as the particle before had it (none: 0)";
  EXPECT_NEAR(out[8], 0.05, 1e-6);
}

TEST(ClothPositionsTest, AMalformedChunkIsRefusedWholeAndWritesNothing) {
  const std::vector<double> x = Row();
  v1::ClothFrame good;
  EncodeClothPositions(x.data(), 41, kClothQuantumM, &good);
  std::vector<float> out(3 * 41, 7.0f);
  const auto untouched = [&] {
    for (float f : out) {
      if (f != 7.0f) return false;
    }
    return true;
  };

  v1::ClothFrame ragged = good;
  ragged.add_position_q(1);
  EXPECT_EQ(DecodeClothPositions(ragged, out.data(), out.size() + 3), -1) << "not 3 per particle";
  EXPECT_EQ(DecodeClothPositions(good, out.data(), out.size() - 1), -1) << "more than the capacity";
  for (const double quantum : {0.0, -1e-6, std::nan(""), std::numeric_limits<double>::infinity(), 1e300}) {
    v1::ClothFrame bad_step = good;
    bad_step.set_quantum_m(quantum);
    EXPECT_EQ(DecodeClothPositions(bad_step, out.data(), out.size()), -1) << quantum;
  }
  v1::ClothFrame runaway = good;
  for (int i = 3; i < runaway.position_q_size(); i += 3)
    runaway.set_position_q(i, std::numeric_limits<std::int32_t>::max());
  EXPECT_EQ(DecodeClothPositions(runaway, out.data(), out.size()), -1) << "sums beyond the limit";
  EXPECT_TRUE(untouched());
}

}  // namespace
}  // namespace haptex::codec
