// The global link's round trip as global_sim measures it, and how much of the border velocity the
// local layer keeps for it.
#include "libs/dual_layer/global_link_delay.h"

#include <gtest/gtest.h>

namespace haptex::dual_layer {
namespace {

TEST(GlobalLinkDelayTest, CountsTheStepsFromCutToMerge) {
  GlobalLinkDelay delay;
  EXPECT_EQ(delay.round_trip_steps(), 0u);
  for (std::uint64_t step = 10; step < 20; ++step) delay.OnResultMerged(step, step - 3);
  EXPECT_EQ(delay.round_trip_steps(), 3u);
}

TEST(GlobalLinkDelayTest, ALateResultCountsAtOnceAndIsForgottenAfterTheWindow) {
  GlobalLinkDelay delay;
  std::uint64_t step = 100;
  for (int k = 0; k < GlobalLinkDelay::kWindow; ++k, ++step) delay.OnResultMerged(step, step);
  delay.OnResultMerged(step, step - 6);
  ++step;
  EXPECT_EQ(delay.round_trip_steps(), 6u);
  for (int k = 0; k < GlobalLinkDelay::kWindow - 1; ++k, ++step) delay.OnResultMerged(step, step);
  EXPECT_EQ(delay.round_trip_steps(), 6u);
  delay.OnResultMerged(step, step);
  EXPECT_EQ(delay.round_trip_steps(), 0u);
}

TEST(GlobalLinkDelayTest, AResultFromTheFutureIsNoMeasurement) {
  GlobalLinkDelay delay;
  delay.OnResultMerged(5, 1'000'000);
  EXPECT_EQ(delay.round_trip_steps(), 0u);
}

TEST(GlobalLinkDelayTest, BorderVelocityIsKeptInFullOnlyForAnImmediateLink) {
  EXPECT_DOUBLE_EQ(BorderVelocityWeight(0), 1.0);
  EXPECT_DOUBLE_EQ(BorderVelocityWeight(2), 0.5);
  EXPECT_DOUBLE_EQ(BorderVelocityWeight(4), 0.0);
  EXPECT_DOUBLE_EQ(BorderVelocityWeight(4'000'000'000u), 0.0);
}

}  // namespace
}  // namespace haptex::dual_layer
