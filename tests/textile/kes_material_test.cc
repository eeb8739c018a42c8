#include "libs/textile/kes_material.h"

#include <cmath>
#include <limits>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "tests/textile/textile_test_util.h"

namespace haptex::textile {
namespace {

using ::testing::HasSubstr;

// Expects `fn` to throw std::invalid_argument whose message contains `text`.
template <typename Fn>
void ExpectThrowsWith(Fn fn, const std::string& text) {
  try {
    fn();
    ADD_FAILURE() << "no exception, expected one mentioning " << text;
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr(text));
  }
}

TEST(KesMaterialTest, ConvertsUnits) {
  const FabricMaterial m = MaterialFromKes(testing::CompositeDenim());
  EXPECT_NEAR(m.density_kg_per_m2, 0.324, 1e-12);
  EXPECT_NEAR(m.bending_warp_Nm, 0.164 * 9.80665e-5, 1e-15);
  EXPECT_NEAR(m.bending_weft_Nm, 0.247 * 9.80665e-5, 1e-15);
  EXPECT_NEAR(m.thickness_m, 1.188e-3, 1e-15);
  // Shear: G [gf/(cm deg)] -> N/m per rad.
  EXPECT_NEAR(m.shear.Value(0.01), 0.475 * 56.18796561619688 * 0.01, 1e-9);
  EXPECT_NEAR(m.shear.Value(-0.01), -m.shear.Value(0.01), 1e-15);
}

TEST(KesMaterialTest, PowerLawReproducesEmtAndLt) {
  kes::KesTensile t;
  t.emt_percent = 5.735;
  t.lt = 0.655;
  const StrainCurve c = TensileCurveFromKes(t, "warp_tensile");
  const double em = 0.05735, fm = 500 * 0.980665;
  // EMT: the curve reaches Fm at EMT.
  EXPECT_NEAR(c.Value(em), fm, 1e-9 * fm);
  // LT = WT / (Fm em / 2): integrate the curve.
  double wt = 0.0;
  const int n = 20000;
  for (int i = 0; i < n; ++i) wt += c.Value((i + 0.5) * em / n) * em / n;
  EXPECT_NEAR(wt / (fm * em / 2), 0.655, 0.01);
  // Never flat at zero strain (floor) and soft under compression.
  EXPECT_GT(c.loading().Slope(0.0), 0.0);
  EXPECT_LT(c.Value(-0.01), 0.0);
}

TEST(KesMaterialTest, UsesDigitizedCurveWhenPresent) {
  kes::KesTensile t;
  t.emt_percent = 99.0;  // ignored: the curve wins
  t.lt = 0.5;
  t.loading_curve = {{0.01, 10.0}, {0.02, 50.0}};
  const StrainCurve c = TensileCurveFromKes(t, "weft_tensile");
  EXPECT_NEAR(c.Value(0.0), 0.0, 1e-12);
  EXPECT_NEAR(c.Value(0.01), 10.0 * 0.980665, 1e-9);
  EXPECT_NEAR(c.Value(0.02), 50.0 * 0.980665, 1e-9);
}

// Compression continues the curve's small-strain slope (its tangent at zero strain), so a bent
// region keeps its length; never flatter than the floor, so a curve with a flat toe still resists.
TEST(KesMaterialTest, CompressionContinuesTheSmallStrainSlope) {
  kes::KesTensile linear;
  linear.loading_curve = {{0.0, 0.0}, {0.05, 205.626}};
  const StrainCurve c = TensileCurveFromKes(linear, "warp_tensile");
  const double k_N_per_m = 205.626 * 0.980665 / 0.05;
  EXPECT_NEAR(c.compression_N_per_m(), k_N_per_m, 1e-9 * k_N_per_m);
  EXPECT_NEAR(c.Value(-1e-3), -1e-3 * k_N_per_m, 1e-9);

  kes::KesTensile toe;  // flat up to 1 %, then 20 gf/cm at 2 %
  toe.loading_curve = {{0.0, 0.0}, {0.01, 0.0}, {0.02, 20.0}};
  const double secant_N_per_m = 20.0 * 0.980665 / 0.02;
  EXPECT_NEAR(TensileCurveFromKes(toe, "warp_tensile").compression_N_per_m(), 0.02 * secant_N_per_m, 1e-9);

  // The power law's slope at zero is its floor: compression as before, 2 % of Fm/EMT.
  kes::KesTensile power;
  power.emt_percent = 5.735;
  power.lt = 0.655;
  const double power_secant_N_per_m = 500 * 0.980665 / 0.05735;
  EXPECT_NEAR(TensileCurveFromKes(power, "warp_tensile").compression_N_per_m(), 0.02 * power_secant_N_per_m,
              1e-9 * power_secant_N_per_m);

  KesConversionOptions half;
  half.compression_fraction = 0.5;
  EXPECT_NEAR(TensileCurveFromKes(linear, "warp_tensile", half).compression_N_per_m(), 0.5 * k_N_per_m,
              1e-9 * k_N_per_m);
}

TEST(KesMaterialTest, ErrorsNameTheField) {
  auto fabric = testing::CompositeDenim();
  fabric.name = "bad";
  {
    auto f = fabric;
    f.weight_mg_per_cm2 = 0.0;
    ExpectThrowsWith([&] { MaterialFromKes(f); }, "weight_mg_per_cm2 is missing");
  }
  {
    auto f = fabric;
    f.warp_bending.b_gfcm2_per_cm = -0.1;
    ExpectThrowsWith([&] { MaterialFromKes(f); }, "warp_bending.b_gfcm2_per_cm");
  }
  {
    auto f = fabric;
    f.shear.g_gf_per_cm_deg = std::numeric_limits<double>::quiet_NaN();
    ExpectThrowsWith([&] { MaterialFromKes(f); }, "shear.g_gf_per_cm_deg");
  }
  {
    auto f = fabric;
    f.weft_tensile.emt_percent = 0.0;
    ExpectThrowsWith([&] { MaterialFromKes(f); }, "weft_tensile.emt_percent");
  }
  {
    auto f = fabric;
    f.warp_tensile.loading_curve = {{0.01, 5.0}, {0.005, 6.0}};
    ExpectThrowsWith([&] { MaterialFromKes(f); }, "warp_tensile.loading_curve[1].x");
  }
  {
    auto f = fabric;
    f.thickness_mm = -1.0;
    ExpectThrowsWith([&] { MaterialFromKes(f); }, "thickness_mm");
  }
  {
    auto f = fabric;
    f.thickness_mm = 0.0;  // optional: unknown
    EXPECT_NO_THROW(MaterialFromKes(f));
  }
}

}  // namespace
}  // namespace haptex::textile
