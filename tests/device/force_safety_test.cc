#include "libs/device/force_safety.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace haptex::device {
namespace {

constexpr double kTick_s = 2e-4;

SafetyInput Request(const Eigen::Vector3d& force_N) {
  SafetyInput in;
  in.requested_W_N = force_N;
  in.model_age_s = 0.0;
  in.model_ttl_s = 0.010;
  in.output_allowed = true;
  return in;
}

// Ticks of fresh requests until the force is back at `request` (along x), or -1 within 1 s.
int TicksToFull(ForceSafety& dut, const Eigen::Vector3d& request) {
  for (int k = 1; k <= 5000; ++k) {
    if (dut.Step(Request(request), kTick_s).force_W_N.x() >= request.x() - 1e-6) return k;
  }
  return -1;
}

// A ForceModel asking for 100 N for 10 s: never above 20 N, never more than 0.5 N change per
// tick, always along the requested direction, and the RMS settles at the 6 N continuous limit.
TEST(ForceSafetyTest, ClampsAndSlewHoldUnderAHundredNewtonRequest) {
  ForceSafetyConfig config;
  config.startup_ramp_s = 0.05;
  ForceSafety dut(config);
  const Eigen::Vector3d dir = Eigen::Vector3d(1.0, -2.0, 0.5).normalized();
  Eigen::Vector3d previous = Eigen::Vector3d::Zero();
  double peak_seen_N = 0.0;
  for (int k = 0; k < 50000; ++k) {
    const SafetyOutput out = dut.Step(Request(100.0 * dir), kTick_s);
    const double n = out.force_W_N.norm();
    peak_seen_N = std::max(peak_seen_N, n);
    ASSERT_LE(n, 20.0 + 1e-9) << "tick " << k;
    ASSERT_LE((out.force_W_N - previous).norm(), 0.5 + 1e-9) << "tick " << k;
    if (n > 1e-9) {
      ASSERT_LT(out.force_W_N.normalized().cross(dir).norm(), 1e-9) << "tick " << k;
    }
    ASSERT_LE(dut.rms_force_N(), 6.0 + 1e-9) << "tick " << k;
    previous = out.force_W_N;
  }
  EXPECT_GT(peak_seen_N, 15.0);             // short bursts may go well above 6 N
  EXPECT_NEAR(previous.norm(), 6.0, 1e-3);  // sustained force is the continuous limit
  EXPECT_GT(dut.counters().peak_limited, 0u);
  EXPECT_GT(dut.counters().continuous_limited, 0u);
  EXPECT_GT(dut.counters().slew_limited, 0u);
}

TEST(ForceSafetyTest, SlewLimitsASuddenReversal) {
  ForceSafetyConfig config;
  config.startup_ramp_s = 0.0;
  ForceSafety dut(config);
  for (int k = 0; k < 100; ++k) dut.Step(Request({5.0, 0.0, 0.0}), kTick_s);
  ASSERT_NEAR(dut.last_force_W_N().x(), 5.0, 1e-12);
  const SafetyOutput out = dut.Step(Request({-5.0, 0.0, 0.0}), kTick_s);
  EXPECT_NEAR(out.force_W_N.x(), 4.5, 1e-12);
  EXPECT_TRUE(out.limited);
}

TEST(ForceSafetyTest, NonFiniteRequestBecomesZeroAndIsCounted) {
  ForceSafetyConfig config;
  config.startup_ramp_s = 0.0;
  ForceSafety dut(config);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 20; ++k) dut.Step(Request({0.0, 0.4, 0.0}), kTick_s);
  SafetyOutput out = dut.Step(Request({nan, 1.0, 0.0}), kTick_s);
  EXPECT_TRUE(out.force_W_N.allFinite());
  // zero request, reached within the slew limit (0.4 N < 0.5 N per tick)
  EXPECT_EQ(out.force_W_N, Eigen::Vector3d::Zero());
  out = dut.Step(Request({0.0, -inf, 0.0}), kTick_s);
  EXPECT_EQ(out.force_W_N, Eigen::Vector3d::Zero());
  EXPECT_EQ(dut.counters().non_finite, 2u);
  EXPECT_TRUE(std::isfinite(dut.rms_force_N()));
}

