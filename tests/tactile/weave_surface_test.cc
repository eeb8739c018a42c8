#include "libs/tactile/weave_surface.h"

#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>

namespace haptex::tactile {
namespace {

TEST(WeaveSurfaceTest, ScaledToTheRequestedSmd) {
  for (const double smd : {2.0, 5.0, 12.0}) {
    WeaveParams p;
    p.smd_um = smd;
    p.size_x = p.size_y = 64;
    EXPECT_NEAR(GenerateWeave(p).MeanAbsoluteDeviationUm(), smd, 1e-9);
  }
}

TEST(WeaveSurfaceTest, InvariantUnderItsLatticeTranslations) {
  // Pitches of whole pixels, so lattice shifts are whole pixels too.
  for (const WeavePattern pattern : {WeavePattern::kPlain, WeavePattern::kTwill, WeavePattern::kSatin}) {
    WeaveParams p;
    p.pattern = pattern;
    p.warp_pitch_m = 0.4e-3;
    p.weft_pitch_m = 0.3e-3;
    p.size_x = p.size_y = 200;
    const HeightMap map = GenerateWeave(p);
    const Eigen::Matrix2d basis = WeaveLatticeBasis(p);
    for (int c = 0; c < 2; ++c) {
      const int sx = static_cast<int>(std::lround(basis(0, c) / p.pixel_size_m));
      const int sy = static_cast<int>(std::lround(basis(1, c) / p.pixel_size_m));
      double worst = 0.0;
      for (int y = 40; y < 120; ++y) {
        for (int x = 40; x < 120; ++x) {
          worst = std::max(worst, std::abs(map.height_um()(x, y) - map.height_um()(x + sx, y + sy)));
        }
      }
      EXPECT_LT(worst, 1e-6) << "pattern " << static_cast<int>(pattern) << " vector " << c;
    }
  }
}

TEST(WeaveSurfaceTest, PatternsInterlaceAsSpecified) {
  WeaveParams p;
  EXPECT_TRUE(WarpOver(p, 0, 0));
  EXPECT_FALSE(WarpOver(p, 1, 0));
  p.pattern = WeavePattern::kTwill;  // 2/1: two overs then one under, shifted each pick
  EXPECT_TRUE(WarpOver(p, 0, 0));
  EXPECT_TRUE(WarpOver(p, 1, 0));
  EXPECT_FALSE(WarpOver(p, 2, 0));
  EXPECT_TRUE(WarpOver(p, 2, 1));
  p.pattern = WeavePattern::kSatin;  // one weft float per 5 warps
  int unders = 0;
  for (int i = 0; i < 5; ++i) unders += WarpOver(p, i, 3) ? 0 : 1;
  EXPECT_EQ(unders, 1);
}

TEST(WeaveSurfaceTest, HairinessAddsSeededNoise) {
  WeaveParams p;
  p.size_x = p.size_y = 64;
  p.hairiness_fraction = 0.3;
  const HeightMap a = GenerateWeave(p);
  const HeightMap b = GenerateWeave(p);
  p.seed = 2;
  const HeightMap c = GenerateWeave(p);
  EXPECT_EQ((a.height_um() - b.height_um()).abs().maxCoeff(), 0.0);
  EXPECT_GT((a.height_um() - c.height_um()).abs().maxCoeff(), 0.1);
}

TEST(WeaveSurfaceTest, BadParametersThrow) {
  WeaveParams p;
  p.warp_pitch_m = 0.0;
  EXPECT_THROW(GenerateWeave(p), std::invalid_argument);
  p = WeaveParams{};
  p.pattern = WeavePattern::kSatin;
  p.satin_step = 5;
  EXPECT_THROW(GenerateWeave(p), std::invalid_argument);
  p = WeaveParams{};
  p.smd_um = -1.0;
  EXPECT_THROW(GenerateWeave(p), std::invalid_argument);
}

}  // namespace
}  // namespace haptex::tactile
