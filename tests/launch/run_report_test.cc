// What recordings and the force log say, and plots that are skipped with a reason.
#include "launch/run_report.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "launch/run_folder.h"
#include "libs/device/force_log_row.h"
#include "tests/launch/hostile_names.h"
#include "tests/launch/launch_test_support.h"

namespace haptex::launch {
namespace {

using ::testing::HasSubstr;

TEST(LaunchRunReportTest, ForceLogStatsPerFinger) {
  const std::string path = testing::FreshDir("force_log") + "/f.csv";
  testing::WriteText(path,
                     std::string(device::kForceLogHeader) +
                         "\n"
                         "1000000000,3,4,0,0,0,0,0,0,1,0,0,0,0,17,0,0,0,0,0,0\n"
                         "1500000000,0,0,0,0,0,0,0,0,3,0,0,0,0,18,0,0,0,0,0,0\n"
                         "2000000000,0,0");  // cut by a kill: ignored
  const auto log = ReadForceLog(path);
  ASSERT_TRUE(log.has_value());
  ASSERT_EQ(log->t_s.size(), 2u);
  EXPECT_DOUBLE_EQ(log->t_s[1], 0.5);
  EXPECT_DOUBLE_EQ(log->stats[0].peak_n, 5.0);
  EXPECT_DOUBLE_EQ(log->stats[0].mean_n, 2.5);
  EXPECT_DOUBLE_EQ(log->stats[0].final_n, 0.0);
  EXPECT_DOUBLE_EQ(log->stats[1].peak_n, 3.0);
  EXPECT_EQ(log->dropouts, 1u) << "the thumb's 5 N cut to zero";
  EXPECT_FALSE(ReadForceLog(path + ".missing").has_value());
}

// A cut to zero is a dropout; a ramp down, or a cut from below 0.5 N (a light touch ending), is not.
TEST(LaunchRunReportTest, ForceDropoutsAreCutsToZeroFromAFeltForce) {
  const std::string path = testing::FreshDir("force_dropouts") + "/f.csv";
  std::string text = std::string(device::kForceLogHeader) + "\n";
  const double thumb_z_N[] = {2.0, 2.0, 0.0, 0.0, 1.0, 2.0, 1.5, 1.0, 0.6, 0.3, 0.0, 0.4, 0.0, 2.0, 0.0};
  for (int k = 0; k < 15; ++k) {
    text += std::to_string(1000000000 + k * 200000) + ",0,0," + std::to_string(thumb_z_N[k]) + ",0,0,0,0,0,1,0,0,0,0," +
            std::to_string(k + 1) + ",0,0,0,0,0,0\n";
  }
  testing::WriteText(path, text);
  const auto log = ReadForceLog(path);
  ASSERT_TRUE(log.has_value());
  EXPECT_EQ(log->dropouts, 2u);
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

// A recording from which every plot is drawn: a pinch (state VIII) with forces, normal forces,
// positions and a loop's Health.
Recording EveryPlotsData() {
  Recording r;
  for (int k = 0; k < 20; ++k) {
    const std::int64_t t_ns = k * 10'000'000;
    v1::Envelope model;
    model.set_send_time_ns(t_ns);
    auto* m = model.mutable_force_model()->add_fingers();
    m->set_finger(v1::FINGER_THUMB);
    m->set_contact_state(v1::CONTACT_STATE_VIII);
    m->mutable_f0_w_n()->set_z(1.0 + 0.1 * k);
    r.envelopes.push_back(model);
    v1::Envelope touch;
    touch.set_send_time_ns(t_ns);
    auto* f = touch.mutable_touch_trace()->add_fingers();
    f->set_finger(v1::FINGER_THUMB);
    f->set_normal_force_n(1.0);
    f->set_tangential_force_n(0.3);
    f->set_friction_normal_force_n(1.0);
    f->set_friction_tangential_force_n(0.3);
    r.envelopes.push_back(touch);
    v1::Envelope states;
    states.set_send_time_ns(t_ns);
    auto* s = states.mutable_finger_states()->add_fingers();
    s->set_finger(v1::FINGER_THUMB);
    s->mutable_position_w_m()->set_x(0.001 * k);
    s->mutable_measured_force_w_n()->set_z(1.0 + 0.1 * k);
    r.envelopes.push_back(states);
  }
  v1::Envelope health;
  health.set_sender("device_bridge\n!touch x");
  auto* loop = health.mutable_health()->add_loops();
  loop->set_name("bridge\"\n!touch x");
  loop->set_period_p50_us(200);
  loop->set_period_p99_us(260);
  loop->set_period_max_us(900);
  r.envelopes.push_back(health);
  return r;
}

// Fig. 10 compares the loading with the tensile curve: the force the device measured on both
// fingers (not a ForceModel's F0, which is at the pose predicted for it), from the pinch until the
// elongation first comes within 2 % of its largest; not the hold after it, nor the run's end,
// where the device lets go of the force while the model still says pinched and the fingers spring on.
TEST(LaunchRunReportTest, TheStripFigureComparesTheLoadingTheDeviceMeasured) {
  constexpr double kWidth_m = 0.01, kRest_m = 0.05, kStiffness_N_per_m = 1000.0;  // the strip's pull per elongation
  Recording r;
  const auto add = [&r](int k, double elongation_m, double pull_N, double squeeze_N, double f0_N) {
    const std::int64_t t_ns = std::int64_t{k} * 25'000'000;  // apart by more than the 20 ms the force is averaged over
    v1::Envelope model;
    model.set_send_time_ns(t_ns);
    v1::Envelope states;
    states.set_send_time_ns(t_ns);
    for (const v1::Finger finger : {v1::FINGER_THUMB, v1::FINGER_INDEX}) {
      const double side = finger == v1::FINGER_THUMB ? 1.0 : -1.0;
      auto* m = model.mutable_force_model()->add_fingers();
      m->set_finger(finger);
      m->set_contact_state(v1::CONTACT_STATE_VIII);
      m->mutable_f0_w_n()->set_x(-f0_N / 2);
      auto* s = states.mutable_finger_states()->add_fingers();
      s->set_finger(finger);
      s->mutable_position_w_m()->set_x(kRest_m + elongation_m);
      s->mutable_position_w_m()->set_y(0.005 * side);
      s->mutable_measured_force_w_n()->set_x(-pull_N / 2);
      s->mutable_measured_force_w_n()->set_y(-squeeze_N * side);
    }
    r.envelopes.push_back(model);
    r.envelopes.push_back(states);
  };
  int k = 0;
  for (; k <= 100; ++k)
    add(k, 1e-5 * k, kStiffness_N_per_m * 1e-5 * k, 4.0, 5.0);  // the pull: on the curve (F0 is not)
  for (; k <= 200; ++k) add(k, 1e-3, 0.5, 4.0, 5.0);            // the hold: the strip relaxes
  for (; k <= 220; ++k) add(k, 2e-3, 0.0, 0.0, 5.0);            // the end: the device lets go
  FigureReference reference;
  reference.strip = ClampedStrip{0.0, kWidth_m, "warp",
                                 [](double strain) { return kStiffness_N_per_m * strain * kRest_m / kWidth_m; }};
  const std::string dir = testing::FreshDir("plots_strip");
  const auto plots = MakePlots(dir, testing::ShippedScene("pinch_strip"), {r}, std::nullopt, reference);
  ASSERT_EQ(plots[2].name, "force_vs_elongation");
  ASSERT_FALSE(plots[2].file.empty()) << plots[2].skipped;
  std::map<std::string, double> measured(plots[2].measured.begin(), plots[2].measured.end());
  EXPECT_NEAR(measured["rest_length_m"], kRest_m, 1e-12);
  EXPECT_NEAR(measured["max_elongation_m"], 0.98e-3, 1.01e-5) << "the loading ends within 2 % of the largest";
  EXPECT_LT(measured["rms_difference_N"], 1e-9) << "the device's force, on the curve; not the hold's nor F0";
  EXPECT_NEAR(measured["samples"], 99.0, 1.0) << "from the pinch to 0.98 mm";
}

// A run folder named by an attacker (as --out may be): its path never reaches a script as code.
TEST(LaunchRunReportTest, HostileRunFolderNamesNeverBecomeGnuplotCode) {
  const std::string base = testing::FreshDir("plots_hostile");
  const std::string marker = base + "/injected";
  for (const std::string& name : testing::HostileNames(marker)) {
    if (name.size() > 200 || name.find('/') != std::string::npos || name.empty() || name == "." || name == "..") {
      continue;  // not a folder name a file system takes (those go through the slug, below)
    }
    const std::string run_dir = base + "/" + name;
    std::filesystem::create_directories(run_dir);
    const auto plots = MakePlots(run_dir, testing::ShippedScene("demo"), {EveryPlotsData()}, std::nullopt);
    ASSERT_EQ(plots.size(), 4u);
    for (const PlotResult& p : plots) {
      EXPECT_EQ(p.file, run_dir + "/plots/" + p.name + ".png") << p.skipped;
      EXPECT_TRUE(std::filesystem::exists(p.file)) << p.name;
    }
    EXPECT_FALSE(std::filesystem::exists(marker)) << "gnuplot ran the folder's name";
  }
}

// The whole path of a default run folder: a hostile scene name becomes a slug, the folder is made
// inside runs/, and its plots create nothing else.
TEST(LaunchRunReportTest, HostileSceneNamesMakeNoFileOutsideTheRunFolder) {
  const std::string base = testing::FreshDir("plots_hostile_scene");
  const std::string runs = base + "/runs";
  const std::string marker = base + "/injected";
  for (const std::string& name : testing::HostileNames(marker)) {
    v1::Scene scene = testing::ShippedScene("demo");
    scene.set_name(name);
    const std::string run_dir = CreateUniqueRunFolder(runs, RunFolderStem(name, "20260101-120000", ""));
    EXPECT_EQ(std::filesystem::path(run_dir).parent_path(), std::filesystem::path(runs));
    const auto plots = MakePlots(run_dir, scene, {EveryPlotsData()}, std::nullopt);
    for (const PlotResult& p : plots) EXPECT_FALSE(p.file.empty()) << p.name << ": " << p.skipped;
  }
  EXPECT_FALSE(std::filesystem::exists(marker));
  std::size_t beside_runs = 0;
  for (const auto& entry : std::filesystem::directory_iterator(base)) beside_runs += entry.path() != runs;
  EXPECT_EQ(beside_runs, 0u);
}

}  // namespace
}  // namespace haptex::launch
