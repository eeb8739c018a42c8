#include "libs/tactile/periodicity.h"

#include <cmath>
#include <ostream>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "libs/tactile/grey_image.h"
#include "libs/tactile/spectrum.h"
#include "libs/tactile/weave_surface.h"

namespace haptex::tactile {
namespace {

WeaveParams Weave(WeavePattern pattern, double hairiness) {
  WeaveParams p;
  p.pattern = pattern;
  p.warp_pitch_m = 0.35e-3;
  p.weft_pitch_m = 0.3e-3;
  p.yarn_diameter_m = 0.22e-3;
  p.hairiness_fraction = hairiness;
  return p;
}

struct LatticeCase {
  WeavePattern pattern;
  double hairiness;
};

void PrintTo(const LatticeCase& c, std::ostream* os) {
  *os << "pattern " << static_cast<int>(c.pattern) << " hairiness " << c.hairiness;
}

class LatticeRecoveryTest : public ::testing::TestWithParam<LatticeCase> {};

TEST_P(LatticeRecoveryTest, RecoversTheWeaveLatticeWithinOnePercentOfThePitch) {
  const WeaveParams p = Weave(GetParam().pattern, GetParam().hairiness);
  const HeightMap map = GenerateWeave(p);
  const LatticeEstimate dut = EstimateLattice(map);
  const double mismatch_m = LatticeMismatch(WeaveLatticeBasis(p), dut.basis_m);
  EXPECT_LT(mismatch_m, 0.01 * p.weft_pitch_m) << "basis [mm]:\n" << dut.basis_m * 1e3;
  EXPECT_GT(dut.periodicity_index, GetParam().hairiness > 0.0 ? 0.9 : 0.98);
  EXPECT_GT(dut.peaks_used, 4);
}

std::string CaseName(const ::testing::TestParamInfo<LatticeCase>& param_info) {
  static const char* const kPatternNames[] = {"Plain", "Twill", "Satin"};
  return std::string(kPatternNames[static_cast<int>(param_info.param.pattern)]) +
         (param_info.param.hairiness > 0.0 ? "Hairy" : "Clean");
}

INSTANTIATE_TEST_SUITE_P(
    Weaves, LatticeRecoveryTest,
    ::testing::Values(LatticeCase{WeavePattern::kPlain, 0.0}, LatticeCase{WeavePattern::kPlain, 0.3},
                      LatticeCase{WeavePattern::kTwill, 0.0}, LatticeCase{WeavePattern::kTwill, 0.3},
                      LatticeCase{WeavePattern::kSatin, 0.0}, LatticeCase{WeavePattern::kSatin, 0.3}),
    CaseName);

TEST(PeriodicityTest, TileReproducesTheSpectrumOfTheMap) {
  const WeaveParams p = Weave(WeavePattern::kTwill, 0.3);
  const HeightMap map = GenerateWeave(p);
  PeriodicityOptions options;
  options.noise_size = 64;
  const PeriodicTile tile = AnalysePeriodicity(map, options);
  const HeightMap rendered(tile.Render(map.size_x(), map.size_y(), map.pixel_size_m()), map.pixel_size_m());

  const PowerSpectrum original = ComputePowerSpectrum(map);
  const PowerSpectrum copy = ComputePowerSpectrum(rendered);
  // Same dominant spatial frequencies (within one bin) ...
  const auto f_original = DominantFrequencies(original, 4);
  const auto f_copy = DominantFrequencies(copy, 4);
  ASSERT_EQ(f_original.size(), 4u);
  ASSERT_EQ(f_copy.size(), 4u);
  for (const Eigen::Vector2d& f : f_original) {
    double nearest = 1e30;
    for (const Eigen::Vector2d& g : f_copy) nearest = std::min(nearest, (f - g).norm());
    EXPECT_LE(nearest, 1.01 * original.df_x_per_m) << "frequency " << f.transpose() << " /m not reproduced";
  }
  // ... and the same energy: total within 10 %, the periodic part alone within 10 % of its share.
  const double e_original = original.power_um2.sum();
  EXPECT_NEAR(copy.power_um2.sum() / e_original, 1.0, 0.1);
  EXPECT_NEAR(tile.periodicity_index(), 1.0 - std::pow(tile.residual_rms_um() / map.RmsDeviationUm(), 2), 0.02);
  EXPECT_GT(tile.periodicity_index(), 0.9);
}

TEST(PeriodicityTest, SeamlessTileOfACleanWeave) {
  const WeaveParams p = Weave(WeavePattern::kPlain, 0.0);
  const HeightMap map = GenerateWeave(p);
  const PeriodicTile tile = AnalysePeriodicity(map);
  // Residual well below the roughness, and no jump across a cell border.
  EXPECT_LT(tile.residual_rms_um(), 0.15 * map.RmsDeviationUm());
  const Eigen::Vector2d a = tile.basis_m().col(0);
  const Eigen::Vector2d b = tile.basis_m().col(1);
  double worst = 0.0;
  for (int i = 0; i < 50; ++i) {
    const Eigen::Vector2d q = Eigen::Vector2d(1e-3, 1e-3) + (i / 50.0) * b - 1e-9 * a;  // just inside the border
    const Eigen::Vector2d r = q + 2e-9 * a;                                             // just across it
    worst = std::max(worst, std::abs(tile.HeightUm(q.x(), q.y()) - tile.HeightUm(r.x(), r.y())));
  }
  EXPECT_LT(worst, 0.01 * map.RmsDeviationUm());
}

TEST(PeriodicityTest, WorksOnAnEightBitGreyImageOfTheFabric) {
  // The scan path: weave -> 8-bit PGM -> height map -> lattice (quantisation adds noise).
  const WeaveParams p = Weave(WeavePattern::kTwill, 0.0);
  const HeightMap original = GenerateWeave(p);
  std::stringstream pgm;
  WritePgm(GreyImageFromArray(original.height_um()), pgm);
  const double relief_um = original.height_um().maxCoeff() - original.height_um().minCoeff();
  const HeightMap scanned = HeightMapFromGreyImage(ReadPgm(pgm), p.pixel_size_m, relief_um);
  const LatticeEstimate dut = EstimateLattice(scanned);
  EXPECT_LT(LatticeMismatch(WeaveLatticeBasis(p), dut.basis_m), 0.01 * p.weft_pitch_m);
  EXPECT_NEAR(scanned.MeanAbsoluteDeviationUm(), p.smd_um, 0.05 * p.smd_um);
}

TEST(PeriodicityTest, NoiseOnlyMapHasNoLattice) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::ArrayXXd h(128, 128);
  for (Eigen::Index k = 0; k < h.size(); ++k) h(k) = normal(rng);
  EXPECT_THROW(EstimateLattice(HeightMap(h, 20e-6)), std::runtime_error);
}

TEST(PeriodicityTest, AutocorrelationOfAGratingPeaksAtItsPeriod) {
  Eigen::ArrayXXd h(64, 32);
  for (int x = 0; x < 64; ++x) h.row(x).setConstant(std::sin(2.0 * std::numbers::pi * x / 8.0));
  const Eigen::ArrayXXd r = NormalisedAutocorrelation(HeightMap(h, 1e-5), 16, 8);
  EXPECT_DOUBLE_EQ(r(16, 8), 1.0);
  EXPECT_NEAR(r(16 + 8, 8), 1.0, 0.01);   // one period (the detrending plane costs a little)
  EXPECT_NEAR(r(16 + 4, 8), -1.0, 0.01);  // half a period
}

TEST(PeriodicityTest, GaussReductionGivesShortVectors) {
  Eigen::Matrix2d b;
  b << 1.0, 5.0, 0.0, 1.0;  // (1,0), (5,1) -> (1,0), (0,1)
  const Eigen::Matrix2d r = ReduceBasis(b);
  EXPECT_NEAR(r.col(0).norm(), 1.0, 1e-12);
  EXPECT_NEAR(r.col(1).norm(), 1.0, 1e-12);
  EXPECT_NEAR(LatticeMismatch(b, r), 0.0, 1e-12);
  Eigen::Matrix2d half;
  half << 2.0, 0.0, 0.0, 1.0;
  EXPECT_TRUE(std::isinf(LatticeMismatch(b, half)));  // a sub-lattice is a different lattice
}

}  // namespace
}  // namespace haptex::tactile
