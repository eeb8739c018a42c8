// A scene's network section: impaired links checked at file:line:column (hostile values
// included), which services a scene runs and which pairs talk, and what each direction of a link
// does.
#include "libs/scene/scene_network.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <limits>

#include "libs/scene/scene_loader.h"
#include "tests/scene/scene_test_support.h"

namespace haptex::scene {
namespace {

using P = v1::ServicePlacement;
using ::testing::HasSubstr;

// Two fingers on the mock controller: bridge, mock controller, global_sim, local_contact.
constexpr char kPinch[] =
    "name: \"net\"\n"
    "fabric { database_name: \"test_cotton\" }\n"
    "fingers { finger: FINGER_THUMB }\n"
    "fingers { finger: FINGER_INDEX }\n"
    "device { mock {} }\n";

class SceneNetworkTest : public ::testing::Test {
 protected:
  SceneNetworkTest() : db_(testing::TestDataDir() + "/fabrics") {}

  v1::Scene Accepted(const std::string& network) {
    return ParseScene(std::string(kPinch) + network, "t.textproto", db_).scene;
  }
  std::vector<TextIssue> Refused(const std::string& network) {
    try {
      ParseScene(std::string(kPinch) + network, "t.textproto", db_);
    } catch (const TextProtoError& e) {
      return e.issues();
    }
    ADD_FAILURE() << "accepted:\n" << network;
    return {};
  }
  // The one issue of `network`, which starts on line 6 of the scene.
  TextIssue OnlyIssue(const std::string& network) {
    const auto issues = Refused(network);
    EXPECT_EQ(issues.size(), 1u) << network;
    return issues.empty() ? TextIssue{} : issues[0];
  }

  FabricDatabase db_;
};

TEST_F(SceneNetworkTest, ALinkLoadsAndResolvesPerDirection) {
  const v1::Scene scene = Accepted(R"(network {
  links { a: SERVICE_DEVICE_BRIDGE b: SERVICE_LOCAL_CONTACT rtt_ms: 100 jitter_ms: 5 loss: 0.05
          burst_loss { p: 0.01 r: 0.5 } seed: 7 back { loss: 0.1 jitter_distribution: "normal" seed: 3 } }
  links { a: SERVICE_GLOBAL_SIM b: SERVICE_LOCAL_CONTACT delay_ms: 20 forward { delay_ms: 5 } }
})");
  ASSERT_EQ(scene.network().links_size(), 2);
  const LinkDirections d = ResolveLink(scene.network().links(0));
  EXPECT_EQ(d.forward.delay_ms, 50.0);  // rtt_ms split evenly
  EXPECT_EQ(d.back.delay_ms, 50.0);
  EXPECT_EQ(d.forward.jitter_ms, 5.0);
  EXPECT_EQ(d.forward.jitter_distribution, netsim::JitterDistribution::kUniform);
  EXPECT_EQ(d.back.jitter_distribution, netsim::JitterDistribution::kNormal);
  EXPECT_EQ(d.forward.loss, 0.05);
  EXPECT_EQ(d.back.loss, 0.1);
  EXPECT_EQ(d.forward.burst.p_good_to_bad, 0.01);
  EXPECT_EQ(d.forward.burst.p_bad_to_good, 0.5);
  EXPECT_EQ(d.forward.burst.loss_bad, 1.0);  // the default of an unwritten optional
  EXPECT_EQ(d.back.burst.p_good_to_bad, 0.01);
  EXPECT_EQ(d.forward.reorder_delay_ms, netsim::ImpairmentConfig{}.reorder_delay_ms);
  EXPECT_EQ(d.forward_seed, 7u);
  EXPECT_EQ(d.back_seed, 3u);

