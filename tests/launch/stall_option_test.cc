// `--stall TARGET@AT:DURATION`: a service or all, each time with its unit, refused with the flag,
// the text and the fix; added to the scene's stalls and checked as the scene loader checks them.
#include "launch/stall_option.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <stdexcept>

#include "libs/scene/scene_loader.h"
#include "libs/scene/scene_stalls.h"
#include "tests/support/test_paths.h"

namespace haptex::launch {
namespace {

using P = v1::ServicePlacement;
using ::testing::HasSubstr;

std::string Refusal(const std::string& text) {
  try {
    ParseStallOption(text);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  ADD_FAILURE() << "accepted: " << text;
  return "";
}

// Two fingers on the mock controller: device_bridge, mock_grab, global_sim, local_contact.
v1::Scene PinchScene(const std::string& more = "") {
  const scene::FabricDatabase fabrics(haptex::testing::SourceDir() + "/tests/scene/testdata/fabrics");
  return scene::ParseScene(
             "name: \"pinch\"\nfabric { database_name: \"test_cotton\" }\n"
             "fingers { finger: FINGER_THUMB }\nfingers { finger: FINGER_INDEX }\ndevice { mock {} }\n" +
                 more,
             "t.textproto", fabrics)
      .scene;
}

std::string RunStallsRefusal(const v1::Scene& scene, const std::vector<std::string>& options) {
  try {
    RunStalls(scene, options);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  ADD_FAILURE() << "accepted";
  return "";
}

TEST(LaunchStallOptionTest, TheIssuesExamplesParse) {
  const v1::Stall one = ParseStallOption("local_contact@4.5s:30ms");
  EXPECT_EQ(one.service(), P::SERVICE_LOCAL_CONTACT);
  EXPECT_FALSE(one.all());
  EXPECT_EQ(one.at_s(), 4.5);
  EXPECT_EQ(one.duration_s(), 0.03);
  const v1::Stall all = ParseStallOption("all@4.5s:30ms");
  EXPECT_TRUE(all.all());
  EXPECT_EQ(all.service(), P::SERVICE_UNSPECIFIED);
  EXPECT_EQ(all.at_s(), 4.5);
  const v1::Stall bridge = ParseStallOption("device_bridge@4500ms:0.03s");
  EXPECT_EQ(bridge.service(), P::SERVICE_DEVICE_BRIDGE);
  EXPECT_EQ(bridge.at_s(), 4.5);
  EXPECT_EQ(bridge.duration_s(), 0.03);
}

TEST(LaunchStallOptionTest, EveryServiceAndTheEdgesOfTheRanges) {
  for (const char* service : {"device_bridge", "mock_grab", "mock_pins", "tactile", "global_sim", "local_contact"}) {
    EXPECT_EQ(scene::StallTarget(ParseStallOption(std::string(service) + "@1s:1s")), service);
  }
  EXPECT_EQ(ParseStallOption("global_sim@0s:10s").duration_s(), 10.0);
  EXPECT_EQ(ParseStallOption("global_sim@0ms:10000ms").duration_s(), 10.0);
  EXPECT_EQ(ParseStallOption("global_sim@1e3ms:1e-3s").at_s(), 1.0);
  EXPECT_EQ(ParseStallOption("global_sim@604800s:1ms").at_s(), scene::kMaxStallAt_s);
}

TEST(LaunchStallOptionTest, BadTextIsRefusedNamingTheFlagAndTheFix) {
  EXPECT_THAT(Refusal("local_contact"),
              HasSubstr("--stall 'local_contact': expected TARGET@AT:DURATION, e.g. local_contact@4.5s:30ms"));
  EXPECT_THAT(Refusal("local_contact@4.5s"), HasSubstr("expected TARGET@AT:DURATION"));
  EXPECT_THAT(Refusal("local_contact:4.5s@30ms"), HasSubstr("expected TARGET@AT:DURATION"));
  EXPECT_THAT(Refusal("@4.5s:30ms"), HasSubstr("expected TARGET@AT:DURATION"));
  EXPECT_THAT(Refusal("local_contact@:30ms"), HasSubstr("expected TARGET@AT:DURATION"));
  EXPECT_THAT(Refusal("local_contact@4.5s:"), HasSubstr("expected TARGET@AT:DURATION"));
  EXPECT_THAT(Refusal("local_contact@4.5s:30ms:1s"), HasSubstr("expected TARGET@AT:DURATION"));
  EXPECT_THAT(Refusal("local_contact@4.5s@5s:30ms"), HasSubstr("expected TARGET@AT:DURATION"));
  EXPECT_THAT(Refusal("contact@4.5s:30ms"),
              HasSubstr("--stall 'contact@4.5s:30ms': unknown service 'contact' (targets: all, device_bridge,"));
  EXPECT_THAT(Refusal("launcher@4.5s:30ms"), HasSubstr("unknown service 'launcher'"));
  EXPECT_THAT(Refusal("ALL@4.5s:30ms"), HasSubstr("unknown service 'ALL'"));
  EXPECT_THAT(Refusal("local_contact@4.5:30ms"), HasSubstr("AT '4.5' needs its unit, s or ms (e.g. 4.5s or 30ms)"));
  EXPECT_THAT(Refusal("local_contact@4.5s:30"), HasSubstr("DURATION '30' needs its unit, s or ms"));
  EXPECT_THAT(Refusal("local_contact@4.5min:30ms"), HasSubstr("AT '4.5min' needs its unit"));
  EXPECT_THAT(Refusal("local_contact@4.5 s:30ms"), HasSubstr("AT: '4.5 ' is not a number"));
  EXPECT_THAT(Refusal("local_contact@soons:30ms"), HasSubstr("AT: 'soon' is not a number"));
  EXPECT_THAT(Refusal("local_contact@ms:30ms"), HasSubstr("AT: '' is not a number"));
  EXPECT_THAT(Refusal("local_contact@+1s:30ms"), HasSubstr("AT: '+1' is not a number"));
  EXPECT_THAT(Refusal("local_contact@0x10s:30ms"), HasSubstr("AT: '0x10' is not a number"));
  EXPECT_THAT(Refusal("local_contact@1s:1e999ms"), HasSubstr("DURATION: '1e999' is beyond the range of a number"));
}

TEST(LaunchStallOptionTest, HostileAndOutOfRangeTimesGetTheScenesWords) {
  EXPECT_THAT(Refusal("local_contact@nans:30ms"), HasSubstr("at_s must be a finite number, got nan"));
  EXPECT_THAT(Refusal("local_contact@infs:30ms"), HasSubstr("at_s must be a finite number, got inf"));
  EXPECT_THAT(Refusal("local_contact@1s:-infms"), HasSubstr("duration_s must be a finite number, got -inf"));
  EXPECT_THAT(Refusal("local_contact@-1s:30ms"),
              HasSubstr("at_s must be in [0, 604800] s from the run's start (force enabled), got -1"));
  EXPECT_THAT(Refusal("local_contact@1e300s:30ms"), HasSubstr("at_s must be in [0, 604800] s"));
  EXPECT_THAT(Refusal("local_contact@1s:0ms"), HasSubstr("duration_s must be in (0, 10] s, got 0"));
  EXPECT_THAT(Refusal("local_contact@1s:-0s"), HasSubstr("duration_s must be in (0, 10] s, got -0"));
  EXPECT_THAT(Refusal("local_contact@1s:10001ms"), HasSubstr("duration_s must be in (0, 10] s, got 10.001"));
  // every problem at once
  const std::string both = Refusal("local_contact@-1s:11s");
  EXPECT_THAT(both, HasSubstr("at_s must be"));
  EXPECT_THAT(both, HasSubstr("duration_s must be"));
}

TEST(LaunchStallOptionTest, TheTextFormReadsBackAsTheSameStall) {
  for (const char* text : {"local_contact@1.5s:0.1s", "all@2s:0.03s", "mock_grab@0s:10s", "tactile@0.1s:1e-05s"}) {
    const v1::Stall stall = ParseStallOption(text);
    EXPECT_EQ(StallText(stall), text);
    EXPECT_EQ(ParseStallOption(StallText(stall)).SerializeAsString(), stall.SerializeAsString()) << text;
  }
  EXPECT_EQ(StallText(ParseStallOption("device_bridge@4500ms:30ms")), "device_bridge@4.5s:0.03s");
}

TEST(LaunchStallOptionTest, StallsAddToTheScenesInOrder) {
  const v1::Scene scene = PinchScene("stalls { service: SERVICE_GLOBAL_SIM at_s: 1 duration_s: 0.5 }\n");
  const std::vector<PlannedStall> stalls = RunStalls(scene, {"local_contact@1.5s:100ms", "all@2s:30ms"});
  ASSERT_EQ(stalls.size(), 3u);
  EXPECT_EQ(stalls[0].source, "scene");
  EXPECT_EQ(StallText(stalls[0].stall), "global_sim@1s:0.5s");
  EXPECT_EQ(stalls[1].source, "--stall");
  EXPECT_EQ(StallText(stalls[1].stall), "local_contact@1.5s:0.1s");
  EXPECT_EQ(StallText(stalls[2].stall), "all@2s:0.03s");
  EXPECT_TRUE(RunStalls(PinchScene(), {}).empty());
}

TEST(LaunchStallOptionTest, StallsTheSceneCannotTakeAreRefusedNamingTheFlag) {
  EXPECT_THAT(RunStallsRefusal(PinchScene(), {"tactile@1s:30ms"}),
              HasSubstr("--stall 'tactile@1s:30ms': the scene does not run tactile (tactile display off)"));
  EXPECT_THAT(RunStallsRefusal(PinchScene("viewer { enabled: true }\n"), {"viewer@1s:30ms"}),
              HasSubstr("--stall 'viewer@1s:30ms': the viewer only shows the run"));
  // overlapping the scene's, or an earlier --stall, of one process (all pauses every one)
  EXPECT_THAT(RunStallsRefusal(PinchScene("stalls { service: SERVICE_GLOBAL_SIM at_s: 1 duration_s: 0.5 }\n"),
                               {"global_sim@1.2s:1s"}),
              HasSubstr("--stall 'global_sim@1.2s:1s': overlaps the scene's stall global_sim@1s:0.5s: stalls that "
                        "pause one process (all pauses every one) must not overlap"));
  EXPECT_THAT(RunStallsRefusal(PinchScene(), {"local_contact@1.5s:100ms", "all@1.55s:30ms"}),
              HasSubstr("--stall 'all@1.55s:30ms': overlaps --stall 'local_contact@1.5s:100ms'"));
  EXPECT_NO_THROW(RunStalls(PinchScene(), {"local_contact@1.5s:100ms", "all@1.6s:30ms", "device_bridge@1.5s:100ms"}));
  // at most 32 in all
  std::string scene_stalls;
  for (int i = 0; i < scene::kMaxStalls; ++i) {
    scene_stalls += "stalls { service: SERVICE_GLOBAL_SIM at_s: " + std::to_string(i) + " duration_s: 0.5 }\n";
  }
  EXPECT_THAT(RunStallsRefusal(PinchScene(scene_stalls), {"local_contact@100s:1s"}),
              HasSubstr("--stall 'local_contact@100s:1s': at most 32 stalls per run (the scene has 32)"));
}

}  // namespace
}  // namespace haptex::launch
