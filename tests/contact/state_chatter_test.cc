// Issue 5: "hysteresis so that states do not chatter". A contact whose evidence swings across the
// classifier's thresholds every few ticks keeps one state: a finger resting on fabric that bounces
// on it at 50 Hz (as hanging cloth does on a resting thumb), and a pinch that slides with its samples
// sticking and slipping in turn. Without the evidence filter (state_filter_s = 0) both chatter,
// which the tests check too, so they can fail.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include "libs/contact/patch_simulation.h"
#include "tests/contact/contact_test_util.h"

namespace haptex::contact {
namespace {

using V = Eigen::Vector3d;
constexpr double kPi = 3.14159265358979323846;

struct StateRuns {
  int changes = 0;  // after the settling time
  std::vector<ContactState> states;
};

void Count(const ContactOutput& out, bool settled, StateRuns* runs) {
  if (!runs->states.empty() && settled && out.state != runs->states.back()) ++runs->changes;
  runs->states.push_back(out.state);
}

// The thumb presses a taut patch 0.6 mm deep and vibrates along its normal at 50 Hz by
// +-0.8 mm: it leaves the fabric and comes back 50 times a second.
StateRuns VibratingFinger(double state_filter_s) {
  ContactOptions options;
  options.state_filter_s = state_filter_s;
  auto sim = testing::MakeFlatPatch(testing::DatabaseMaterial("wang2011_black_denim_11oz"), 0.03, 31, options,
                                    testing::LocalStep(), 0.01);
  const double r = options.thumb.radius_m + options.fabric_half_thickness_m;
  StateRuns runs;
  const double dt = sim->dt_s();
  for (int k = 1; k * dt <= 1.0; ++k) {
    const double t = k * dt;
    const double depth = std::min(1.0, t / 0.2) * 0.0006 + (t > 0.2 ? 0.0008 * std::sin(2 * kPi * 50 * t) : 0.0);
    const ContactOutput& out = sim->Tick({true, testing::PoseFacing(V(0, 0, r - depth), V(0, 0, -1), V::UnitX())}, {});
    Count(out, t > 0.3, &runs);
  }
  return runs;
}

TEST(StateChatterTest, FabricBouncingOnAFingerIsOneState) {
  const StateRuns unfiltered = VibratingFinger(0.0);
  const StateRuns filtered = VibratingFinger(ContactOptions{}.state_filter_s);
  std::printf("[chatter] vibrating finger: %d state changes unfiltered, %d filtered (0.7 s)\n", unfiltered.changes,
              filtered.changes);
  EXPECT_GE(unfiltered.changes, 30) << "the scenario no longer crosses the thresholds";
  EXPECT_LE(filtered.changes, 1);
  // On the fabric at the end: IV or V, not I.
  const ContactState last = filtered.states.back();
  EXPECT_TRUE(last == ContactState::kIV || last == ContactState::kV) << ToString(last);
}

// Thumb above, index below a taut patch: they close to a pinch 0.5 mm deep each, hold, then shake
// the pinch along +-y at 50 Hz by +-1 mm: its samples stick and slip in turn.
StateRuns ShakenPinch(double state_filter_s, int* ticks_with_slip) {
  ContactOptions options;
  options.state_filter_s = state_filter_s;
  auto sim = testing::MakeFlatPatch(testing::DatabaseMaterial("wang2011_black_denim_11oz"), 0.03, 31, options,
                                    testing::LocalStep(), 0.01);
  const double r = options.thumb.radius_m + options.fabric_half_thickness_m;
  const double squeeze_m = 0.0005, shake_m = 0.001, shake_start = 0.4, end = 1.1;
  const V above(0, 0, r + 0.003), below(0, 0, -r - 0.003);
  const V thumb_in(0, 0, r - squeeze_m), index_in(0, 0, -(r - squeeze_m));
  StateRuns runs;
  *ticks_with_slip = 0;
  const double dt = sim->dt_s();
  for (int k = 1; k * dt <= end; ++k) {
    const double t = k * dt;
    const V shift(0, t > shake_start ? shake_m * std::sin(2 * kPi * 50 * (t - shake_start)) : 0.0, 0);
    const V thumb = testing::Ramp(above, thumb_in, t, 0.0, 0.3) + shift;
    const V index = testing::Ramp(below, index_in, t, 0.0, 0.3) + shift;
    const ContactOutput& out = sim->Tick({true, testing::PoseFacing(thumb, V(0, 0, -1), V::UnitX())},
                                         {true, testing::PoseFacing(index, V(0, 0, 1), V::UnitX())});
    Count(out, t > shake_start, &runs);
    if (t > shake_start) *ticks_with_slip += out.evidence.slip_fraction > 0.0;
  }
  return runs;
}

TEST(StateChatterTest, PinchWhoseSamplesStickAndSlipInTurnIsOneState) {
  int slip_unfiltered = 0, slip_filtered = 0;
  const StateRuns unfiltered = ShakenPinch(0.0, &slip_unfiltered);
  const StateRuns filtered = ShakenPinch(ContactOptions{}.state_filter_s, &slip_filtered);
  std::printf(
      "[chatter] shaken pinch: %d state changes unfiltered, %d filtered (0.7 s; samples "
      "slid in %d ticks)\n",
      unfiltered.changes, filtered.changes, slip_filtered);
  EXPECT_GE(unfiltered.changes, 30) << "the scenario no longer crosses the thresholds";
  EXPECT_GT(slip_filtered, 100);
  EXPECT_LE(filtered.changes, 1);
  const ContactState last = filtered.states.back();
  EXPECT_TRUE(last == ContactState::kVIII || last == ContactState::kIX) << ToString(last);
}

}  // namespace
}  // namespace haptex::contact