TEST(ForceSafetyTest, WatchdogHoldsThenRampsToExactlyZeroAtTwentyMilliseconds) {
  ForceSafetyConfig config;
  config.startup_ramp_s = 0.0;
  ForceSafety dut(config);
  const Eigen::Vector3d request(0.0, 0.0, 15.0);
  for (int k = 0; k < 200; ++k) dut.Step(Request(request), kTick_s);
  ASSERT_NEAR(dut.last_force_W_N().z(), 15.0, 1e-9);
  // the model stops arriving: age grows by one tick per step
  for (int k = 1; k <= 150; ++k) {
    SafetyInput in = Request(request);
    in.model_age_s = k * kTick_s;
    const SafetyOutput out = dut.Step(in, kTick_s);
    if (in.model_age_s <= 0.010 + 1e-9) {
      EXPECT_NEAR(out.force_W_N.z(), 15.0, 1e-9) << "still fresh at " << in.model_age_s;
    } else if (in.model_age_s >= 0.020 - 1e-9) {
      EXPECT_EQ(out.force_W_N, Eigen::Vector3d::Zero()) << "age " << in.model_age_s;
    } else {
      const double expected = 15.0 * (1.0 - (in.model_age_s - 0.010) / 0.010);
      EXPECT_NEAR(out.force_W_N.z(), expected, 1e-6) << "age " << in.model_age_s;
      EXPECT_TRUE(out.ramping);
    }
  }
  EXPECT_GT(dut.counters().watchdog_zero_steps, 0u);
}

TEST(ForceSafetyTest, ShortTtlEndsFreshnessEarlier) {
  ForceSafetyConfig config;
  config.startup_ramp_s = 0.0;
  ForceSafety dut(config);
  SafetyInput in = Request({1.0, 0.0, 0.0});
  in.model_ttl_s = 0.002;
  in.model_age_s = 0.012 + kTick_s;  // 2 ms ttl + 10 ms ramp are over
  for (int k = 0; k < 5; ++k) dut.Step(in, kTick_s);
  EXPECT_EQ(dut.last_force_W_N(), Eigen::Vector3d::Zero());
}

TEST(ForceSafetyTest, NoModelOrNotAllowedMeansZero) {
  ForceSafety dut(ForceSafetyConfig{});
  SafetyInput in = Request({3.0, 0.0, 0.0});
  in.model_age_s = std::numeric_limits<double>::infinity();
  EXPECT_EQ(dut.Step(in, kTick_s).force_W_N, Eigen::Vector3d::Zero());
  in = Request({3.0, 0.0, 0.0});
  in.output_allowed = false;
  EXPECT_EQ(dut.Step(in, kTick_s).force_W_N, Eigen::Vector3d::Zero());
}

TEST(ForceSafetyTest, StartupRampScalesForceIn) {
  ForceSafetyConfig config;
  config.startup_ramp_s = 0.5;
  ForceSafety dut(config);
  const Eigen::Vector3d request(4.0, 0.0, 0.0);
  for (int k = 1; k <= 1250; ++k) dut.Step(Request(request), kTick_s);  // 0.25 s
  EXPECT_NEAR(dut.last_force_W_N().x(), 2.0, 1e-6);
  for (int k = 0; k < 1500; ++k) dut.Step(Request(request), kTick_s);
  EXPECT_NEAR(dut.last_force_W_N().x(), 4.0, 1e-9);
  // a forced zero (device not allowed) re-arms the ramp
  SafetyInput off = Request(request);
  off.output_allowed = false;
  dut.Step(off, kTick_s);
  EXPECT_EQ(dut.last_force_W_N(), Eigen::Vector3d::Zero());
  dut.Step(Request(request), kTick_s);
  EXPECT_NEAR(dut.last_force_W_N().x(), 4.0 * kTick_s / 0.5, 1e-9);
}

