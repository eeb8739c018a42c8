// The paper's section 6 figures from real runs of the scenes made for them (every service a real
// process over loopback): rub_friction's F_T/F_N breaks away at mu_s and slides at mu_d (Fig. 9),
// pinch_strip's force along the pull follows the fabric's tensile curve (Fig. 10), and the plots are
// in the run folder. Physics only, with stated tolerances; no timing.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <iostream>

#include "tests/launch/launch_test_support.h"
#include "tests/support/subprocess.h"
#include "tests/support/summary_json.h"

namespace haptex::launch {
namespace {

using namespace std::chrono_literals;
namespace pb = google::protobuf;
using haptex::testing::Number;
using haptex::testing::Object;
using haptex::testing::ParseJson;

// Runs a shipped scene for `duration_s` into a fresh folder; its summary.json.
pb::Struct RunScene(const std::string& scene, const std::string& duration_s, std::string* run_dir) {
  *run_dir = testing::FreshDir(scene) + "/run";
  haptex::testing::Subprocess launcher({haptex::testing::BuildDir() + "/cli/haptex", "launch",
                                        testing::ShippedScenePath(scene), "--duration", duration_s, "--out", *run_dir});
  const auto code = launcher.WaitFor(180s);
  EXPECT_EQ(code, std::optional<int>(0)) << launcher.Stdout() << launcher.Stderr();
  std::cout << launcher.Stdout();
  return ParseJson(testing::ReadText(*run_dir + "/summary.json"));
}

// Fig. 9: the stroke sticks, breaks away at mu_s and slides at mu_d; pulled by the user's spring
// the finger sticks and slips in turn (some 25 ms sticks) and the turn of the stroke sticks again.
// 5 s: approach and press (1.8 s), then a stroke out to 1 cm and back.
TEST(LaunchFiguresTest, RubFrictionSticksUpToMuStaticAndSlidesAtMuDynamic) {
  std::string run;
  const pb::Struct summary = RunScene("rub_friction", "5", &run);
  const pb::Struct& plot = Object(Object(summary, "plots"), "friction_ratio");
  EXPECT_TRUE(std::filesystem::exists(run + "/plots/friction_ratio.png"));
  const pb::Struct& m = Object(plot, "measured");
  const double mu_s = Number(m, "mu_s"), mu_d = Number(m, "mu_d");
  EXPECT_EQ(mu_s, 0.4);
  EXPECT_EQ(mu_d, 0.2);
  EXPECT_GE(Number(m, "breakaways"), 3.0) << "stick-slip: the finger sticks again while pulled";
  // The friction law's F^T/F^N (the paper's): every break-away at mu_s, sliding at mu_d.
  EXPECT_NEAR(Number(m, "stick_peak_min"), mu_s, 0.01 * mu_s);
  EXPECT_NEAR(Number(m, "stick_peak_max"), mu_s, 0.01 * mu_s);
  EXPECT_GT(Number(m, "slide_samples"), 200.0) << "slides long enough to have a plateau";
  EXPECT_NEAR(Number(m, "slide_median"), mu_d, 0.02 * mu_d);
  // The device's force: the law decides on the load before the haptic step and the fabric under
  // the finger gives during it, so its break-aways peak lower (median 0.355-0.37, on a loaded host
  // too; the slow stroke of rub_friction_test.cc reaches 0.39) and it slides a little higher. A
  // single break-away's peak depends on the host: in a stall the finger moves several ticks' way
  // in one and the fabric answers that jump (0.30 and 0.49 seen beside a parallel ctest), so the
  // median of the break-aways is asserted; the first and the largest are reported.
  EXPECT_GE(Number(m, "device_breakaways"), 3.0);
  EXPECT_NEAR(Number(m, "device_stick_peak_median"), mu_s, 0.15 * mu_s);
  EXPECT_NEAR(Number(m, "device_slide_median"), mu_d, 0.1 * mu_d);
}

double LargestStrain(const pb::Struct& summary) {
  return Number(Object(Object(Object(summary, "plots"), "force_vs_elongation"), "measured"), "max_strain");
}

// Fig. 10: the clamped strip pinched and pulled slowly some 3 mm (6.5 % of its 46 mm): the pinch
// holds through the pull within the device's continuous force, and the force the device measured
// on the fingers follows the warp tensile curve times the strip's width over the loading: 6.4-7.0 %
// RMS of the curve's value at the largest elongation on a quiet host, up to 14 % where the host
// paused 60-70 times in the run (docs/validation.md); a figure gone wrong is 30 % or more.
TEST(LaunchFiguresTest, PinchedStripFollowsTheFabricsTensileCurve) {
  constexpr double kRmsPercentBound = 20.0;
  std::string run;
  pb::Struct summary = RunScene("pinch_strip", "10", &run);
  const auto rms_percent = [](const pb::Struct& s) {
    return Number(Object(Object(Object(s, "plots"), "force_vs_elongation"), "measured"), "rms_percent_of_peak");
  };
  std::cout << "[measured] largest strain " << LargestStrain(summary) << ", " << rms_percent(summary)
            << " % RMS from the curve\n";
  // A pause of the host can cut the force while the grip builds up; the resume then holds it to
  // max(1.1 x held, held + 0.3 N) for up to a second while the squeeze goes on (docs/stalls.md), by
  // design, and the figure is not the fabric's over that second. What holds whatever the host does
  // is asserted always; the figure's accuracy only in a run the bound did not hold down.
  const int limited_resumes =
      haptex::testing::ExpectResumesWithinTheirBound(haptex::testing::ServiceSummary(summary, "device_bridge"));
  EXPECT_TRUE(std::filesystem::exists(run + "/plots/force_vs_elongation.png"));
  const pb::Struct& m = Object(Object(Object(summary, "plots"), "force_vs_elongation"), "measured");
  EXPECT_NEAR(Number(m, "rest_length_m"), 0.046, 1e-6);
  EXPECT_NEAR(Number(m, "width_m"), 0.015, 1e-9);
  EXPECT_GT(Number(m, "max_strain"), 0.05) << "the pinch let the strip go before the pull was done";
  EXPECT_GT(Number(m, "samples"), 1000.0);
  EXPECT_GT(Number(Object(summary, "contact_states"), "VIII"), 2000.0) << "pinched (VIII) through the pull";
  if (limited_resumes > 0) {
    std::cout << "[measured] a cut during the grip: " << limited_resumes
              << " resumes held down by their bound; the figure's accuracy is not asserted in this run\n";
    return;
  }
  EXPECT_LT(Number(m, "rms_percent_of_peak"), kRmsPercentBound);
  EXPECT_THAT(testing::ReadText(run + "/summary.json"),
              ::testing::HasSubstr(R"("service":"device_bridge","counter":"continuous_limited_ticks","value":0})"))
      << "the scene's squeeze is within the device's continuous force";
}

}  // namespace
}  // namespace haptex::launch
