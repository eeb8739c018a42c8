// What recordings and the force log say, and plots that are skipped with a reason.
#include "launch/run_report.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "tests/launch/launch_test_support.h"

namespace haptex::launch {
namespace {

using ::testing::HasSubstr;

TEST(LaunchRunReportTest, ForceLogStatsPerFinger) {
  const std::string path = testing::FreshDir("force_log") + "/f.csv";
  testing::WriteText(path,
                     "time_ns,tcx,tcy,tcz,tax,tay,taz,icx,icy,icz,iax,iay,iaz,host_timed_out,host_sequence\n"
                     "1000000000,3,4,0,0,0,0,0,0,1,0,0,0,0,17\n"
                     "1500000000,0,0,0,0,0,0,0,0,3,0,0,0,0,18\n"
                     "2000000000,0,0");  // cut by a kill: ignored
  const auto log = ReadForceLog(path);
  ASSERT_TRUE(log.has_value());
  ASSERT_EQ(log->t_s.size(), 2u);
  EXPECT_DOUBLE_EQ(log->t_s[1], 0.5);
  EXPECT_DOUBLE_EQ(log->stats[0].peak_n, 5.0);
  EXPECT_DOUBLE_EQ(log->stats[0].mean_n, 2.5);
  EXPECT_DOUBLE_EQ(log->stats[0].final_n, 0.0);
  EXPECT_DOUBLE_EQ(log->stats[1].peak_n, 3.0);
  EXPECT_FALSE(ReadForceLog(path + ".missing").has_value());
}

TEST(LaunchRunReportTest, ContactStatesAndModelForces) {
  Recording r;
  for (auto state : {v1::CONTACT_STATE_I, v1::CONTACT_STATE_VIII, v1::CONTACT_STATE_VIII}) {
    v1::Envelope e;
    auto* f = e.mutable_force_model()->add_fingers();
    f->set_finger(v1::FINGER_THUMB);
    f->set_contact_state(state);
    f->mutable_f0_w_n()->set_z(2);
    r.envelopes.push_back(e);
  }
  const RecordingAnalysis a = AnalyseRecordings({r});
  EXPECT_EQ(a.force_models, 3u);
  EXPECT_EQ(a.contact_states[1], 1u);
  EXPECT_EQ(a.contact_states[8], 2u);
  EXPECT_DOUBLE_EQ(a.model_forces.at("thumb").peak_n, 2.0);
  EXPECT_EQ(RomanState(8), "VIII");
}

TEST(LaunchRunReportTest, PlotsWithoutDataAreSkippedWithTheReason) {
  const std::string dir = testing::FreshDir("plots_empty");
  const auto plots = MakePlots(dir, testing::ShippedScene("rub_friction"), {}, std::nullopt);
  ASSERT_EQ(plots.size(), 4u);
  for (const PlotResult& p : plots) {
    EXPECT_TRUE(p.file.empty()) << p.name;
    EXPECT_FALSE(p.skipped.empty()) << p.name;
  }
  EXPECT_THAT(plots[2].skipped, HasSubstr("not a stretch scene"));
}

TEST(LaunchRunReportTest, LoopPeriodPlotFromHealth) {
  Recording r;
  v1::Envelope e;
  e.set_sender("device_bridge");
  auto* loop = e.mutable_health()->add_loops();
  loop->set_name("device_bridge");
  loop->set_period_p50_us(200);
  loop->set_period_p99_us(260);
  loop->set_period_max_us(900);
  r.envelopes.push_back(e);
  const std::string dir = testing::FreshDir("plots_health");
  const auto plots = MakePlots(dir, testing::ShippedScene("demo"), {r}, std::nullopt);
  EXPECT_EQ(plots[3].name, "loop_periods");
  EXPECT_EQ(plots[3].file, dir + "/plots/loop_periods.png") << plots[3].skipped;
  EXPECT_TRUE(std::filesystem::exists(dir + "/plots/loop_periods.png"));
}

}  // namespace
}  // namespace haptex::launch
