#include "libs/tactile/tactile_colour.h"

#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>

#include "libs/tactile/receptor_filter.h"

namespace haptex::tactile {
namespace {

// The matcher built from the threshold tables themselves (|W| = 1 / T), as in docs/tactile.md section 7.1.
ColourMatcher TableMatcher() {
  const ThresholdCurve ra = ThresholdCurve::DefaultRa();
  const ThresholdCurve pc = ThresholdCurve::DefaultPc();
  return ColourMatcher(1.0 / ra.ThresholdUm(40.0), 1.0 / ra.ThresholdUm(320.0), 1.0 / pc.ThresholdUm(40.0),
                       1.0 / pc.ThresholdUm(320.0));
}

TEST(TactileColourTest, LinesAtThePrimariesAreReproducedExactly) {
  const ThresholdCurve ra = ThresholdCurve::DefaultRa();
  const ThresholdCurve pc = ThresholdCurve::DefaultPc();
  const ColourMatcher dut = TableMatcher();
  // 40 Hz 10 um + 320 Hz 1 um (docs/tactile.md section 7.1: E_RA = 3.16, E_PC = 3.78).
  const double e_ra = std::hypot(10.0 / ra.ThresholdUm(40.0), 1.0 / ra.ThresholdUm(320.0));
  const double e_pc = std::hypot(10.0 / pc.ThresholdUm(40.0), 1.0 / pc.ThresholdUm(320.0));
  EXPECT_NEAR(e_ra, 3.16, 0.01);
  EXPECT_NEAR(e_pc, 3.78, 0.01);
  const TactileColour c = dut.Match(e_ra, e_pc);
  EXPECT_NEAR(c.amplitude_low_um, 10.0, 1e-9);
  EXPECT_NEAR(c.amplitude_high_um, 1.0, 1e-9);
  EXPECT_FALSE(c.out_of_gamut);
}

TEST(TactileColourTest, WorkedExampleFromTheNotes) {
  // Grating p = 0.5 mm, a = 5 um at 100 mm/s (200 Hz): matched A40 = 0.99, A320 = 5.00 um
  // (docs/tactile.md section 7.1, computed by docs/derivations/tactile_colour.py).
  const ThresholdCurve ra = ThresholdCurve::DefaultRa();
  const ThresholdCurve pc = ThresholdCurve::DefaultPc();
  const TactileColour c = TableMatcher().Match(5.0 / ra.ThresholdUm(200.0), 5.0 / pc.ThresholdUm(200.0));
  EXPECT_NEAR(c.amplitude_low_um, 0.99, 0.01);
  EXPECT_NEAR(c.amplitude_high_um, 5.00, 0.01);
}

TEST(TactileColourTest, PureRaTargetIsOutOfGamutWithZeroHighAmplitude) {
  // A 20 Hz line excites RA far more than PC relative to the primaries.
  const ThresholdCurve ra = ThresholdCurve::DefaultRa();
  const ThresholdCurve pc = ThresholdCurve::DefaultPc();
  const double e_ra = 10.0 / ra.ThresholdUm(20.0);
  const TactileColour c = TableMatcher().Match(e_ra, 10.0 / pc.ThresholdUm(20.0));
  EXPECT_TRUE(c.out_of_gamut);
  EXPECT_EQ(c.amplitude_high_um, 0.0);
  EXPECT_NEAR(c.amplitude_low_um, e_ra * ra.ThresholdUm(40.0), 1e-9);  // RA excitation kept
  const TactileColour silent = TableMatcher().Match(0.0, 0.0);
  EXPECT_EQ(silent.amplitude_low_um, 0.0);
  EXPECT_EQ(silent.amplitude_high_um, 0.0);
}

TEST(TactileColourTest, SingularPrimariesThrow) {
  EXPECT_THROW(ColourMatcher(1.0, 1.0, 2.0, 2.0), std::invalid_argument);
}

}  // namespace
}  // namespace haptex::tactile
