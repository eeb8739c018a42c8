#include "libs/tactile/pin_renderer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <ostream>
#include <string>
#include <utility>

#include <gtest/gtest.h>

#include "libs/tactile/periodicity.h"
#include "libs/tactile/weave_surface.h"
#include "tests/support/allocation_counter.h"

namespace haptex::tactile {
namespace {

// A sinusoidal grating along u: h = amplitude sin(2 pi u / period), constant along v.
PeriodicTile Grating(double period_m, double amplitude_um) {
  Eigen::Matrix2d basis;
  basis << period_m, 0.0, 0.0, period_m;
  Eigen::ArrayXXd h(64, 4);
  for (int i = 0; i < 64; ++i) h.row(i).setConstant(amplitude_um * std::sin(2.0 * std::numbers::pi * i / 64.0));
  return PeriodicTile(basis, Eigen::Vector2d::Zero(), h);
}

PeriodicTile WeaveTile(double smd_um) {
  WeaveParams p;
  p.smd_um = smd_um;
  p.size_x = 128;
  p.size_y = 128;
  return ExtractPeriodicTile(GenerateWeave(p), WeaveLatticeBasis(p));
}

struct Channels {
  double a40 = 0.0;  // mean over pins inside the contact area
  double a320 = 0.0;
  double max40 = 0.0;
  double max320 = 0.0;
};

Channels Summarise(const PinFrame& f) {
  Channels c;
  int n = 0;
  for (int k = 0; k < PinLayout::kPinCount; ++k) {
    const auto uk = static_cast<std::size_t>(k);
    c.a40 += static_cast<double>(f.amplitude_40hz[uk]);
    c.a320 += static_cast<double>(f.amplitude_320hz[uk]);
    c.max40 = std::max(c.max40, static_cast<double>(f.amplitude_40hz[uk]));
    c.max320 = std::max(c.max320, static_cast<double>(f.amplitude_320hz[uk]));
    ++n;
  }
  c.a40 /= n;
  c.a320 /= n;
  return c;
}

// Slides at constant velocity with ~1 kHz jittered updates and returns the mean amplitudes
// over the frames of the last 0.2 s.
Channels Slide(const RendererModel& model, const Eigen::Vector2d& velocity, double force_N, FingerRenderState* state,
               double orientation_rad = 0.0, double duration_s = 0.6, bool in_contact = true, double radius_m = 0.0) {
  RenderWorkspace ws;
  FingerInput in;
  // Continue from where the state's previous slide ended (a jump would count as a fault).
  in.touch_point_m = state->has_last_point ? state->last_point_m : Eigen::Vector2d(0.05, 0.05);
  in.slip_velocity_m_per_s = velocity;
  in.normal_force_N = force_N;
  in.in_contact = in_contact;
  in.orientation_rad = orientation_rad;
  in.contact_radius_m = radius_m;
  Channels sum;
  int frames = 0;
  double t = 0.0;
  for (int i = 0; t < duration_s; ++i) {
    const double dt = (i % 3 == 0) ? 0.0012 : 0.0009;  // variable dt
    t += dt;
    in.touch_point_m += velocity * dt;
    if (RenderStep(model, in, dt, state, &ws) > 0 && t > duration_s - 0.2) {
      const Channels c = Summarise(state->frame);
      sum.a40 += c.a40;
      sum.a320 += c.a320;
      sum.max40 = std::max(sum.max40, c.max40);
      sum.max320 = std::max(sum.max320, c.max320);
      ++frames;
    }
  }
  if (frames > 0) {
    sum.a40 /= frames;
    sum.a320 /= frames;
  }
  return sum;
}

bool AllZero(const PinFrame& f) {
  for (int k = 0; k < PinLayout::kPinCount; ++k) {
    if (f.amplitude_40hz[static_cast<std::size_t>(k)] != 0.0f || f.amplitude_320hz[static_cast<std::size_t>(k)] != 0.0f)
      return false;
  }
  return true;
}

bool AllFiniteInRange(const PinFrame& f) {
  for (int k = 0; k < PinLayout::kPinCount; ++k) {
    for (float a : {f.amplitude_40hz[static_cast<std::size_t>(k)], f.amplitude_320hz[static_cast<std::size_t>(k)]}) {
      if (!std::isfinite(a) || a < 0.0f || a > 1.0f) return false;
    }
  }
  return true;
}

TEST(PinRendererTest, FramesComeAtTheDisplayRate) {
  RendererConfig config;
  config.display_rate_hz = 250.0;
  const RendererModel dut(Grating(1e-3, 10.0), config);
  FingerRenderState state;
  RenderWorkspace ws;
  FingerInput in;
  int frames = 0;
  for (int i = 0; i < 1000; ++i) frames += RenderStep(dut, in, 0.001, &state, &ws);
  EXPECT_NEAR(frames, 250, 1);
  EXPECT_EQ(state.frame.sequence, static_cast<std::uint64_t>(frames));
}

TEST(PinRendererTest, SilentWithoutContact) {
  const RendererModel dut(Grating(1e-3, 20.0));
  FingerRenderState state;
  Slide(dut, {0.1, 0.0}, 2.0, &state, 0.0, 0.4, /*in_contact=*/false);
  EXPECT_TRUE(AllZero(state.frame));
}

TEST(PinRendererTest, SilentAtRest) {
  const RendererModel dut(Grating(1e-3, 20.0));
  FingerRenderState state;
  const Channels c = Slide(dut, {0.0, 0.0}, 2.0, &state);
  EXPECT_TRUE(AllZero(state.frame));
  EXPECT_EQ(c.max40, 0.0);
}

TEST(PinRendererTest, FallsSilentWhenSlidingStops) {
  const RendererModel dut(Grating(1e-3, 20.0));
  FingerRenderState state;
  const Channels moving = Slide(dut, {0.04, 0.0}, 1.0, &state);
  ASSERT_GT(moving.a40, 0.05);
  Slide(dut, {0.0, 0.0}, 1.0, &state, 0.0, 0.05);
  EXPECT_TRUE(AllZero(state.frame));
}

TEST(PinRendererTest, SlidingHasHysteresis) {
  const RendererModel dut(Grating(1e-3, 20.0));
  const double between = 0.5 * (dut.config().slide_start_speed_m_per_s + dut.config().slide_stop_speed_m_per_s);
  FingerRenderState from_rest;
  Slide(dut, {between, 0.0}, 1.0, &from_rest, 0.0, 0.3);
  EXPECT_FALSE(from_rest.sliding);
  EXPECT_TRUE(AllZero(from_rest.frame));
  FingerRenderState moving;
  Slide(dut, {0.04, 0.0}, 1.0, &moving);
  Slide(dut, {between, 0.0}, 1.0, &moving, 0.0, 0.05);
  EXPECT_TRUE(moving.sliding);  // keeps sliding until below the stop speed
}

TEST(PinRendererTest, SameInputSameFrames) {
  const RendererModel dut(WeaveTile(5.0));
  FingerRenderState a, b;
  Slide(dut, {0.03, -0.02}, 1.3, &a, 0.2);
  Slide(dut, {0.03, -0.02}, 1.3, &b, 0.2);
  EXPECT_EQ(a.frame.amplitude_40hz, b.frame.amplitude_40hz);
  EXPECT_EQ(a.frame.amplitude_320hz, b.frame.amplitude_320hz);
  EXPECT_EQ(a.frame.sequence, b.frame.sequence);
}

TEST(PinRendererTest, FastSlidesUseABandLimitedFabric) {
  const RendererModel dut(Grating(0.25e-3, 5.0));
  ASSERT_GE(dut.level_count(), 2);
  const PeriodicTile& slow = dut.FabricForSpeed(0.05);
  const PeriodicTile& fast = dut.FabricForSpeed(dut.config().max_speed_m_per_s);
  EXPECT_EQ(&slow, &dut.fabric());
  // A 0.25 mm grating is attenuated more in the level used at the top speed.
  EXPECT_LT(std::abs(fast.HeightUm(0.0625e-3, 0.0)), 0.5 * std::abs(slow.HeightUm(0.0625e-3, 0.0)));
}

TEST(PinRendererTest, PinsOutsideTheContactAreaAreSilent) {
  const RendererModel dut(Grating(1e-3, 20.0));
  FingerRenderState state;
  Slide(dut, {0.04, 0.0}, 1.0, &state, 0.0, 0.6, true, /*radius_m=*/3e-3);
  const PinLayout layout;
  int active = 0;
  for (int k = 0; k < PinLayout::kPinCount; ++k) {
    const auto uk = static_cast<std::size_t>(k);
    const bool inside = layout.OffsetOnFingerM(k).norm() <= 3e-3;
    if (!inside) {
      EXPECT_EQ(state.frame.amplitude_40hz[uk], 0.0f) << "pin " << k;
      EXPECT_EQ(state.frame.amplitude_320hz[uk], 0.0f) << "pin " << k;
    } else {
      EXPECT_GT(state.frame.amplitude_40hz[uk], 0.0f) << "pin " << k;
      ++active;
    }
  }
  EXPECT_GT(active, 0);
  EXPECT_LT(active, PinLayout::kPinCount);
}

struct GratingCase {
  double speed_m_per_s;
  bool low_dominates;
};

void PrintTo(const GratingCase& c, std::ostream* os) { *os << c.speed_m_per_s * 1000 << " mm/s"; }

class GratingChannelTest : public ::testing::TestWithParam<GratingCase> {};

TEST_P(GratingChannelTest, EnergyGoesToTheChannelContainingSpeedOverPeriod) {
  const RendererModel dut(Grating(1e-3, 5.0));
  const GratingCase gc = GetParam();
  // Both directions along the grating, and a rotated finger (orientation must not matter).
  for (const double sign : {1.0, -1.0}) {
    for (const double orientation : {0.0, 0.7}) {
      FingerRenderState state;
      const Channels c = Slide(dut, {sign * gc.speed_m_per_s, 0.0}, 1.0, &state, orientation);
      SCOPED_TRACE(::testing::Message() << "v=" << sign * gc.speed_m_per_s << " orientation=" << orientation);
      EXPECT_GT(c.a40 + c.a320, 0.01);
      if (gc.low_dominates) {
        EXPECT_GT(c.a40, 4.0 * c.a320);
      } else {
        EXPECT_GT(c.a320, 4.0 * c.a40);
      }
    }
  }
}

// p = 1 mm: 40 mm/s -> 40 Hz, 320 mm/s -> 320 Hz.
std::string SpeedName(const ::testing::TestParamInfo<GratingCase>& param_info) {
  return std::to_string(static_cast<int>(std::lround(param_info.param.speed_m_per_s * 1000))) + "mm_per_s";
}

INSTANTIATE_TEST_SUITE_P(OneMillimetre, GratingChannelTest,
                         ::testing::Values(GratingCase{0.040, true}, GratingCase{0.320, false}), SpeedName);

TEST(PinRendererTest, PureLineAtAPrimaryIsReproducedAtItsAmplitude) {
  // A 40 Hz line of 5 um (grating without the footprint blur) should drive 40 Hz at about 5 um.
  RendererConfig config;
  config.footprint_sigma_m = 0.0;
  const RendererModel dut(Grating(1e-3, 5.0), config);
  FingerRenderState state;
  const Channels c = Slide(dut, {0.04, 0.0}, 1.0, &state);
  EXPECT_NEAR(c.max40 * config.max_amplitude_40hz_um, 5.0, 0.5);
  EXPECT_LT(c.max320 * config.max_amplitude_320hz_um, 0.5);
}

TEST(PinRendererTest, MatchesTheSpectralComputationWithin1Db) {
  // Variant A (spectral) vs the real-time filter bank (variant B): a 1 mm grating with a second
  // harmonic, slid at v, is two lines at v/p and 2v/p. The expected drive follows from the line
  // amplitudes (attenuated by the footprint Gaussian), the filter responses and the matcher.
  const double period = 1e-3, a1 = 4.0, a2 = 2.0;
  Eigen::Matrix2d basis;
  basis << period, 0.0, 0.0, period;
  Eigen::ArrayXXd h(64, 4);
  for (int i = 0; i < 64; ++i) {
    const double x = 2.0 * std::numbers::pi * i / 64.0;
    h.row(i).setConstant(a1 * std::sin(x) + a2 * std::sin(2.0 * x));
  }
  const RendererModel dut(PeriodicTile(basis, Eigen::Vector2d::Zero(), h));
  const RendererConfig& c = dut.config();
  for (const double speed : {0.03, 0.06, 0.1, 0.15}) {
    double e_ra2 = 0.0, e_pc2 = 0.0;
    for (const auto& [harmonic, amplitude] : {std::pair{1.0, a1}, std::pair{2.0, a2}}) {
      const double wavelength = period / harmonic;
      const double f = speed / wavelength;
      const double a = amplitude * std::exp(-2.0 * std::numbers::pi * std::numbers::pi * c.footprint_sigma_m *
                                            c.footprint_sigma_m / (wavelength * wavelength));
      e_ra2 += std::pow(a * dut.ra_filter().ResponsePerUm(f), 2);
      e_pc2 += std::pow(a * dut.pc_filter().ResponsePerUm(f), 2);
    }
    const TactileColour expected = dut.matcher().Match(std::sqrt(e_ra2), std::sqrt(e_pc2));
    FingerRenderState state;
    const Channels rendered = Slide(dut, {speed, 0.0}, 1.0, &state);
    SCOPED_TRACE(::testing::Message() << "speed " << speed << " expected " << expected.amplitude_low_um << " / "
                                      << expected.amplitude_high_um << " um");
    const double lo = rendered.max40 * c.max_amplitude_40hz_um;
    const double hi = rendered.max320 * c.max_amplitude_320hz_um;
    // 1 dB, plus 0.1 um absolute for a primary that is (nearly) off.
    EXPECT_NEAR(lo, expected.amplitude_low_um, 0.12 * expected.amplitude_low_um + 0.1);
    EXPECT_NEAR(hi, expected.amplitude_high_um, 0.12 * expected.amplitude_high_um + 0.1);
  }
}

TEST(PinRendererTest, RougherFabricGivesLargerAmplitudes) {
  const RendererModel smooth(WeaveTile(2.0));
  const RendererModel rough(WeaveTile(8.0));
  FingerRenderState s1, s2;
  const Channels a = Slide(smooth, {0.05, 0.0}, 1.0, &s1);
  const Channels b = Slide(rough, {0.05, 0.0}, 1.0, &s2);
  ASSERT_GT(a.a40 + a.a320, 0.0);
  // Linear in height below the clamp: 4x the SMD gives 4x the drive.
  EXPECT_NEAR((b.a40 + b.a320) / (a.a40 + a.a320), 4.0, 0.2);
}

// Perceived intensity of the strongest pin of a frame: the channel excitations the two drive
// amplitudes produce, combined as stronger + half the weaker (docs/tactile.md section 1.1).
double PerceivedIntensity(const RendererModel& model, const PinFrame& f) {
  const RendererConfig& c = model.config();
  double best = 0.0;
  for (int k = 0; k < PinLayout::kPinCount; ++k) {
    const double lo = static_cast<double>(f.amplitude_40hz[static_cast<std::size_t>(k)]) * c.max_amplitude_40hz_um;
    const double hi = static_cast<double>(f.amplitude_320hz[static_cast<std::size_t>(k)]) * c.max_amplitude_320hz_um;
    const double ra = std::hypot(lo * model.ra_filter().ResponsePerUm(c.low_primary_hz),
                                 hi * model.ra_filter().ResponsePerUm(c.high_primary_hz));
    const double pc = std::hypot(lo * model.pc_filter().ResponsePerUm(c.low_primary_hz),
                                 hi * model.pc_filter().ResponsePerUm(c.high_primary_hz));
    best = std::max(best, std::max(ra, pc) + 0.5 * std::min(ra, pc));
  }
  return best;
}

TEST(PinRendererTest, AmplitudesGrowWithSpeedUntilTheySaturate) {
  // Weave with 0.4 mm threads: over exploration speeds its vibration moves from the insensitive
  // low frequencies up to the Pacinian optimum, so the rendered intensity rises with speed.
  const RendererModel dut(WeaveTile(8.0));
  double previous = 0.0;
  for (const double speed : {0.005, 0.01, 0.02, 0.05, 0.1}) {
    FingerRenderState state;
    Slide(dut, {speed, 0.0}, 1.0, &state);
    const double intensity = PerceivedIntensity(dut, state.frame);
    EXPECT_GT(intensity, 1.1 * previous) << "speed " << speed;
    previous = intensity;
  }
  // With a firm press the display range is reached and the drive saturates at 1.
  FingerRenderState state;
  const Channels pressed = Slide(dut, {0.1, 0.0}, 20.0, &state);
  EXPECT_FLOAT_EQ(static_cast<float>(std::max(pressed.max40, pressed.max320)), 1.0f);
  EXPECT_GT(state.counters.amplitude_clamped, 0u);
}

TEST(PinRendererTest, AmplitudesScaleWithForceAndAreClamped) {
  const RendererModel dut(Grating(1e-3, 5.0));
  FingerRenderState s1, s2, s3;
  const Channels one = Slide(dut, {0.04, 0.0}, 1.0, &s1);
  const Channels two = Slide(dut, {0.04, 0.0}, 2.0, &s2);
  EXPECT_NEAR(two.max40 / one.max40, 2.0, 0.05);
  const Channels huge = Slide(dut, {0.04, 0.0}, 19.0, &s3);
  EXPECT_FLOAT_EQ(static_cast<float>(huge.max40), 1.0f);
  EXPECT_TRUE(AllFiniteInRange(s3.frame));
  EXPECT_GT(s3.counters.amplitude_clamped, 0u);
}

TEST(PinRendererTest, BadInputGivesSilenceAndACount) {
  const RendererModel dut(Grating(1e-3, 20.0));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  struct Case {
    const char* name;
    Eigen::Vector2d velocity;
    double force;
    bool absurd;
  };
  for (const Case& bad : {Case{"nan velocity", {nan, 0.0}, 1.0, false}, Case{"nan force", {0.04, 0.0}, nan, false},
                          Case{"negative force", {0.04, 0.0}, -1.0, false}, Case{"inf force", {0.04, 0.0}, inf, false},
                          Case{"absurd speed", {50.0, 0.0}, 1.0, true}}) {
    SCOPED_TRACE(bad.name);
    FingerRenderState state;
    const Channels before = Slide(dut, {0.04, 0.0}, 1.0, &state);
    ASSERT_GT(before.a40, 0.0);
    RenderWorkspace ws;
    FingerInput in;
    in.touch_point_m = Eigen::Vector2d(0.06, 0.05);
    in.slip_velocity_m_per_s = bad.velocity;
    in.normal_force_N = bad.force;
    in.in_contact = true;
    int frames = 0;
    for (int i = 0; i < 10; ++i) frames += RenderStep(dut, in, 0.001, &state, &ws);
    EXPECT_GT(frames, 0);
    EXPECT_TRUE(AllZero(state.frame));
    EXPECT_TRUE(AllFiniteInRange(state.frame));
    EXPECT_EQ(bad.absurd ? state.counters.absurd_speed : state.counters.bad_input, 10u);
    // Good input afterwards renders again.
    const Channels after = Slide(dut, {0.04, 0.0}, 1.0, &state);
    EXPECT_GT(after.a40, 0.5 * before.a40);
  }
}

TEST(PinRendererTest, TouchingDownElsewhereIsNotAFault) {
  const RendererModel dut(Grating(1e-3, 20.0));
  FingerRenderState state;
  RenderWorkspace ws;
  Slide(dut, {0.04, 0.0}, 1.0, &state);
  FingerInput lifted;
  lifted.touch_point_m = state.last_point_m;
  RenderStep(dut, lifted, 0.001, &state, &ws);  // off the fabric
  FingerInput down = lifted;
  down.in_contact = true;
  down.normal_force_N = 1.0;
  down.slip_velocity_m_per_s = Eigen::Vector2d(0.04, 0.0);
  down.touch_point_m += Eigen::Vector2d(0.03, 0.02);  // 36 mm away, one step later
  RenderStep(dut, down, 0.001, &state, &ws);
  EXPECT_EQ(state.counters.absurd_speed, 0u);
  const Channels again = Slide(dut, {0.04, 0.0}, 1.0, &state);
  EXPECT_GT(again.max40, 0.0);
}

TEST(PinRendererTest, BadTimeStepsAreCountedNotRendered) {
  const RendererModel dut(Grating(1e-3, 20.0));
  FingerRenderState state;
  RenderWorkspace ws;
  FingerInput in;
  in.in_contact = true;
  in.normal_force_N = 1.0;
  EXPECT_EQ(RenderStep(dut, in, std::numeric_limits<double>::quiet_NaN(), &state, &ws), 0);
  EXPECT_EQ(RenderStep(dut, in, -0.001, &state, &ws), 0);
  EXPECT_EQ(state.counters.bad_input, 2u);
  EXPECT_EQ(RenderStep(dut, in, 10.0, &state, &ws), 1);  // a gap: one silent frame
  EXPECT_EQ(state.counters.time_gaps, 1u);
  EXPECT_TRUE(AllZero(state.frame));
}

TEST(PinRendererTest, ForceAboveTheMaximumIsClampedAndCounted) {
  const RendererModel dut(Grating(1e-3, 1.0));
  FingerRenderState a, b;
  const Channels at_max = Slide(dut, {0.04, 0.0}, 20.0, &a);
  const Channels above = Slide(dut, {0.04, 0.0}, 1000.0, &b);
  EXPECT_NEAR(above.a40, at_max.a40, 1e-6);
  EXPECT_GT(b.counters.force_clamped, 0u);
  EXPECT_EQ(a.counters.force_clamped, 0u);
}

TEST(PinRendererTest, BadConfigurationThrowsWithTheField) {
  RendererConfig config;
  config.display_rate_hz = -1.0;
  EXPECT_THROW(
      {
        try {
          RendererModel(Grating(1e-3, 1.0), config);
        } catch (const std::invalid_argument& e) {
          EXPECT_NE(std::string(e.what()).find("display_rate_hz"), std::string::npos);
          throw;
        }
      },
      std::invalid_argument);
  config = RendererConfig{};
  config.high_primary_hz = 3000.0;
  EXPECT_THROW(RendererModel(Grating(1e-3, 1.0), config), std::invalid_argument);
}

TEST(PinRendererTest, WarmedUpStepDoesNotAllocate) {
  if (!testing::AllocationCountingSupported()) GTEST_SKIP() << "allocation counting unavailable in this build";
  const RendererModel dut(WeaveTile(5.0));
  FingerRenderState state;
  RenderWorkspace ws;
  FingerInput in;
  in.in_contact = true;
  in.normal_force_N = 1.5;
  in.slip_velocity_m_per_s = Eigen::Vector2d(0.05, 0.02);
  in.orientation_rad = 0.3;
  for (int i = 0; i < 100; ++i) {
    in.touch_point_m += in.slip_velocity_m_per_s * 0.001;
    RenderStep(dut, in, 0.001, &state, &ws);
  }
  int frames = 0;
  {
    haptex::testing::AllocationCounter counter;
    for (int i = 0; i < 100; ++i) {
      in.touch_point_m += in.slip_velocity_m_per_s * 0.001;
      frames += RenderStep(dut, in, 0.001, &state, &ws);
    }
    // Faulty input takes the same no-allocation path.
    in.normal_force_N = std::numeric_limits<double>::quiet_NaN();
    frames += RenderStep(dut, in, 0.001, &state, &ws);
    EXPECT_EQ(counter.count(), 0);
  }
  EXPECT_GT(frames, 40);
}

}  // namespace
}  // namespace haptex::tactile
