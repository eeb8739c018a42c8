#include "libs/tactile/receptor_filter.h"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

namespace haptex::tactile {
namespace {

constexpr double kRate = 4000.0;

// Peak excitation (threshold units) of a steady sinusoid through the channel filter.
double SimulatedExcitation(const ReceptorChannelFilter& f, double frequency_hz, double amplitude_um) {
  BiquadState hp, lp;
  hp.Reset(f.high_pass(), 0.0);
  lp.Reset(f.low_pass(), 0.0);
  double sum = 0.0;
  int n = 0;
  const int total = static_cast<int>(2.0 * kRate);
  for (int i = 0; i < total; ++i) {
    const double x = amplitude_um * std::sin(2.0 * std::numbers::pi * frequency_hz * i / kRate);
    const double y = f.gain_per_um() * lp.Process(f.low_pass(), hp.Process(f.high_pass(), x));
    if (i >= total / 2) {
      sum += y * y;
      ++n;
    }
  }
  return std::sqrt(2.0 * sum / n);
}

TEST(ThresholdCurveTest, InterpolatesTheTablesOfTheNotes) {
  const ThresholdCurve ra = ThresholdCurve::DefaultRa();
  const ThresholdCurve pc = ThresholdCurve::DefaultPc();
  // docs/tactile.md section 7: T_RA(40)=3.16, T_PC(40)=3.98, T_RA(320)=25.1, T_PC(320)=0.355 um.
  EXPECT_NEAR(ra.ThresholdUm(40.0), 3.16, 0.01);
  EXPECT_NEAR(pc.ThresholdUm(40.0), 3.98, 0.01);
  EXPECT_NEAR(ra.ThresholdUm(320.0), 25.1, 0.1);
  EXPECT_NEAR(pc.ThresholdUm(320.0), 0.355, 0.001);
  EXPECT_NEAR(ra.ThresholdDb(56.5685), 11.5, 1e-3);  // halfway between 40 and 80 Hz in log f
}

TEST(ThresholdCurveTest, RejectsUnsortedPoints) {
  EXPECT_THROW(ThresholdCurve({{40, 1}, {20, 2}}), std::invalid_argument);
  EXPECT_THROW(ThresholdCurve({{40, 1}}), std::invalid_argument);
}

TEST(ReceptorFilterTest, SinusoidAtThresholdGivesExcitationOne) {
  const ReceptorChannelFilter ra(DefaultRaShape(), ThresholdCurve::DefaultRa(), kRate);
  const ReceptorChannelFilter pc(DefaultPcShape(), ThresholdCurve::DefaultPc(), kRate);
  EXPECT_NEAR(SimulatedExcitation(ra, 40.0, ThresholdCurve::DefaultRa().ThresholdUm(40.0)), 1.0, 0.01);
  EXPECT_NEAR(SimulatedExcitation(pc, 250.0, ThresholdCurve::DefaultPc().ThresholdUm(250.0)), 1.0, 0.01);
  // The simulated filter agrees with its analytic response.
  EXPECT_NEAR(SimulatedExcitation(pc, 80.0, 3.0), 3.0 * pc.ResponsePerUm(80.0), 0.01 * 3.0 * pc.ResponsePerUm(80.0));
}

TEST(ReceptorFilterTest, ResponseFollowsTheInverseThreshold) {
  const ThresholdCurve ra_t = ThresholdCurve::DefaultRa();
  const ThresholdCurve pc_t = ThresholdCurve::DefaultPc();
  const ReceptorChannelFilter ra(DefaultRaShape(), ra_t, kRate);
  const ReceptorChannelFilter pc(DefaultPcShape(), pc_t, kRate);
  for (const double f : {20.0, 40.0, 80.0, 160.0, 250.0, 320.0}) {
    // RA: a 2+2-pole shape cannot follow the table's kink at 40 Hz exactly; pinned at 40 Hz.
    EXPECT_NEAR(20.0 * std::log10(ra.ResponsePerUm(f) * ra_t.ThresholdUm(f)), 0.0, 2.5) << "RA at " << f;
    EXPECT_NEAR(20.0 * std::log10(pc.ResponsePerUm(f) * pc_t.ThresholdUm(f)), 0.0, 1.0) << "PC at " << f;
  }
  // The channels are tuned apart: RA prefers 40 Hz, PC 320 Hz.
  EXPECT_GT(ra.ResponsePerUm(40.0), ra.ResponsePerUm(320.0));
  EXPECT_GT(pc.ResponsePerUm(320.0), 10.0 * pc.ResponsePerUm(40.0));
}

TEST(ReceptorFilterTest, ResetGivesSteadyStateWithoutTransient) {
  const Biquad hp = DesignHighPass(20.0, 0.7, kRate);
  const Biquad lp = DesignLowPass(100.0, 0.7, kRate);
  BiquadState a, b;
  a.Reset(hp, 37.0);
  b.Reset(lp, 37.0);
  for (int i = 0; i < 10; ++i) {
    EXPECT_NEAR(a.Process(hp, 37.0), 0.0, 1e-9);
    EXPECT_NEAR(b.Process(lp, 37.0), 37.0, 1e-9);
  }
}

TEST(ReceptorFilterTest, BadDesignThrows) {
  EXPECT_THROW(DesignLowPass(3000.0, 0.7, kRate), std::invalid_argument);
  EXPECT_THROW(DesignHighPass(100.0, 0.0, kRate), std::invalid_argument);
}

}  // namespace
}  // namespace haptex::tactile
