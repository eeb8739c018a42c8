#include "libs/scene/scene_loader.h"

#include <gtest/gtest.h>

#include "tests/scene/scene_test_support.h"

namespace haptex::scene {
namespace {

class SceneLoaderTest : public ::testing::Test {
 protected:
  SceneLoaderTest() : db_(testing::TestDataDir() + "/fabrics") {}

  // The issues of a scene that must be refused.
  std::vector<TextIssue> Refused(const std::string& text) {
    try {
      ParseScene(text, "t.textproto", db_);
    } catch (const TextProtoError& e) {
      return e.issues();
    }
    ADD_FAILURE() << "accepted:\n" << text;
    return {};
  }

  static bool Mentions(const std::vector<TextIssue>& issues, const std::string& word) {
    for (const auto& issue : issues) {
      if (issue.message.find(word) != std::string::npos) return true;
    }
    return false;
  }

  FabricDatabase db_;
};

constexpr char kMinimal[] = "name: \"hang\"\nfabric { database_name: \"test_cotton\" }\n";

TEST_F(SceneLoaderTest, MinimalSceneLoadsWithItsFabric) {
  const LoadedScene loaded = ParseScene(kMinimal, "t", db_);
  EXPECT_EQ(loaded.scene.name(), "hang");
  EXPECT_EQ(loaded.fabric.name(), "test_cotton");
}

TEST_F(SceneLoaderTest, InlineFabricIsUsedAsGiven) {
  const LoadedScene loaded = ParseScene(R"(
name: "inline"
fabric { inline_fabric {
  name: "mine"
  warp_tensile { emt_percent: 5 lt: 0.7 } weft_tensile { emt_percent: 5 lt: 0.7 }
  shear { g_gf_per_cm_deg: 1 } warp_bending { b_gfcm2_per_cm: 0.1 } weft_bending { b_gfcm2_per_cm: 0.1 }
  thickness_mm: 0.4 weight_mg_per_cm2: 12 } }
)",
                                        "t", db_);
  EXPECT_EQ(loaded.fabric.name(), "mine");
}

// Fewer than 3 Gauss-Seidel iterations per haptic tick went unstable (docs/contact.md).
TEST_F(SceneLoaderTest, LocalSolverDialsAreRangeChecked) {
  const auto few = Refused(
      "name: \"x\"\nfabric { database_name: \"test_cotton\" }\n"
      "model { local_cg_max_iterations: 2 }\n");
  ASSERT_EQ(few.size(), 1u);
  EXPECT_EQ(few[0].line, 3);
  EXPECT_NE(few[0].message.find("local_cg_max_iterations must be in [3, 100000]"), std::string::npos) << few[0].message;
  EXPECT_TRUE(Mentions(Refused("name: \"x\"\nfabric { database_name: \"test_cotton\" }\n"
                               "model { local_cg_tolerance: 0.9 }\n"),
                       "local_cg_tolerance"));
  const LoadedScene ok = ParseScene(
      "name: \"x\"\nfabric { database_name: \"test_cotton\" }\n"
      "model { local_cg_tolerance: 1e-3 local_cg_max_iterations: 20 }\n",
      "t", db_);
  EXPECT_EQ(ok.scene.model().local_cg_max_iterations(), 20u);
}

TEST_F(SceneLoaderTest, OutOfRangeValueIsLocatedAtItsField) {
  const auto issues =
      Refused("name: \"x\"\nfabric { database_name: \"test_cotton\" }\ncloth {\n    particles_u: 1\n}\n");
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].line, 4);
  EXPECT_EQ(issues[0].column, 5);
  EXPECT_NE(issues[0].message.find("particles_u must be in [2, 401]"), std::string::npos) << issues[0].message;
}

TEST_F(SceneLoaderTest, EveryProblemIsReportedAtOnce) {
  const auto issues = Refused(R"(name: "x"
fabric { database_name: "silk" }
rates { local_hz: 50 }
duration_s: nan
fingers { finger: FINGER_THUMB radius_m: 0.5 }
fingers { finger: FINGER_THUMB }
)");
  EXPECT_TRUE(Mentions(issues, "no fabric 'silk'"));
  EXPECT_TRUE(Mentions(issues, "local_hz"));
  EXPECT_TRUE(Mentions(issues, "duration_s"));
  EXPECT_TRUE(Mentions(issues, "radius_m"));
  EXPECT_TRUE(Mentions(issues, "listed twice"));
  EXPECT_TRUE(Mentions(issues, "needs a device"));
  EXPECT_GE(issues.size(), 6u);
}

TEST_F(SceneLoaderTest, SceneWithoutFabricSaysHowToGiveOne) {
  EXPECT_TRUE(Mentions(Refused("name: \"x\"\n"), "scene needs a fabric"));
}

