#include "cli/netcheck_report.h"

#include <gtest/gtest.h>

namespace haptex::cli {
namespace {

TEST(ProbeRecorderTest, CountsLossDuplicatesReorderingAndPercentiles) {
  ProbeRecorder recorder(10);
  // probes 1..8 answered (5 before 4), 9 and 10 lost, 3 twice, one reply out of range
  for (std::uint64_t seq : {1, 2, 3, 5, 4, 6, 7, 8}) recorder.OnReply(seq, static_cast<std::int64_t>(seq) * 100000);
  recorder.OnReply(3, 1);
  recorder.OnReply(42, 1);
  NetcheckReport report;
  recorder.Summarise(10, LinkVerdictLimits{}, &report);
  EXPECT_EQ(report.sent, 10u);
  EXPECT_EQ(report.received, 8u);
  EXPECT_EQ(report.lost, 2u);
  EXPECT_DOUBLE_EQ(report.loss_fraction, 0.2);
  EXPECT_EQ(report.duplicates, 1u);
  EXPECT_EQ(report.reordered, 1u);
  EXPECT_EQ(report.rejected, 1u);
  EXPECT_DOUBLE_EQ(report.rtt_min_us, 100.0);
  EXPECT_DOUBLE_EQ(report.rtt_max_us, 800.0);
  EXPECT_DOUBLE_EQ(report.rtt_p50_us, 400.0);
  EXPECT_DOUBLE_EQ(report.rtt_mean_us, 450.0);
  EXPECT_DOUBLE_EQ(report.jitter_us, 100.0);  // consecutive probes differ by 100 us
}

TEST(ClassifyLinkTest, VerdictFollowsLatencyAndLoss) {
  const LinkVerdictLimits limits;
  NetcheckReport r;
  r.received = 100;
  r.rtt_p99_us = 150;
  r.loss_fraction = 0;
  ClassifyLink(limits, &r);
  EXPECT_EQ(r.verdict, "good");
  r.rtt_p99_us = 5000;
  ClassifyLink(limits, &r);
  EXPECT_EQ(r.verdict, "usable");
  r.rtt_p99_us = 150;
  r.loss_fraction = 0.05;
  ClassifyLink(limits, &r);
  EXPECT_EQ(r.verdict, "usable");
  // a campus or continental link: the haptic link renders through 100 ms
  r.rtt_p99_us = 100000;
  ClassifyLink(limits, &r);
  EXPECT_EQ(r.verdict, "usable");
  EXPECT_NE(r.advice.find("local_contact and global_sim there"), std::string::npos);
  r.rtt_p99_us = 150000;  // beyond the bridge's model age limit: only the global link may cross
  ClassifyLink(limits, &r);
  EXPECT_EQ(r.verdict, "global_only");
  EXPECT_NE(r.advice.find("remote_global"), std::string::npos);
  r.rtt_p99_us = 250000;  // beyond what was measured
  ClassifyLink(limits, &r);
  EXPECT_EQ(r.verdict, "poor");
  r.rtt_p99_us = 150;
  r.loss_fraction = 0.2;
  ClassifyLink(limits, &r);
  EXPECT_EQ(r.verdict, "poor");
  r.received = 0;
  ClassifyLink(limits, &r);
  EXPECT_EQ(r.verdict, "unreachable");
  EXPECT_NE(r.advice.find("session key"), std::string::npos);
}

TEST(ClassifyLinkTest, TheHapticLimitIsTheBridgesOwn) {
  // one source: the bridge's model age limit, less its recovery margin
  const device::DeviceBridgeConfig bridge;
  EXPECT_DOUBLE_EQ(LinkVerdictLimits{}.usable_p99_us, 1e6 * bridge.recover_fraction * bridge.max_model_age_s);
}

TEST(ReportToJsonTest, HasEveryFigure) {
  NetcheckReport r;
  r.target = "127.0.0.1:1";
  r.verdict = "good";
  const std::string json = ReportToJson(r);
  for (const char* key : {"\"sent\":", "\"lost\":", "\"reordered\":", "\"p99\":", "\"p99_9\":", "\"max\":",
                          "\"jitter_us\":", "\"verdict\":\"good\""}) {
    EXPECT_NE(json.find(key), std::string::npos) << key;
  }
}

}  // namespace
}  // namespace haptex::cli
