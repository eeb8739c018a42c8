// The paper's figures measured from series: Fig. 9's stick peak and sliding plateau, Fig. 10's
// force against elongation beside the fabric's tensile curve.
#include "launch/figure_curves.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace haptex::launch {
namespace {

constexpr int kIV = 4, kV = 5, kVIII = 8;

// A finger pressed with 1 N rubbed at 1 kHz: the ratio climbs to `peak` in 0.3 s while it sticks
// (IV), then slides (V) 0.4 s, falling to `slide` over its first 10 ms.
void AppendStroke(double peak, double slide, int* tick, std::vector<FrictionSample>* out) {
  for (int k = 0; k < 300; ++k, ++*tick) out->push_back({*tick * 0.001, 1.0, peak * k / 299.0, kIV});
  for (int k = 0; k < 400; ++k, ++*tick) {
    out->push_back({*tick * 0.001, 1.0, std::max(slide, peak - (peak - slide) * k / 10.0), kV});
  }
}

TEST(LaunchFigureCurvesTest, StickPeakAndSlidePlateauOfEachBreakaway) {
  std::vector<FrictionSample> samples;
  int tick = 0;
  AppendStroke(0.41, 0.2, &tick, &samples);
  AppendStroke(0.39, 0.21, &tick, &samples);
  const StickSlipFigure f = MeasureStickSlip(samples);
  EXPECT_EQ(f.breakaways, 2);
  EXPECT_NEAR(f.first_peak, 0.41, 1e-12);
  EXPECT_NEAR(f.first_peak_t_s, 0.299, 1e-9);
  EXPECT_NEAR(f.peak_min, 0.39, 1e-12);
  EXPECT_NEAR(f.peak_max, 0.41, 1e-12);
  EXPECT_NEAR(f.peak_median, 0.41, 1e-12) << "nearest rank of two: the upper";
  // past the 20-sample transient of each slide: 380 samples at 0.2, 380 at 0.21
  EXPECT_NEAR(static_cast<double>(f.slide_samples), 760.0, 2.0);
  EXPECT_NEAR(f.slide_p10, 0.2, 1e-12);
  EXPECT_NEAR(f.slide_p90, 0.21, 1e-12);
}

// The slide is named a few ticks after the contact broke away: the peak is the break-away's,
// not the last value the stick state saw.
TEST(LaunchFigureCurvesTest, PeakFoundWhenTheSlideIsNamedLate) {
  std::vector<FrictionSample> samples;
  double t = 0.0;
  for (int k = 0; k < 100; ++k, t += 0.001) samples.push_back({t, 2.0, 0.8 * k / 99.0, kIV});
  for (int k = 0; k < 5; ++k, t += 0.001) samples.push_back({t, 2.0, 0.6, kIV});  // slipped, still named IV
  samples.push_back({t, 2.0, 0.84, kV});  // the peak lands on the first V tick (0.42)
  t += 0.001;
  for (int k = 0; k < 200; ++k, t += 0.001) samples.push_back({t, 2.0, 0.4, kV});
  const StickSlipFigure f = MeasureStickSlip(samples);
  EXPECT_EQ(f.breakaways, 1);
  EXPECT_NEAR(f.first_peak, 0.42, 1e-12);
  EXPECT_NEAR(f.slide_median, 0.2, 1e-12);
}

// A finger pressed on at a slant starts its stick with a high ratio; that is how it met the
// fabric, not where it broke away (30 samples before the slide and 20 after it are the break-away's).
TEST(LaunchFigureCurvesTest, TheStartOfAStickIsNotItsBreakaway) {
  std::vector<FrictionSample> samples;
  double t = 0.0;
  samples.push_back({t, 1.0, 0.46, kIV});
  t += 0.001;
  for (int k = 0; k < 200; ++k, t += 0.001) samples.push_back({t, 1.0, 0.37 * k / 199.0, kIV});
  for (int k = 0; k < 100; ++k, t += 0.001) samples.push_back({t, 1.0, 0.2, kV});
  const StickSlipFigure f = MeasureStickSlip(samples);
  EXPECT_EQ(f.breakaways, 1);
  EXPECT_NEAR(f.first_peak, 0.37, 1e-12);
  EXPECT_NEAR(f.first_peak_t_s, 0.2, 1e-9);
}

// A host stall between the break-away and the state's naming of the slide drops ticks from the
// series: the peak is still the break-away's (its window counts samples, not seconds).
TEST(LaunchFigureCurvesTest, AStallOfTheHostDoesNotHideTheBreakaway) {
  std::vector<FrictionSample> samples;
  double t = 0.0;
  for (int k = 0; k < 100; ++k, t += 0.001) samples.push_back({t, 1.0, 0.4 * k / 99.0, kIV});
  for (int k = 0; k < 5; ++k, t += 0.001) samples.push_back({t, 1.0, 0.2, kIV});  // slipped, still named IV
  t += 0.052;                                                                     // the stall
  for (int k = 0; k < 2; ++k, t += 0.001) samples.push_back({t, 1.0, 0.2, kIV});
  for (int k = 0; k < 100; ++k, t += 0.001) samples.push_back({t, 1.0, 0.2, kV});
  const StickSlipFigure f = MeasureStickSlip(samples);
  EXPECT_EQ(f.breakaways, 1);
  EXPECT_NEAR(f.first_peak, 0.4, 1e-12);
  EXPECT_NEAR(f.first_peak_t_s, 0.099, 1e-9);
  EXPECT_EQ(f.slide_samples, 80u) << "a slide of 100 past its first 20 samples";
}

// Sliding without a stick before it (it started sliding), a light touch, or another state
// (a pinch) is no break-away; a press that lifts in between starts afresh.
TEST(LaunchFigureCurvesTest, NoBreakawayWithoutAStickOfTheSamePress) {
  std::vector<FrictionSample> samples;
  double t = 0.0;
  for (int k = 0; k < 50; ++k, t += 0.001) samples.push_back({t, 1.0, 0.3, kIV});
  samples.push_back({t, 0.01, 0.0, kIV});  // lifted
  t += 0.001;
  for (int k = 0; k < 50; ++k, t += 0.001) samples.push_back({t, 1.0, 0.2, kV});
  for (int k = 0; k < 50; ++k, t += 0.001) samples.push_back({t, 1.0, 0.9, kVIII});
  for (int k = 0; k < 50; ++k, t += 0.001) samples.push_back({t, 1.0, 0.2, kV});
  const StickSlipFigure f = MeasureStickSlip(samples);
  EXPECT_EQ(f.breakaways, 0);
  EXPECT_EQ(f.first_peak, 0.0);
  EXPECT_NEAR(static_cast<double>(f.slide_samples), 60.0, 2.0) << "each slide of 50 past its first 20 samples";
  EXPECT_NEAR(f.slide_median, 0.2, 1e-12);
  EXPECT_EQ(MeasureStickSlip({}).breakaways, 0);
}

TEST(LaunchFigureCurvesTest, ForceAgainstElongationBesideTheTensileCurve) {
  // a 12 mm strip clamped 50 mm from the pinch, linear fabric 400 N/m: 0.096 N per mm
  const TensileStrip strip{0.05, 0.012, [](double strain) { return 400.0 * strain; }};
  EXPECT_NEAR(StripForceN(strip, 0.001), 0.096, 1e-12);
  std::vector<StretchSample> samples;
  for (int k = -2; k <= 10; ++k) {
    const double e = 0.0002 * k;
    samples.push_back({e, StripForceN(strip, e) + (k % 2 == 0 ? 0.003 : -0.003)});
  }
  const ForceElongationFigure f = CompareWithTensileCurve(samples, strip);
  EXPECT_EQ(f.samples, 11u) << "the two before the pull (elongation < 0) are not compared";
  EXPECT_NEAR(f.max_elongation_m, 0.002, 1e-15);
  EXPECT_NEAR(f.curve_peak_N, 0.192, 1e-12);
  EXPECT_NEAR(f.rms_difference_N, 0.003, 1e-12);
  EXPECT_NEAR(f.max_difference_N, 0.003, 1e-12);
  EXPECT_NEAR(f.rms_percent_of_peak, 100.0 * 0.003 / 0.192, 1e-9);
  EXPECT_EQ(CompareWithTensileCurve({}, strip).samples, 0u);
}

}  // namespace
}  // namespace haptex::launch
