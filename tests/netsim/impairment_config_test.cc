#include "libs/netsim/impairment_config.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <functional>
#include <limits>
#include <stdexcept>
#include <string>

#include "libs/netsim/impairment_model.h"

namespace haptex::netsim {
namespace {

using ::testing::HasSubstr;

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

std::string ValidationMessage(const std::function<void(ImpairmentConfig*)>& change) {
  ImpairmentConfig config;
  change(&config);
  try {
    Validate(config);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "valid";
}

TEST(ImpairmentConfigTest, DefaultsAreValidAndDoNothing) {
  const ImpairmentConfig config;
  EXPECT_NO_THROW(Validate(config));
  EXPECT_EQ(config.delay_ms, 0.0);
  EXPECT_EQ(config.loss, 0.0);
  EXPECT_FALSE(config.burst.enabled());
  EXPECT_EQ(config.rate_kbps, 0.0);
  EXPECT_EQ(config.max_datagram_bytes, 65507u);
}

TEST(ImpairmentConfigTest, EachBadParameterIsNamed) {
  EXPECT_THAT(ValidationMessage([](auto* c) { c->delay_ms = kNan; }), HasSubstr("delay_ms must be a finite number"));
  EXPECT_THAT(ValidationMessage([](auto* c) { c->delay_ms = -1; }), HasSubstr("delay_ms must be within"));
  EXPECT_THAT(ValidationMessage([](auto* c) { c->delay_ms = 1e9; }), HasSubstr("delay_ms"));
  EXPECT_THAT(ValidationMessage([](auto* c) { c->jitter_ms = kInf; }), HasSubstr("jitter_ms"));
  EXPECT_THAT(ValidationMessage([](auto* c) { c->loss = 1.5; }), HasSubstr("loss must be a probability"));
  EXPECT_THAT(ValidationMessage([](auto* c) { c->loss = -0.01; }), HasSubstr("loss"));
  EXPECT_THAT(ValidationMessage([](auto* c) { c->burst.p_good_to_bad = kNan; }), HasSubstr("burst.p must"));
  EXPECT_THAT(ValidationMessage([](auto* c) { c->burst.p_bad_to_good = 2; }), HasSubstr("burst.r must"));
  EXPECT_THAT(ValidationMessage([](auto* c) { c->burst.loss_bad = -1; }), HasSubstr("burst.loss_bad"));
  EXPECT_THAT(ValidationMessage([](auto* c) { c->burst.loss_good = 1.1; }), HasSubstr("burst.loss_good"));
  EXPECT_THAT(ValidationMessage([](auto* c) { c->duplicate = kNan; }), HasSubstr("duplicate"));
  EXPECT_THAT(ValidationMessage([](auto* c) { c->reorder = 3; }), HasSubstr("reorder must"));
  EXPECT_THAT(ValidationMessage([](auto* c) { c->reorder_delay_ms = -5; }), HasSubstr("reorder_delay_ms"));
  EXPECT_THAT(ValidationMessage([](auto* c) { c->rate_kbps = -1; }), HasSubstr("rate_kbps"));
  EXPECT_THAT(ValidationMessage([](auto* c) { c->rate_kbps = kInf; }), HasSubstr("rate_kbps"));
  EXPECT_THAT(ValidationMessage([](auto* c) { c->outage_after_s = kNan; }), HasSubstr("outage_after_s"));
  EXPECT_THAT(ValidationMessage([](auto* c) { c->outage_s = -1; }), HasSubstr("outage_s"));
  EXPECT_THAT(ValidationMessage([](auto* c) { c->outage_s = 1e6; }), HasSubstr("outage_s"));
  EXPECT_THAT(ValidationMessage([](auto* c) { c->queue_bytes = 0; }), HasSubstr("queue_bytes"));
  EXPECT_THAT(ValidationMessage([](auto* c) { c->max_datagram_bytes = 0; }), HasSubstr("max_datagram_bytes"));
  EXPECT_THAT(ValidationMessage([](auto* c) { c->max_datagram_bytes = 70000; }), HasSubstr("max_datagram_bytes"));
}

TEST(ImpairmentConfigTest, BurstsThatNeverEndAreRefused) {
  EXPECT_THAT(ValidationMessage([](auto* c) {
                c->burst.p_good_to_bad = 0.1;
                c->burst.p_bad_to_good = 0.0;
              }),
              HasSubstr("burst.r must be > 0 when burst.p > 0"));
  // a chain that never enters the bad state may have r = 0
  EXPECT_EQ(ValidationMessage([](auto* c) { c->burst.p_bad_to_good = 0.0; }), "valid");
}

TEST(ImpairmentConfigTest, TheModelRefusesABadConfig) {
  ImpairmentConfig config;
  config.loss = kNan;
  EXPECT_THROW(ImpairmentModel(config, 1), std::invalid_argument);
}

TEST(ImpairmentConfigTest, JitterDistributionsByName) {
  EXPECT_EQ(ParseJitterDistribution("uniform"), JitterDistribution::kUniform);
  EXPECT_EQ(ParseJitterDistribution("normal"), JitterDistribution::kNormal);
  EXPECT_EQ(JitterDistributionName(JitterDistribution::kNormal), "normal");
  try {
    ParseJitterDistribution("cauchy");
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("'uniform' or 'normal', got 'cauchy'"));
  }
}

}  // namespace
}  // namespace haptex::netsim
