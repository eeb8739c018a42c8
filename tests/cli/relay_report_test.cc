#include "cli/relay_report.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <regex>
#include <string>

#include "libs/netsim/impairment_model.h"

namespace haptex::cli {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

RelayReport SampleReport() {
  RelayReport report;
  report.listen = "127.0.0.1:7000";
  report.upstream = "0.0.0.0:40000";
  report.to = "127.0.0.1:7001";
  report.duration_s = 2.5;
  report.forward.config.delay_ms = 20;
  report.forward.config.loss = 0.25;
  report.forward.seed = 5;
  // four datagrams: one lost, one delivered 20 ms later, one sent late, one held at stop
  netsim::ImpairmentConfig config;
  config.loss = 0.5;
  netsim::ImpairmentModel model(config, 3);
  int kept = 0;
  for (int i = 0; kept < 3; ++i) kept += model.Decide(i, 100).copies;
  model.OnDelivered(0, 0, 20'000'000);
  model.OnUndelivered(netsim::DropCause::kSendFailed);
  model.OnUndelivered(netsim::DropCause::kUnsentAtStop);
  report.forward.stats = model.stats();
  report.back.seed = 6;
  return report;
}

TEST(RelayReportTest, TextHasOneLinePerDirectionWithCausesAndDelays) {
  const RelayReport report = SampleReport();
  const std::string text = RelayReportToText(report);
  EXPECT_THAT(text, HasSubstr("relay ran 2.500 s: listen 127.0.0.1:7000, upstream 0.0.0.0:40000, to "
                              "127.0.0.1:7001, back to the last client"));
  const std::uint64_t lost = report.forward.stats.dropped.Get(netsim::DropCause::kLoss);
  EXPECT_THAT(text, HasSubstr("forward: received " + std::to_string(report.forward.stats.received) +
                              ", forwarded 1, duplicated 0, reordered 0 (held back 0), dropped " +
                              std::to_string(lost + 2) + " (loss " + std::to_string(lost) +
                              ", send_failed 1, unsent_at_stop 1); delay ms p50 20.000 p99 20.000 max 20.000"));
  EXPECT_THAT(text, HasSubstr("back: received 0, forwarded 0, duplicated 0, reordered 0 (held back 0), "
                              "dropped 0; delay ms"));
}

TEST(RelayReportTest, JsonHasConfigCountsAndDelaysPerDirection) {
  const RelayReport report = SampleReport();
  const std::string json = RelayReportToJson(report);
  EXPECT_EQ(json.front(), '{');
  EXPECT_EQ(json.back(), '}');
  EXPECT_THAT(json, HasSubstr("\"back_to\":\"last client\""));
  EXPECT_THAT(json, HasSubstr("\"duration_s\":2.5"));
  const std::size_t forward = json.find("\"forward\":{");
  const std::size_t back = json.find("\"back\":{");
  ASSERT_NE(forward, std::string::npos);
  ASSERT_NE(back, std::string::npos);
  const std::string f = json.substr(forward, back - forward);
  EXPECT_THAT(f, HasSubstr("\"config\":{\"delay_ms\":20,\"jitter_ms\":0,\"jitter_dist\":\"uniform\",\"loss\":0.25,"));
  EXPECT_THAT(f, HasSubstr("\"burst_loss\":{\"p\":0,\"r\":1,\"loss_bad\":1,\"loss_good\":0}"));
  EXPECT_THAT(f, HasSubstr("\"seed\":5"));
  EXPECT_THAT(f, HasSubstr("\"forwarded\":1,"));
  EXPECT_THAT(f, HasSubstr("\"send_failed\":1,\"no_destination\":0,\"unsent_at_stop\":1,\"outage\":0}"));
  EXPECT_THAT(f, HasSubstr("\"in_flight\":0"));
  EXPECT_THAT(f, HasSubstr("\"delay_ms\":{\"p50\":20,\"p99\":20,\"max\":20,\"mean\":20}"));
  const std::string b = json.substr(back);
  EXPECT_THAT(b, HasSubstr("\"seed\":6"));
  EXPECT_THAT(b, HasSubstr("\"received\":0"));
  EXPECT_THAT(json, Not(HasSubstr("nan")));
}

TEST(RelayReportTest, NamedBackToIsReported) {
  RelayReport report = SampleReport();
  report.back_to = "127.0.0.1:9000";
  EXPECT_THAT(RelayReportToJson(report), HasSubstr("\"back_to\":\"127.0.0.1:9000\""));
  EXPECT_THAT(RelayReportToText(report), HasSubstr("back to 127.0.0.1:9000"));
}

}  // namespace
}  // namespace haptex::cli