// A brief link interruption (host stall, controller host timeout) of a fully armed stage resumes
// over resume_ramp_s, not the half-second start-up ramp, which would let a squeezing user's fingers
// close through the fabric (force_safety.h). Other forced zeros, an interruption during the
// start-up ramp, and long interruptions keep the start-up ramp.
TEST(ForceSafetyTest, BriefLinkInterruptionResumesOverResumeRamp) {
  ForceSafetyConfig config;
  config.startup_ramp_s = 0.5;
  config.resume_ramp_s = 0.02;
  config.resume_within_s = 0.05;
  const Eigen::Vector3d request(2.0, 0.0, 0.0);
  SafetyInput link = Request(request);
  link.output_allowed = false;
  link.link_interruption = true;
  const auto ticks_to_full = [&](ForceSafety& dut) { return TicksToFull(dut, request); };
  {
    ForceSafety dut(config);
    ASSERT_EQ(ticks_to_full(dut), 2500);  // start-up: 0.5 s
    EXPECT_EQ(dut.Step(link, 0.005).force_W_N, Eigen::Vector3d::Zero());
    EXPECT_EQ(ticks_to_full(dut), 100) << "resumed over 20 ms";
    // back-to-back interruptions during the resume ramp keep it short
    EXPECT_EQ(dut.Step(link, 0.005).force_W_N, Eigen::Vector3d::Zero());
    for (int k = 0; k < 50; ++k) dut.Step(Request(request), kTick_s);
    EXPECT_EQ(dut.Step(link, 0.005).force_W_N, Eigen::Vector3d::Zero());
    EXPECT_EQ(ticks_to_full(dut), 100);
    // an interruption longer than resume_within_s ramps in over the start-up ramp
    for (int k = 0; k < 300; ++k) dut.Step(link, kTick_s);  // 60 ms
    EXPECT_EQ(ticks_to_full(dut), 2500);
    // any other forced zero too
    SafetyInput off = Request(request);
    off.output_allowed = false;
    dut.Step(off, kTick_s);
    EXPECT_EQ(ticks_to_full(dut), 2500);
  }
  {
    // an interruption during the start-up ramp restarts the start-up ramp
    ForceSafety dut(config);
    for (int k = 0; k < 1000; ++k) dut.Step(Request(request), kTick_s);
    dut.Step(link, 0.005);
    EXPECT_EQ(ticks_to_full(dut), 2500);
  }
  config.resume_ramp_s = -1.0;
  EXPECT_THROW(ForceSafety{config}, std::invalid_argument);
}

// Models that fall silent while output is allowed (a paused host: local_contact or the whole VM
// stopped for 20 ms or more) zero the force by the watchdog; when fresh models come back within
// resume_within_s, the force resumes over resume_ramp_s too. Over the half-second start-up ramp a
// user squeezing 5 N closed the fingers through the fabric (mock pinch runs on a loaded host).
TEST(ForceSafetyTest, ModelsBackAfterABriefSilenceResumeOverResumeRamp) {
  ForceSafetyConfig config;
  config.startup_ramp_s = 0.5;
  config.resume_ramp_s = 0.02;
  config.resume_within_s = 0.05;
  const Eigen::Vector3d request(5.0, 0.0, 0.0);
  const auto ticks_to_full = [&](ForceSafety& dut) { return TicksToFull(dut, request); };
  // the models fall silent for `silence_s` (age growing tick by tick), then a fresh one arrives
  const auto silence = [&](ForceSafety& dut, double silence_s) {
    for (int k = 1; k * kTick_s <= silence_s + 1e-9; ++k) {
      SafetyInput in = Request(request);
      in.model_age_s = k * kTick_s;
      dut.Step(in, kTick_s);
    }
  };
  ForceSafety dut(config);
  ASSERT_EQ(ticks_to_full(dut), 2500);
  silence(dut, 0.030);  // zero from 20 ms on
  EXPECT_EQ(dut.last_force_W_N(), Eigen::Vector3d::Zero());
  EXPECT_GT(dut.counters().watchdog_zero_steps, 0u);
  EXPECT_EQ(ticks_to_full(dut), 100) << "resumed over 20 ms";
  // zero for longer than resume_within_s: the start-up ramp
  silence(dut, 0.020 + 0.060);
  EXPECT_EQ(ticks_to_full(dut), 2500);
  // a silence while the device was held (output not allowed, not for the link) is no brief cause
  silence(dut, 0.025);
  SafetyInput held = Request(request);
  held.output_allowed = false;
  dut.Step(held, kTick_s);
  EXPECT_EQ(ticks_to_full(dut), 2500);
  // a silence during the start-up ramp restarts the start-up ramp
  ForceSafety ramping(config);
  for (int k = 0; k < 1000; ++k) ramping.Step(Request(request), kTick_s);
  silence(ramping, 0.030);
  EXPECT_EQ(ticks_to_full(ramping), 2500);
}

