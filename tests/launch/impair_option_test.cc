// `--impair SERVICE-SERVICE:KEY=VALUE,...`: the scene's LinkImpairment fields as keys, refused
// with the flag, the text and the fix; and the text form printed back.
#include "launch/impair_option.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <limits>

namespace haptex::launch {
namespace {

using P = v1::ServicePlacement;
using ::testing::HasSubstr;

std::string Refusal(const std::string& text) {
  try {
    ParseImpairOption(text);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  ADD_FAILURE() << "accepted: " << text;
  return "";
}

TEST(LaunchImpairOptionTest, TheIssuesExampleParses) {
  const v1::LinkImpairment link = ParseImpairOption("device_bridge-local_contact:rtt_ms=100,jitter_ms=5,loss=0.05");
  EXPECT_EQ(link.a(), P::SERVICE_DEVICE_BRIDGE);
  EXPECT_EQ(link.b(), P::SERVICE_LOCAL_CONTACT);
  EXPECT_EQ(link.rtt_ms(), 100.0);
  EXPECT_EQ(link.jitter_ms(), 5.0);
  EXPECT_EQ(link.loss(), 0.05);
  EXPECT_FALSE(link.has_seed());
  EXPECT_FALSE(link.has_forward());
}

TEST(LaunchImpairOptionTest, EveryKeyAndBothDirections) {
  const v1::LinkImpairment link = ParseImpairOption(
      "local_contact-global_sim:delay_ms=3,jitter_distribution=normal,burst_loss=0.01/0.5/0.9/0.001,"
      "reorder=0.1,reorder_delay_ms=0,duplicate=0.2,rate_kbps=1000,seed=18446744073709551615,"
      "forward.delay_ms=7,forward.seed=0,back.loss=0.3,back.burst_loss=0.2/0.4,back.jitter_ms=1");
  EXPECT_EQ(link.a(), P::SERVICE_LOCAL_CONTACT);  // the order as typed: forward is a -> b
  EXPECT_EQ(link.delay_ms(), 3.0);
  EXPECT_EQ(link.jitter_distribution(), "normal");
  EXPECT_EQ(link.burst_loss().p(), 0.01);
  EXPECT_EQ(link.burst_loss().r(), 0.5);
  EXPECT_EQ(link.burst_loss().loss_bad(), 0.9);
  EXPECT_EQ(link.burst_loss().loss_good(), 0.001);
  EXPECT_TRUE(link.has_reorder_delay_ms());  // an explicit 0 is kept apart from "not given"
  EXPECT_EQ(link.reorder_delay_ms(), 0.0);
  EXPECT_EQ(link.seed(), std::numeric_limits<std::uint64_t>::max());
  EXPECT_EQ(link.forward().delay_ms(), 7.0);
  EXPECT_TRUE(link.forward().has_seed());
  EXPECT_EQ(link.forward().seed(), 0u);
  EXPECT_EQ(link.back().loss(), 0.3);
  EXPECT_FALSE(link.back().burst_loss().has_loss_bad());
  EXPECT_EQ(link.back().jitter_ms(), 1.0);
}

TEST(LaunchImpairOptionTest, ALinkWithoutValuesIsARelayThatOnlyMeasures) {
  for (const char* text : {"device_bridge-local_contact", "device_bridge-local_contact:"}) {
    const v1::LinkImpairment link = ParseImpairOption(text);
    EXPECT_EQ(ImpairmentText(link), "") << text;
  }
}

TEST(LaunchImpairOptionTest, BadTextIsRefusedNamingTheFlagAndTheFix) {
  EXPECT_THAT(Refusal("device_bridge"), HasSubstr("expected SERVICE-SERVICE[:KEY=VALUE,...]"));
  EXPECT_THAT(Refusal("device_bridge-local_contact-tactile"), HasSubstr("expected SERVICE-SERVICE"));
  EXPECT_THAT(
      Refusal("bridge-local_contact:loss=0.1"),
      HasSubstr("--impair 'bridge-local_contact:loss=0.1': unknown service 'bridge' (services: device_bridge,"));
  EXPECT_THAT(Refusal("device_bridge-local_contact:latency=3"),
              HasSubstr("unknown key 'latency' (keys: rtt_ms, delay_ms, jitter_ms, jitter_distribution, loss"));
  EXPECT_THAT(Refusal("device_bridge-local_contact:sideways.loss=3"), HasSubstr("unknown key 'sideways.loss'"));
  EXPECT_THAT(Refusal("device_bridge-local_contact:forward.rtt_ms=3"), HasSubstr("unknown key 'forward.rtt_ms'"));
  EXPECT_THAT(Refusal("device_bridge-local_contact:a=2"), HasSubstr("unknown key 'a'"));
  EXPECT_THAT(Refusal("device_bridge-local_contact:forward=2"), HasSubstr("unknown key 'forward'"));
  EXPECT_THAT(Refusal("device_bridge-local_contact:loss"), HasSubstr("expected KEY=VALUE, got 'loss'"));
  EXPECT_THAT(Refusal("device_bridge-local_contact:loss=0.1,,seed=2"), HasSubstr("expected KEY=VALUE, got ''"));
  EXPECT_THAT(Refusal("device_bridge-local_contact:=3"), HasSubstr("expected KEY=VALUE"));
  EXPECT_THAT(Refusal("device_bridge-local_contact:loss="), HasSubstr("loss needs a value"));
  EXPECT_THAT(Refusal("device_bridge-local_contact:loss=0.1,loss=0.2"), HasSubstr("loss is given twice"));
  EXPECT_THAT(Refusal("device_bridge-local_contact:loss=lots"), HasSubstr("loss: 'lots' is not a number"));
  EXPECT_THAT(Refusal("device_bridge-local_contact:loss=0.1x"), HasSubstr("'0.1x' is not a number"));
  EXPECT_THAT(Refusal("device_bridge-local_contact:seed=1.5"), HasSubstr("seed: '1.5' is not a whole number"));
  EXPECT_THAT(Refusal("device_bridge-local_contact:seed=-1"), HasSubstr("is not a whole number"));
  EXPECT_THAT(Refusal("device_bridge-local_contact:burst_loss=0.1"), HasSubstr("expected P/R[/LOSS_BAD[/LOSS_GOOD]]"));
  EXPECT_THAT(Refusal("device_bridge-local_contact:burst_loss=0.1/0.2/0.3/0.4/0.5"), HasSubstr("expected P/R"));
}

TEST(LaunchImpairOptionTest, HostileValuesGetTheRelaysWords) {
  EXPECT_THAT(Refusal("device_bridge-local_contact:loss=nan"), HasSubstr("loss must be a finite number, got nan"));
  EXPECT_THAT(Refusal("device_bridge-local_contact:rtt_ms=inf"), HasSubstr("rtt_ms must be a finite number"));
  EXPECT_THAT(Refusal("device_bridge-local_contact:forward.delay_ms=-infinity"),
              HasSubstr("forward.delay_ms must be a finite number"));
  EXPECT_THAT(Refusal("device_bridge-local_contact:loss=1.5"), HasSubstr("loss must be a probability within [0, 1]"));
  EXPECT_THAT(Refusal("device_bridge-local_contact:delay_ms=1e300"), HasSubstr("delay_ms must be within [0, 60000]"));
  EXPECT_THAT(Refusal("device_bridge-local_contact:rtt_ms=200000"), HasSubstr("rtt_ms must be within [0, 120000]"));
  EXPECT_THAT(Refusal("device_bridge-local_contact:jitter_ms=-0.5"), HasSubstr("jitter_ms must be within"));
  EXPECT_THAT(Refusal("device_bridge-local_contact:rate_kbps=-1"), HasSubstr("rate_kbps must be within"));
  EXPECT_THAT(Refusal("device_bridge-local_contact:burst_loss=0.5/0"),
              HasSubstr("burst_loss.r must be > 0 when burst_loss.p > 0"));
  EXPECT_THAT(Refusal("device_bridge-local_contact:back.burst_loss=nan/0.5"),
              HasSubstr("back.burst_loss.p must be a finite number"));
  EXPECT_THAT(Refusal("device_bridge-local_contact:jitter_distribution=pareto"),
              HasSubstr("'uniform' or 'normal', got 'pareto'"));
  EXPECT_THAT(Refusal("device_bridge-local_contact:rtt_ms=10,forward.delay_ms=3"), HasSubstr("give one of them"));
  // every problem at once
  const std::string both = Refusal("device_bridge-local_contact:loss=2,duplicate=-1");
  EXPECT_THAT(both, HasSubstr("loss must be"));
  EXPECT_THAT(both, HasSubstr("duplicate must be"));
}

TEST(LaunchImpairOptionTest, TheTextFormReadsBackAsTheSameLink) {
  const std::string text =
      "rtt_ms=20,jitter_ms=0.5,loss=0.02,burst_loss=0.01/0.5/0.9,reorder_delay_ms=0,seed=1,"
      "forward.loss=0.1,back.burst_loss=0.2/0.4,back.seed=3";
  const v1::LinkImpairment link = ParseImpairOption("device_bridge-local_contact:" + text);
  EXPECT_EQ(ImpairmentText(link), text);
  const v1::LinkImpairment again = ParseImpairOption("device_bridge-local_contact:" + ImpairmentText(link));
  EXPECT_EQ(again.SerializeAsString(), link.SerializeAsString());
}

TEST(LaunchImpairOptionTest, ExactNumbersReadBackBitForBit) {
  for (const double value : {0.1, 1e-5, 0.1234567891234, 60000.0, 5e-324, 0.0}) {
    EXPECT_EQ(std::strtod(ExactNumber(value).c_str(), nullptr), value)
        << ExactNumber(value);  // stod refuses subnormals
  }
  EXPECT_EQ(ExactNumber(10.0), "10");
  EXPECT_EQ(ExactNumber(0.02), "0.02");
}

}  // namespace
}  // namespace haptex::launch