TEST_F(SceneLoaderTest, BadInlineFabricIsLocatedInsideTheScene) {
  const auto issues = Refused(R"(name: "x"
fabric { inline_fabric {
  name: "mine"
  warp_tensile { emt_percent: 5 lt: 0.7 } weft_tensile { emt_percent: 5 lt: 0.7 }
  shear { g_gf_per_cm_deg: 1 } warp_bending { b_gfcm2_per_cm: 0.1 } weft_bending { b_gfcm2_per_cm: 0.1 }
  thickness_mm: -1 weight_mg_per_cm2: 12 } }
)");
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].line, 6);
  EXPECT_NE(issues[0].message.find("thickness_mm"), std::string::npos);
}

TEST_F(SceneLoaderTest, DeviceNetworkAndKeyProblems) {
  const auto issues = Refused(R"(name: "x"
fabric { database_name: "test_cotton" }
fingers { finger: FINGER_INDEX }
device { grab { controller_address: "10.0.0.5" } peak_force_n: 50 }
hosts { name: "lab" address: "192.0.2.1" }
services { service: SERVICE_GLOBAL_SIM host: "cluster" }
services { service: SERVICE_TACTILE port: 7000 }
services { service: SERVICE_LOCAL_CONTACT port: 7000 }
session_key { hex: "1234" }
friction { finger_fabric_mu_static: 0.2 finger_fabric_mu_dynamic: 0.4 }
)");
  EXPECT_TRUE(Mentions(issues, "has no port"));
  EXPECT_TRUE(Mentions(issues, "peak_force_n"));
  EXPECT_TRUE(Mentions(issues, "unknown host 'cluster'"));
  EXPECT_TRUE(Mentions(issues, "used twice"));
  EXPECT_TRUE(Mentions(issues, "64 hex digits"));
  EXPECT_TRUE(Mentions(issues, "must not exceed static"));
}

TEST_F(SceneLoaderTest, LoadsAndDisplaysMustExist) {
  const auto issues = Refused(R"(name: "x"
fabric { database_name: "test_cotton" }
cloth { particles_u: 3 particles_v: 3 }
loads { kind: KIND_POINT particle: 9 }
fingers { finger: FINGER_INDEX }
device { mock {} }
tactile { enabled: true }
)");
  EXPECT_TRUE(Mentions(issues, "particle 9 does not exist (the grid has 9)"));
  EXPECT_TRUE(Mentions(issues, "display_address"));
}

TEST_F(SceneLoaderTest, TactileSurfaceValuesNeedTheirSource) {
  const auto issues = Refused(R"(name: "x"
fabric { database_name: "test_cotton" }
fingers { finger: FINGER_INDEX }
device { mock {} }
tactile { enabled: true mock_display: true
  surface { pattern: PATTERN_KNIT warp_pitch_mm: 9 smd_um: 3 }
}
)");
  EXPECT_TRUE(Mentions(issues, "surface values need their origin"));
  EXPECT_TRUE(Mentions(issues, "warp_pitch_mm must be in [0.05, 5]"));
  EXPECT_TRUE(Mentions(issues, "woven patterns"));
  EXPECT_NO_THROW(ParseScene(R"(name: "x"
fabric { database_name: "test_cotton" }
fingers { finger: FINGER_INDEX }
device { mock {} }
tactile { enabled: true mock_display: true
  surface { pattern: PATTERN_TWILL smd_um: 3 source { citation: "a paper" } }
}
)",
                             "ok.textproto", db_));
}

TEST_F(SceneLoaderTest, RefinedPatchesMustFitOneDatagram) {
  const std::string scene = R"(name: "x"
fabric { database_name: "test_cotton" }
cloth { width_m: 0.2 height_m: 0.2 particles_u: 41 particles_v: 41 }
fingers { finger: FINGER_INDEX }
device { mock {} }
model { patch_refinement: REFINE }
)";
  auto with = [&](const std::string& levels) {
    std::string text = scene;
    text.replace(text.find("REFINE"), 6, levels);
    return text;
  };
  // 5 mm cells, 29 mm sphere: about 15 x 15 particles (20 kB); refined once, 29 x 29 (76 kB)
  EXPECT_NO_THROW(ParseScene(with("0"), "ok.textproto", db_));
  EXPECT_TRUE(Mentions(Refused(with("1")), "over one 60 kB datagram"));
}

TEST_F(SceneLoaderTest, MissingSceneFileIsAnError) {
  EXPECT_THROW(LoadScene("/nonexistent.textproto", db_), TextProtoError);
}

}  // namespace
}  // namespace haptex::scene