// The resume ramp assumes the user still holds the finger where it had force. A finger that moved
// farther than resume_within_m meanwhile (the models stalled while the squeeze went on, and the
// fingers closed onto each other) ramps in over the start-up ramp, whatever the cause: the model
// would answer the new place at once with a force the hand never felt build up.
TEST(ForceSafetyTest, AFingerThatMovedAwayDuringAnInterruptionRampsInFromTheStart) {
  ForceSafetyConfig config;
  config.startup_ramp_s = 0.5;
  config.resume_ramp_s = 0.02;
  config.resume_within_m = 0.002;
  const Eigen::Vector3d request(5.0, 0.0, 0.0);
  const Eigen::Vector3d held_W_m(0.01, 0.0, 0.0);
  const auto at = [&](const Eigen::Vector3d& p_W_m) {
    SafetyInput in = Request(request);
    in.p_W_m = p_W_m;
    return in;
  };
  const auto ticks_to_full = [&](ForceSafety& dut, const Eigen::Vector3d& p_W_m) {
    for (int k = 1; k <= 5000; ++k) {
      if (dut.Step(at(p_W_m), kTick_s).force_W_N.x() >= 5.0 - 1e-6) return k;
    }
    return -1;
  };
  // 30 ms of silent models, the finger moving from `held_W_m` by `move_m` along y meanwhile
  const auto silence_moving = [&](ForceSafety& dut, double move_m) -> Eigen::Vector3d {
    for (int k = 1; k <= 150; ++k) {
      SafetyInput in = at(held_W_m + Eigen::Vector3d(0.0, move_m * k / 150.0, 0.0));
      in.model_age_s = k * kTick_s;
      dut.Step(in, kTick_s);
    }
    return held_W_m + Eigen::Vector3d(0.0, move_m, 0.0);
  };
  ForceSafety dut(config);
  ASSERT_EQ(ticks_to_full(dut, held_W_m), 2500);
  EXPECT_EQ(ticks_to_full(dut, silence_moving(dut, 0.001)), 100) << "1 mm: still held, resumed over 20 ms";
  ASSERT_EQ(ticks_to_full(dut, held_W_m + Eigen::Vector3d(0.0, 0.001, 0.0)), 1);
  EXPECT_EQ(ticks_to_full(dut, silence_moving(dut, 0.004)), 2500) << "4 mm: moved away";
  // a link interruption too
  ASSERT_EQ(ticks_to_full(dut, held_W_m), 1);
  SafetyInput link = at(held_W_m + Eigen::Vector3d(0.0, 0.0, 0.003));
  link.output_allowed = false;
  link.link_interruption = true;
  dut.Step(link, 0.005);
  EXPECT_EQ(ticks_to_full(dut, link.p_W_m), 2500);
  // and a finger whose position is not finite never resumes early
  ASSERT_EQ(ticks_to_full(dut, link.p_W_m), 1);
  link.p_W_m.x() = std::numeric_limits<double>::quiet_NaN();
  dut.Step(link, 0.005);
  EXPECT_EQ(ticks_to_full(dut, held_W_m), 2500);
}

void ExpectConfigError(const ForceSafetyConfig& config, const std::string& field) {
  try {
    config.Validate();
    FAIL() << "expected std::invalid_argument for " << field;
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
  }
}

TEST(ForceSafetyTest, InvalidConfigsThrowWithClearMessages) {
  EXPECT_NO_THROW(ForceSafetyConfig{}.Validate());
  ForceSafetyConfig c;
  c.peak_force_N = 25.0;
  ExpectConfigError(c, "peak_force_N");
  c = {};
  c.continuous_force_N = 8.0;
  ExpectConfigError(c, "continuous_force_N");
  c = {};
  c.slew_N_per_tick = 0.0;
  ExpectConfigError(c, "slew_N_per_tick");
  c = {};
  c.stale_after_s = 0.015;
  ExpectConfigError(c, "stale_after_s + stale_ramp_s");
  c = {};
  c.continuous_window_s = std::numeric_limits<double>::quiet_NaN();
  ExpectConfigError(c, "continuous_window_s");
  EXPECT_THROW(ForceSafety{c}, std::invalid_argument);
  c = {};
  c.resume_within_m = -0.001;
  ExpectConfigError(c, "resume_within_m");
}

// At 20 kHz a step may move a quarter of what it may at 5 kHz (2.5 kN/s either way); one long
// step after a stall moves no more than one tick's 0.5 N.
TEST(ForceSafetyTest, SlewIsPerUnitOfTimeAndAtMostOneTicksWorthPerStep) {
  ForceSafetyConfig config;
  config.startup_ramp_s = 0.0;
  ForceSafety dut(config);
  const SafetyOutput fast = dut.Step(Request({5.0, 0.0, 0.0}), 5e-5);
  EXPECT_NEAR(fast.force_W_N.x(), 2500.0 * 5e-5, 1e-12);
  const SafetyOutput stalled = dut.Step(Request({5.0, 0.0, 0.0}), 0.008);
  EXPECT_NEAR(stalled.force_W_N.x(), 2500.0 * 5e-5 + config.slew_N_per_tick, 1e-12);
  ForceSafetyConfig bad;
  bad.slew_N_per_s = std::numeric_limits<double>::infinity();
  ExpectConfigError(bad, "slew_N_per_s");
}

}  // namespace
}  // namespace haptex::device
