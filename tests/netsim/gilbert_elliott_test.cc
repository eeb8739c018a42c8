#include "libs/netsim/gilbert_elliott.h"

#include <gtest/gtest.h>

namespace haptex::netsim {
namespace {

TEST(GilbertElliottTest, DisabledByDefault) {
  GilbertElliott dut(GilbertElliottConfig{});
  EXPECT_FALSE(GilbertElliottConfig{}.enabled());
  for (int i = 0; i < 100; ++i) EXPECT_FALSE(dut.Step(0.0, 0.0));
  EXPECT_FALSE(dut.bad());
}

TEST(GilbertElliottTest, LosesInTheBadStateAndLeavesItWithProbabilityR) {
  GilbertElliottConfig config;
  config.p_good_to_bad = 0.5;
  config.p_bad_to_good = 0.5;
  GilbertElliott dut(config);
  // good: this datagram passes, the transition draw 0.4 < p moves the chain to bad
  EXPECT_FALSE(dut.Step(0.0, 0.4));
  EXPECT_TRUE(dut.bad());
  // bad: lost; 0.6 >= r keeps it bad
  EXPECT_TRUE(dut.Step(0.99, 0.6));
  EXPECT_TRUE(dut.bad());
  // bad: lost; 0.1 < r returns it to good
  EXPECT_TRUE(dut.Step(0.5, 0.1));
  EXPECT_FALSE(dut.bad());
  EXPECT_FALSE(dut.Step(0.0, 0.9));
}

TEST(GilbertElliottTest, StateLossProbabilitiesApply) {
  GilbertElliottConfig config;
  config.loss_good = 0.25;  // chain stays good (p = 0)
  GilbertElliott dut(config);
  EXPECT_TRUE(config.enabled());
  EXPECT_TRUE(dut.Step(0.2, 0.0));
  EXPECT_FALSE(dut.Step(0.3, 0.0));
}

}  // namespace
}  // namespace haptex::netsim
