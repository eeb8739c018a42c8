#include "libs/contact/contact_state.h"

#include <limits>

#include <gtest/gtest.h>

namespace haptex::contact {
namespace {

ContactState C(bool thumb, bool index, bool touch, bool dynamic) { return Classify({thumb, index, touch, dynamic}); }

TEST(ContactStateTest, Table1) {
  EXPECT_EQ(C(false, false, false, false), ContactState::kI);
  EXPECT_EQ(C(false, false, false, true), ContactState::kI);
  EXPECT_EQ(C(false, false, true, false), ContactState::kII);
  EXPECT_EQ(C(false, false, true, true), ContactState::kIII);
  EXPECT_EQ(C(true, false, false, false), ContactState::kIV);
  EXPECT_EQ(C(false, true, false, true), ContactState::kV);
  EXPECT_EQ(C(true, true, false, false), ContactState::kVI);
  EXPECT_EQ(C(true, true, false, true), ContactState::kVII);
  EXPECT_EQ(C(true, true, true, false), ContactState::kVIII);
  EXPECT_EQ(C(true, true, true, true), ContactState::kIX);
  // The table's "-": one finger on textile while the fingers touch is named by the textile side.
  EXPECT_EQ(C(true, false, true, false), ContactState::kIV);
}

TEST(ContactStateTest, Names) {
  EXPECT_STREQ(ToString(ContactState::kI), "I");
  EXPECT_STREQ(ToString(ContactState::kIX), "IX");
}

TEST(ContactStateTest, HysteresisDoesNotChatter) {
  Hysteresis h(0.6, 0.4);
  EXPECT_FALSE(h.Update(0.5));
  EXPECT_TRUE(h.Update(0.61));
  EXPECT_TRUE(h.Update(0.5));  // inside the band: stays on
  EXPECT_TRUE(h.Update(0.41));
  EXPECT_FALSE(h.Update(0.39));
  EXPECT_FALSE(h.Update(0.59));  // inside the band: stays off
}

// A value that swings across both thresholds every 5 ticks (5 at 0.8, 5 at 0.2, at 1 kHz, like the
// slip share of a held pinch whose samples stick and slip in turn): the bare hysteresis flips with
// it; the filtered one (tau 10 ms) holds, since its ripple, (0.8 - 0.2) tanh(T / (4 tau)) = 0.15 for the
// period T = 10 ms, stays inside the band 0.4 .. 0.6.
TEST(ContactStateTest, FilteredHysteresisHoldsASwingingValue) {
  Hysteresis bare(0.6, 0.4);
  FilteredHysteresis filtered(0.6, 0.4, 0.01);
  int bare_flips = 0, filtered_flips = 0;
  bool bare_on = false, filtered_on = false;
  for (int k = 0; k < 1000; ++k) {
    const double value = (k / 5) % 2 == 0 ? 0.8 : 0.2;
    const bool b = bare.Update(value), f = filtered.Update(value, 0.001);
    if (k >= 100) {
      bare_flips += b != bare_on;
      filtered_flips += f != filtered_on;
    }
    bare_on = b, filtered_on = f;
  }
  EXPECT_EQ(bare_flips, 180);
  EXPECT_EQ(filtered_flips, 0);
  EXPECT_NEAR(filtered.filtered(), 0.5, 0.1);
}

// A clean step still switches, after tau ln((1 - 0) / (1 - 0.6)) = 9.2 ms for 0 -> 1 (tau 10 ms),
// and off again tau ln(1 / 0.4) = 9.2 ms after 1 -> 0; tau = 0 switches on the tick.
TEST(ContactStateTest, FilteredHysteresisFollowsAStepWithinItsTimeConstant) {
  FilteredHysteresis h(0.6, 0.4, 0.01);
  int on_after = -1;
  for (int k = 1; k <= 50 && on_after < 0; ++k) {
    if (h.Update(1.0, 0.001)) on_after = k;
  }
  EXPECT_EQ(on_after, 10);
  for (int k = 0; k < 100; ++k) h.Update(1.0, 0.001);
  int off_after = -1;
  for (int k = 1; k <= 50 && off_after < 0; ++k) {
    if (!h.Update(0.0, 0.001)) off_after = k;
  }
  EXPECT_EQ(off_after, 10);
  FilteredHysteresis none(0.6, 0.4, 0.0);
  EXPECT_TRUE(none.Update(0.61, 0.001));
  EXPECT_FALSE(none.Update(0.39, 0.001));
}

// The load's filter (Rise::kAtOnce): a contact is named on its first tick, kept through gaps of a
// bouncing contact, and released tau ln(peak / leave) after its last load.
TEST(ContactStateTest, PeakHoldNamesAtOnceAndReleasesAfterTheDecay) {
  FilteredHysteresis load(0.01, 0.005, 0.01, FilteredHysteresis::Rise::kAtOnce);
  EXPECT_FALSE(load.Update(0.009, 0.001));
  EXPECT_TRUE(load.Update(0.011, 0.001));  // the first tick above the threshold
  // 50 Hz bounce: 8 ticks at 0.05 N, 12 ticks at 0: held.
  for (int k = 0; k < 400; ++k) EXPECT_TRUE(load.Update((k % 20) < 8 ? 0.05 : 0.0, 0.001)) << k;
  for (int k = 0; k < 100; ++k) load.Update(0.1, 0.001);
  int off_after = -1;
  for (int k = 1; k <= 100 && off_after < 0; ++k) {
    if (!load.Update(0.0, 0.001)) off_after = k;
  }
  EXPECT_EQ(off_after, 30);  // 10 ms ln(0.1 / 0.005) = 29.96 ms
}

TEST(ContactStateTest, FilteredHysteresisSkipsNonFiniteValues) {
  FilteredHysteresis h(0.6, 0.4, 0.01);
  for (int k = 0; k < 100; ++k) h.Update(1.0, 0.001);
  const double before = h.filtered();
  EXPECT_TRUE(h.Update(std::numeric_limits<double>::quiet_NaN(), 0.001));
  EXPECT_TRUE(h.Update(std::numeric_limits<double>::infinity(), 0.001));
  EXPECT_EQ(h.filtered(), before);
  h.Reset();
  EXPECT_FALSE(h.on());
  EXPECT_EQ(h.filtered(), 0.0);
}

}  // namespace
}  // namespace haptex::contact
