// Reading back what `haptex relay --json` writes: the writer itself (cli/relay_report.h) makes
// the reports, so the reader follows the format wherever it goes.
#include "launch/relay_report_reader.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "cli/relay_report.h"
#include "libs/netsim/impairment_model.h"

namespace haptex::launch {
namespace {

using ::testing::HasSubstr;

cli::RelayReport Report() {
  cli::RelayReport report;
  report.listen = "127.0.0.1:7000";
  report.to = "127.0.0.1:7001";
  report.duration_s = 2.5;
  netsim::ImpairmentConfig config;
  config.loss = 0.5;
  config.duplicate = 0.3;
  netsim::ImpairmentModel model(config, 3);
  std::uint64_t copies = 0;
  for (int i = 0; i < 50; ++i) copies += model.Decide(i, 100).copies;
  for (std::uint64_t c = 0; c + 1 < copies; ++c) model.OnDelivered(0, 0, 20'000'000);
  model.OnUndelivered(netsim::DropCause::kSendFailed);
  report.forward.stats = model.stats();
  return report;
}

TEST(LaunchRelayReportReaderTest, CountsAndDelaysComeBackAsWritten) {
  const cli::RelayReport report = Report();
  const RelayResult r = ParseRelayReport(cli::RelayReportToJson(report));
  const netsim::ImpairmentStats& s = report.forward.stats;
  EXPECT_EQ(r.duration_s, 2.5);
  EXPECT_EQ(r.forward.received, 50u);
  EXPECT_EQ(r.forward.received, s.received);
  EXPECT_EQ(r.forward.forwarded, s.forwarded);
  EXPECT_EQ(r.forward.duplicated, s.duplicated);
  EXPECT_GT(r.forward.duplicated, 0u);
  EXPECT_EQ(r.forward.dropped_total, s.dropped.Total());
  EXPECT_EQ(r.forward.dropped.at("loss"), s.dropped.Get(netsim::DropCause::kLoss));
  EXPECT_EQ(r.forward.dropped.at("send_failed"), 1u);
  EXPECT_EQ(r.forward.forwarded + r.forward.dropped_total, r.forward.received + r.forward.duplicated);
  EXPECT_EQ(r.forward.in_flight, 0u);
  EXPECT_NEAR(r.forward.delay_p50_ms, 20.0, 0.5);
  EXPECT_NEAR(r.forward.delay_max_ms, 20.0, 0.5);
  EXPECT_EQ(r.back.received, 0u);
}

TEST(LaunchRelayReportReaderTest, BrokenReportsAreRefusedSayingWhat) {
  EXPECT_THROW(ParseRelayReport("not json"), std::runtime_error);
  try {
    ParseRelayReport(R"({"duration_s": 1, "forward": {"received": 3}})");
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("no forward.forwarded"));
  }
  try {
    ReadRelayReport(::testing::TempDir() + "/no_such_report.json");
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("no relay report"));
  }
}

}  // namespace
}  // namespace haptex::launch
