// The run's impaired links: the scene's network section, --impair replacing a pair's link (either
// order) or adding one, and links the scene cannot carry refused.
#include "launch/impaired_links.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "tests/launch/launch_test_support.h"

namespace haptex::launch {
namespace {

using P = v1::ServicePlacement;
using ::testing::HasSubstr;

v1::Scene PinchWithNetwork() {
  return testing::SceneFromText(R"(
    name: "net" fabric { database_name: "wang2011_black_denim_11oz" }
    fingers { finger: FINGER_THUMB } fingers { finger: FINGER_INDEX } device { mock {} }
    network {
      links { a: SERVICE_DEVICE_BRIDGE b: SERVICE_LOCAL_CONTACT rtt_ms: 100 }
      links { a: SERVICE_GLOBAL_SIM b: SERVICE_LOCAL_CONTACT loss: 0.1 }
    })");
}

std::string Refusal(const v1::Scene& scene, const std::vector<std::string>& options) {
  try {
    ImpairedLinks(scene, options);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  ADD_FAILURE() << "accepted";
  return "";
}

TEST(LaunchImpairedLinksTest, TheScenesLinksWithoutOptions) {
  const auto links = ImpairedLinks(PinchWithNetwork(), {});
  ASSERT_EQ(links.size(), 2u);
  EXPECT_EQ(links[0].source, "scene");
  EXPECT_EQ(links[0].link.rtt_ms(), 100.0);
  EXPECT_EQ(links[1].link.a(), P::SERVICE_GLOBAL_SIM);
  EXPECT_TRUE(ImpairedLinks(testing::ShippedScene("pinch_stretch"), {}).empty());
}

TEST(LaunchImpairedLinksTest, ImpairReplacesThePairsLinkInEitherOrderAndAddsTheRest) {
  const auto links = ImpairedLinks(
      PinchWithNetwork(), {"local_contact-device_bridge:rtt_ms=20,loss=0.02", "device_bridge-mock_grab:jitter_ms=0.1"});
  ASSERT_EQ(links.size(), 3u);
  EXPECT_EQ(links[0].source, "--impair");  // in the scene's place
  EXPECT_EQ(links[0].link.a(), P::SERVICE_LOCAL_CONTACT);
  EXPECT_EQ(links[0].link.rtt_ms(), 20.0);
  EXPECT_EQ(links[0].link.loss(), 0.02);  // the whole link is replaced, not merged
  EXPECT_EQ(links[1].source, "scene");
  EXPECT_EQ(links[2].source, "--impair");
  EXPECT_EQ(links[2].link.b(), P::SERVICE_MOCK_GRAB);
  EXPECT_EQ(LinksOf(links).size(), 3u);
}

TEST(LaunchImpairedLinksTest, LinksTheSceneCannotCarryAreRefused) {
  const v1::Scene pinch = testing::ShippedScene("pinch_stretch");
  EXPECT_THAT(Refusal(pinch, {"local_contact-tactile:loss=0.1"}),
              HasSubstr("--impair 'local_contact-tactile:loss=0.1': the scene does not run tactile (tactile display "
                        "off)"));
  EXPECT_THAT(Refusal(testing::ShippedScene("hanging"), {"device_bridge-global_sim"}),
              HasSubstr("the scene does not run device_bridge (the scene has no fingers)"));
  EXPECT_THAT(Refusal(pinch, {"mock_grab-global_sim"}), HasSubstr("mock_grab and global_sim exchange no datagrams"));
  EXPECT_THAT(Refusal(pinch, {"global_sim-global_sim"}), HasSubstr("got global_sim twice"));
  EXPECT_THAT(Refusal(pinch, {"device_bridge-local_contact:loss=0.1", "local_contact-device_bridge:loss=0.2"}),
              HasSubstr("link local_contact-device_bridge is given twice; one --impair per pair of services"));
  EXPECT_THAT(Refusal(pinch, {"device_bridge-local_contact:loss=nan"}), HasSubstr("loss must be a finite number"));
}

}  // namespace
}  // namespace haptex::launch
