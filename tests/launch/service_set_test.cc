// "Model only what a scene requires": the service set of every shipped scene, with reasons.
#include "launch/service_set.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>

#include "libs/scene/scene_network.h"
#include "tests/launch/launch_test_support.h"

namespace haptex::launch {
namespace {

using P = v1::ServicePlacement;
using ::testing::ElementsAre;
using ::testing::HasSubstr;

std::vector<ServiceKind> Kinds(const std::vector<PlannedService>& services) {
  std::vector<ServiceKind> kinds;
  for (const auto& s : services) kinds.push_back(s.kind);
  return kinds;
}

std::string ReasonOf(const std::vector<PlannedService>& services, ServiceKind kind) {
  for (const auto& s : services) {
    if (s.kind == kind) return s.reason;
  }
  return "";
}

TEST(LaunchServiceSetTest, HangingIsGlobalSimAlone) {
  const auto services = DeriveServices(testing::ShippedScene("hanging"));
  EXPECT_THAT(Kinds(services), ElementsAre(P::SERVICE_GLOBAL_SIM));
  EXPECT_THAT(services[0].reason, HasSubstr("no fingers"));
  const auto omitted = OmittedServices(testing::ShippedScene("hanging"));
  EXPECT_THAT(ReasonOf(omitted, P::SERVICE_LOCAL_CONTACT), HasSubstr("no fingers"));
  EXPECT_THAT(ReasonOf(omitted, P::SERVICE_TACTILE), HasSubstr("tactile display off"));
}

TEST(LaunchServiceSetTest, OfflineValidationScenesNeedOnlyTheFabric) {
  for (const char* name : {"tensile_strip_denim", "tensile_strip_knit", "cantilever"}) {
    EXPECT_THAT(Kinds(DeriveServices(testing::ShippedScene(name))), ElementsAre(P::SERVICE_GLOBAL_SIM)) << name;
  }
}

TEST(LaunchServiceSetTest, DemoNeedsEverythingInStartOrder) {
  const auto services = DeriveServices(testing::ShippedScene("demo"));
  EXPECT_THAT(Kinds(services),
              ElementsAre(P::SERVICE_DEVICE_BRIDGE, P::SERVICE_MOCK_GRAB, P::SERVICE_MOCK_PINS, P::SERVICE_TACTILE,
                          P::SERVICE_GLOBAL_SIM, P::SERVICE_LOCAL_CONTACT, P::SERVICE_VIEWER));
  EXPECT_THAT(ReasonOf(services, P::SERVICE_LOCAL_CONTACT), HasSubstr("two fingers (thumb and index)"));
  EXPECT_THAT(ReasonOf(services, P::SERVICE_MOCK_GRAB), HasSubstr("KIND_DEMO"));
  EXPECT_THAT(ReasonOf(services, P::SERVICE_MOCK_PINS), HasSubstr("mock_display"));
  EXPECT_TRUE(OmittedServices(testing::ShippedScene("demo")).empty());
}

TEST(LaunchServiceSetTest, RubAndPinchHaveNoTactile) {
  for (const char* name : {"rub_friction", "pinch_stretch"}) {
    EXPECT_THAT(
        Kinds(DeriveServices(testing::ShippedScene(name))),
        ElementsAre(P::SERVICE_DEVICE_BRIDGE, P::SERVICE_MOCK_GRAB, P::SERVICE_GLOBAL_SIM, P::SERVICE_LOCAL_CONTACT))
        << name;
  }
  EXPECT_THAT(ReasonOf(DeriveServices(testing::ShippedScene("pinch_stretch")), P::SERVICE_LOCAL_CONTACT),
              HasSubstr("I-IX"));
}

TEST(LaunchServiceSetTest, OneFingerGetsOneFingerModelsOnly) {
  const auto services = DeriveServices(testing::ShippedScene("one_finger"));
  EXPECT_THAT(Kinds(services), ElementsAre(P::SERVICE_DEVICE_BRIDGE, P::SERVICE_MOCK_GRAB, P::SERVICE_GLOBAL_SIM,
                                           P::SERVICE_LOCAL_CONTACT));
  EXPECT_THAT(ReasonOf(services, P::SERVICE_LOCAL_CONTACT), HasSubstr("one finger (index)"));
  EXPECT_THAT(ReasonOf(services, P::SERVICE_LOCAL_CONTACT), HasSubstr("no pinch"));
}

TEST(LaunchServiceSetTest, RemoteSceneNeedsEverything) {
  EXPECT_EQ(DeriveServices(testing::ShippedScene("remote")).size(), 6u);
}

TEST(LaunchServiceSetTest, RealDevicesStartNoMocks) {
  const v1::Scene scene = testing::SceneFromText(R"(
    name: "real" fabric { database_name: "wang2011_black_denim_11oz" }
    fingers { finger: FINGER_THUMB } fingers { finger: FINGER_INDEX }
    device { grab { controller_address: "127.0.0.1:7000" } }
    tactile { enabled: true display_address: "127.0.0.1:7001" })");
  const auto services = DeriveServices(scene);
  EXPECT_THAT(Kinds(services), ElementsAre(P::SERVICE_DEVICE_BRIDGE, P::SERVICE_TACTILE, P::SERVICE_GLOBAL_SIM,
                                           P::SERVICE_LOCAL_CONTACT));
  EXPECT_THAT(ReasonOf(services, P::SERVICE_DEVICE_BRIDGE), HasSubstr("127.0.0.1:7000"));
  const auto omitted = OmittedServices(scene);
  EXPECT_THAT(ReasonOf(omitted, P::SERVICE_MOCK_GRAB), HasSubstr("real GRAB controller at 127.0.0.1:7000"));
  EXPECT_THAT(ReasonOf(omitted, P::SERVICE_MOCK_PINS), HasSubstr("real pin display at 127.0.0.1:7001"));
}

// The scene layer's SceneRunsService (its network checks refuse a link to a service the scene does
// not run) says what DeriveServices says.
TEST(LaunchServiceSetTest, TheSceneLayerAgreesOnWhatASceneRuns) {
  std::vector<v1::Scene> scenes;
  for (const char* name : {"demo", "hanging", "rub_friction", "pinch_stretch", "one_finger", "remote", "cantilever"}) {
    scenes.push_back(testing::ShippedScene(name));
  }
  scenes.push_back(testing::SceneFromText(R"(
    name: "real" fabric { database_name: "wang2011_black_denim_11oz" }
    fingers { finger: FINGER_THUMB } device { grab { controller_address: "127.0.0.1:7000" } }
    tactile { enabled: true display_address: "127.0.0.1:7001" })"));
  for (const v1::Scene& scene : scenes) {
    const auto planned = Kinds(DeriveServices(scene));
    for (const ServiceSpec& spec : ServiceTable()) {
      const bool derived = std::find(planned.begin(), planned.end(), spec.kind) != planned.end();
      EXPECT_EQ(scene::SceneRunsService(scene, spec.kind), derived) << scene.name() << ": " << spec.name;
    }
  }
}

TEST(LaunchServiceSetTest, StopOrderPutsModelsFirstAndTheBridgeAfterThem) {
  const auto stop = StopOrder(DeriveServices(testing::ShippedScene("demo")));
  // the viewer only watches: it goes first
  EXPECT_THAT(Kinds(stop),
              ElementsAre(P::SERVICE_VIEWER, P::SERVICE_LOCAL_CONTACT, P::SERVICE_GLOBAL_SIM, P::SERVICE_TACTILE,
                          P::SERVICE_MOCK_PINS, P::SERVICE_DEVICE_BRIDGE, P::SERVICE_MOCK_GRAB));
}

}  // namespace
}  // namespace haptex::launch