  const LinkDirections g = ResolveLink(scene.network().links(1));
  EXPECT_EQ(g.forward.delay_ms, 5.0);
  EXPECT_EQ(g.back.delay_ms, 20.0);
  EXPECT_EQ(g.forward_seed, 1u);  // as `haptex relay` without --seed
  EXPECT_EQ(g.back_seed, 2u);
}

TEST_F(SceneNetworkTest, ABadValueIsLocatedAtItsField) {
  const TextIssue issue = OnlyIssue(
      "network {\n"
      "  links { a: SERVICE_DEVICE_BRIDGE b: SERVICE_LOCAL_CONTACT\n"
      "          loss: 1.5 }\n"
      "}\n");
  EXPECT_EQ(issue.line, 8);
  EXPECT_EQ(issue.column, 11);
  EXPECT_THAT(issue.message, HasSubstr("loss must be a probability within [0, 1], got 1.5"));
}

TEST_F(SceneNetworkTest, ADirectionsValueIsNamedAndLocatedInsideIt) {
  const TextIssue issue = OnlyIssue(
      "network { links { a: SERVICE_DEVICE_BRIDGE b: SERVICE_LOCAL_CONTACT\n"
      "  forward {\n"
      "    jitter_ms: -1 } } }\n");
  EXPECT_EQ(issue.line, 8);
  EXPECT_EQ(issue.column, 5);
  EXPECT_THAT(issue.message, HasSubstr("forward.jitter_ms must be within [0, 60000], got -1"));
}

TEST_F(SceneNetworkTest, HostileNumbersAreRefused) {
  for (const std::string value : {"nan", "inf", "-inf", "1e308", "-1e-300"}) {
    const auto issues = Refused("network { links { a: SERVICE_DEVICE_BRIDGE b: SERVICE_LOCAL_CONTACT rtt_ms: " + value +
                                " delay_ms: 0 } }\n");
    ASSERT_EQ(issues.size(), 1u) << value;
    EXPECT_EQ(issues[0].line, 6) << value;
    EXPECT_THAT(issues[0].message, HasSubstr("rtt_ms must be")) << value;
  }
  for (const std::string field : {"loss", "reorder", "duplicate", "forward { loss", "back { duplicate"}) {
    const bool nested = field.find('{') != std::string::npos;
    const auto issues = Refused("network { links { a: SERVICE_DEVICE_BRIDGE b: SERVICE_LOCAL_CONTACT " + field +
                                ": nan" + (nested ? " }" : "") + " } }\n");
    ASSERT_EQ(issues.size(), 1u) << field;
    EXPECT_THAT(issues[0].message, HasSubstr("must be a finite number, got nan")) << field;
  }
  EXPECT_THAT(
      OnlyIssue("network { links { a: SERVICE_DEVICE_BRIDGE b: SERVICE_LOCAL_CONTACT rate_kbps: 1e300 } }\n").message,
      HasSubstr("rate_kbps must be within"));
  EXPECT_THAT(
      OnlyIssue("network { links { a: SERVICE_DEVICE_BRIDGE b: SERVICE_LOCAL_CONTACT reorder_delay_ms: -5 } }\n")
          .message,
      HasSubstr("reorder_delay_ms must be within [0, 60000]"));
  EXPECT_THAT(OnlyIssue("network { links { a: SERVICE_DEVICE_BRIDGE b: SERVICE_LOCAL_CONTACT "
                        "burst_loss { p: 0.1 r: 0.5 loss_bad: 2 } } }\n")
                  .message,
              HasSubstr("burst_loss.loss_bad must be a probability within [0, 1], got 2"));
  // the largest seed is a seed (back wraps round, as `haptex relay --seed` does)
  const v1::Scene scene =
      Accepted("network { links { a: SERVICE_DEVICE_BRIDGE b: SERVICE_LOCAL_CONTACT seed: 18446744073709551615 } }\n");
  EXPECT_EQ(ResolveLink(scene.network().links(0)).forward_seed, std::numeric_limits<std::uint64_t>::max());
}

TEST_F(SceneNetworkTest, WordsAndCombinationsAreChecked) {
  EXPECT_THAT(
      OnlyIssue(
          "network { links { a: SERVICE_DEVICE_BRIDGE b: SERVICE_LOCAL_CONTACT jitter_distribution: \"cauchy\" } }\n")
          .message,
      HasSubstr("'uniform' or 'normal', got 'cauchy'"));
  const TextIssue both = OnlyIssue(
      "network { links { a: SERVICE_DEVICE_BRIDGE b: SERVICE_LOCAL_CONTACT\n"
      "  rtt_ms: 10 back { delay_ms: 3 } } }\n");
  EXPECT_EQ(both.line, 7);
  EXPECT_EQ(both.column, 3);
  EXPECT_THAT(both.message, HasSubstr("give one of them"));
  // a bad state that never ends, located at the burst (r was not written)
  const TextIssue burst = OnlyIssue(
      "network { links { a: SERVICE_DEVICE_BRIDGE b: SERVICE_LOCAL_CONTACT\n"
      "  burst_loss { p: 0.1 } } }\n");
  EXPECT_EQ(burst.line, 7);
  EXPECT_THAT(burst.message, HasSubstr("burst_loss.r must be > 0 when burst_loss.p > 0"));
}

TEST_F(SceneNetworkTest, EndsMustBeServicesTheSceneRunsThatTalk) {
  EXPECT_THAT(OnlyIssue("network { links { a: SERVICE_TACTILE b: SERVICE_LOCAL_CONTACT } }\n").message,
              HasSubstr("the scene does not run tactile (tactile display off)"));
  const TextIssue quiet = OnlyIssue(
      "network { links { a: SERVICE_GLOBAL_SIM\n"
      "  b: SERVICE_MOCK_GRAB } }\n");
  EXPECT_EQ(quiet.line, 7);
  EXPECT_EQ(quiet.column, 3);
  EXPECT_THAT(quiet.message, HasSubstr("global_sim and mock_grab exchange no datagrams"));
  EXPECT_THAT(quiet.message, HasSubstr("device_bridge-local_contact (FingerStates, ForceModels)"));
  EXPECT_THAT(OnlyIssue("network { links { a: SERVICE_LOCAL_CONTACT b: SERVICE_LOCAL_CONTACT } }\n").message,
              HasSubstr("two different services, got local_contact twice"));
  EXPECT_THAT(OnlyIssue("network { links { a: SERVICE_LAUNCHER b: SERVICE_DEVICE_BRIDGE } }\n").message,
              HasSubstr("launcher is not a service a link can join"));
  EXPECT_THAT(OnlyIssue("network { links { a: SERVICE_DEVICE_BRIDGE } }\n").message,
              HasSubstr("a link needs both ends: `b: SERVICE_...`"));
}

TEST_F(SceneNetworkTest, OneLinkPerPairInEitherOrder) {
  const TextIssue twice = OnlyIssue(
      "network {\n"
      "  links { a: SERVICE_DEVICE_BRIDGE b: SERVICE_LOCAL_CONTACT }\n"
      "  links { a: SERVICE_LOCAL_CONTACT b: SERVICE_DEVICE_BRIDGE loss: 0.1 }\n"
      "}\n");
  EXPECT_EQ(twice.line, 8);
  EXPECT_THAT(twice.message, HasSubstr("link local_contact-device_bridge is given twice (first on line 7)"));
}

TEST_F(SceneNetworkTest, EveryProblemIsReportedAtOnce) {
  const auto issues = Refused(
      "network {\n"
      "  links { a: SERVICE_DEVICE_BRIDGE b: SERVICE_LOCAL_CONTACT loss: -1 duplicate: 2 }\n"
      "  links { a: SERVICE_TACTILE b: SERVICE_MOCK_PINS }\n"
      "}\n");
  EXPECT_EQ(issues.size(), 4u);
}

TEST(SceneNetworkNamesTest, ServiceAndLinkNamesAreTheLaunchers) {
  EXPECT_EQ(ServiceName(P::SERVICE_DEVICE_BRIDGE), "device_bridge");
  EXPECT_EQ(ServiceName(P::SERVICE_MOCK_PINS), "mock_pins");
  v1::LinkImpairment link;
  link.set_a(P::SERVICE_LOCAL_CONTACT);
  link.set_b(P::SERVICE_GLOBAL_SIM);
  EXPECT_EQ(LinkName(link), "local_contact-global_sim");
  v1::LinkImpairment reversed;
  reversed.set_a(P::SERVICE_GLOBAL_SIM);
  reversed.set_b(P::SERVICE_LOCAL_CONTACT);
  EXPECT_TRUE(SamePair(link, reversed));
  EXPECT_TRUE(ExchangeDatagrams(P::SERVICE_MOCK_GRAB, P::SERVICE_DEVICE_BRIDGE));
  EXPECT_FALSE(ExchangeDatagrams(P::SERVICE_MOCK_GRAB, P::SERVICE_LOCAL_CONTACT));
}

TEST(SceneNetworkResolveTest, RefusesWhatTheChecksRefuse) {
  v1::LinkImpairment link;
  link.set_a(P::SERVICE_DEVICE_BRIDGE);
  link.set_b(P::SERVICE_LOCAL_CONTACT);
  EXPECT_TRUE(CheckLinkValues(link).empty());
  link.set_loss(std::numeric_limits<double>::quiet_NaN());
  EXPECT_THROW(ResolveLink(link), std::invalid_argument);
}

}  // namespace
}  // namespace haptex::scene
