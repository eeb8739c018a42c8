#include "libs/scene/scene_loader.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <functional>

#include "libs/scene/scene_stalls.h"
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

// BDF2 needs Newton's iterations (libs/textile/step_options.h) and is for a cloth without the dual
// layer (docs/fabric-model.md).
TEST_F(SceneLoaderTest, Bdf2NeedsNewtonIterationsAndNoDualLayer) {
  const std::string head = "name: \"x\"\nfabric { database_name: \"test_cotton\" }\n";
  const auto single = Refused(head + "model { global_integrator: INTEGRATOR_BDF2 }\n");
  ASSERT_EQ(single.size(), 1u);
  EXPECT_EQ(single[0].line, 3);
  EXPECT_NE(single[0].message.find("INTEGRATOR_BDF2 needs newton_max_iterations of 2 or more"), std::string::npos)
      << single[0].message;
  EXPECT_TRUE(Mentions(Refused(head + "model { local_integrator: INTEGRATOR_BDF2 }\n"), "for the global layer"));
  // with fingers the dual layer merges patch results into the cloth: not with BDF2
  EXPECT_TRUE(
      Mentions(Refused(head + "fingers { finger: FINGER_THUMB shape: SHAPE_CAPSULE radius_m: 0.008 length_m: 0.012 }\n"
                              "model { global_integrator: INTEGRATOR_BDF2 newton_max_iterations: 6 }\n"),
               "without local_contact"));
  const LoadedScene ok =
      ParseScene(head + "model { global_integrator: INTEGRATOR_BDF2 newton_max_iterations: 6 }\n", "t", db_);
  EXPECT_EQ(ok.scene.model().global_integrator(), v1::ModelOptions::INTEGRATOR_BDF2);
}

TEST_F(SceneLoaderTest, OutOfRangeValueIsLocatedAtItsField) {
  const auto issues =
      Refused("name: \"x\"\nfabric { database_name: \"test_cotton\" }\ncloth {\n    particles_u: 1\n}\n");
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].line, 4);
  EXPECT_EQ(issues[0].column, 5);
  EXPECT_NE(issues[0].message.find("particles_u must be in [2, 401]"), std::string::npos) << issues[0].message;
}

TEST_F(SceneLoaderTest, MaterialAngleOutsideHalfATurnIsRefused) {
  const auto issues =
      Refused("name: \"x\"\nfabric { database_name: \"test_cotton\" }\ncloth {\n  material_angle_deg: 270\n}\n");
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].line, 4);
  EXPECT_NE(issues[0].message.find("material_angle_deg must be in [-180, 180] deg, got 270"), std::string::npos)
      << issues[0].message;
  EXPECT_EQ(
      Refused("name: \"x\"\nfabric { database_name: \"test_cotton\" }\ncloth { material_angle_deg: nan }\n").size(),
      1u);
  const LoadedScene ok = ParseScene(
      "name: \"x\"\nfabric { database_name: \"test_cotton\" }\ncloth { material_angle_deg: -45 }\n", "t", db_);
  EXPECT_EQ(ok.scene.cloth().material_angle_deg(), -45.0);
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

TEST_F(SceneLoaderTest, TheMockUsersSpeedsAreRangeChecked) {
  const auto issues = Refused(R"(name: "x"
fabric { database_name: "test_cotton" }
fingers { finger: FINGER_INDEX }
device { mock { user { kind: KIND_PINCH_AND_STRETCH speed_m_per_s: 2
                       stretch_speed_m_per_s: 0.00001 } } }
)");
  ASSERT_EQ(issues.size(), 2u);
  EXPECT_TRUE(Mentions(issues, "speed_m_per_s must be in [0.001, 1]"));
  EXPECT_EQ(issues[1].line, 5);
  EXPECT_NE(issues[1].message.find("stretch_speed_m_per_s must be in [0.0001, 1]"), std::string::npos)
      << issues[1].message;
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

// Every float and enum field the schema has, at any depth: found by reflection, so a field added
// later is covered too. `visit(path)` gets the field names from Scene down to each leaf.
void ForEachLeaf(const google::protobuf::Descriptor& d, std::vector<const google::protobuf::FieldDescriptor*>* path,
                 const std::function<void(const std::vector<const google::protobuf::FieldDescriptor*>&)>& visit) {
  if (path->size() > 6) return;
  for (int i = 0; i < d.field_count(); ++i) {
    const google::protobuf::FieldDescriptor* f = d.field(i);
    path->push_back(f);
    if (f->cpp_type() == google::protobuf::FieldDescriptor::CPPTYPE_MESSAGE) {
      ForEachLeaf(*f->message_type(), path, visit);
    } else {
      visit(*path);
    }
    path->pop_back();
  }
}

// A scene whose line 3 sets the leaf at `path` to `value` (the rest minimal and valid).
std::string SceneSetting(const std::vector<const google::protobuf::FieldDescriptor*>& path, const std::string& value) {
  std::string leaf, close;
  for (std::size_t i = 0; i + 1 < path.size(); ++i) {
    leaf += std::string(path[i]->name()) + " { ";
    close += " }";
  }
  leaf += std::string(path.back()->name()) + ": " + value + close;
  const bool in_fabric = path.front()->name() == "fabric";
  return std::string("name: \"x\"\n") + (in_fabric ? "\n" : "fabric { database_name: \"test_cotton\" }\n") + leaf +
         "\n";
}

std::string PathName(const std::vector<const google::protobuf::FieldDescriptor*>& path) {
  std::string name;
  for (const auto* f : path) name += (name.empty() ? "" : ".") + std::string(f->name());
  return name;
}

TEST_F(SceneLoaderTest, EveryNumberFieldRefusesNanAndInfAtItsLine) {
  std::vector<const google::protobuf::FieldDescriptor*> path;
  int checked = 0;
  ForEachLeaf(*v1::Scene::descriptor(), &path, [&](const auto& leaf) {
    const auto type = leaf.back()->cpp_type();
    if (type != google::protobuf::FieldDescriptor::CPPTYPE_DOUBLE &&
        type != google::protobuf::FieldDescriptor::CPPTYPE_FLOAT) {
      return;
    }
    for (const char* value : {"nan", "inf", "-inf"}) {
      const auto issues = Refused(SceneSetting(leaf, value));
      const bool located = std::any_of(issues.begin(), issues.end(), [&](const TextIssue& issue) {
        return issue.line == 3 &&
               issue.message.find(std::string(leaf.back()->name()) + " must be a finite number") != std::string::npos;
      });
      EXPECT_TRUE(located) << PathName(leaf) << ": " << value;
    }
    ++checked;
  });
  EXPECT_GT(checked, 60) << "the walk found the schema's numbers";
  // the named ones, with their whole path
  const auto stand = Refused(SceneSetting({v1::Scene::descriptor()->FindFieldByName("cloth"),
                                           v1::ClothGeometry::descriptor()->FindFieldByName("stand_position_w_m"),
                                           v1::Vec3::descriptor()->FindFieldByName("x")},
                                          "nan"));
  ASSERT_EQ(stand.size(), 1u) << "one issue per field";
  EXPECT_EQ(stand[0].message, "cloth.stand_position_w_m.x must be a finite number, got nan");
  EXPECT_EQ(stand[0].column, 30);
}

TEST_F(SceneLoaderTest, EveryEnumFieldRefusesValuesItDoesNotDefine) {
  std::vector<const google::protobuf::FieldDescriptor*> path;
  int checked = 0;
  ForEachLeaf(*v1::Scene::descriptor(), &path, [&](const auto& leaf) {
    if (leaf.back()->cpp_type() != google::protobuf::FieldDescriptor::CPPTYPE_ENUM) return;
    const auto issues = Refused(SceneSetting(leaf, "99"));
    const bool located = std::any_of(issues.begin(), issues.end(), [&](const TextIssue& issue) {
      return issue.line == 3 && issue.message.find("99 is not a value of") != std::string::npos;
    });
    EXPECT_TRUE(located) << PathName(leaf);
    ++checked;
  });
  EXPECT_GT(checked, 8);
  const auto finger = Refused(std::string(kMinimal) + "fingers { finger: 99 }\ndevice { mock {} }\n");
  ASSERT_EQ(finger.size(), 1u);
  EXPECT_EQ(finger[0].line, 3);
  EXPECT_EQ(finger[0].column, 11);
  EXPECT_EQ(finger[0].message, "fingers[0].finger: 99 is not a value of Finger (FINGER_THUMB, FINGER_INDEX)");
}

TEST_F(SceneLoaderTest, PositionsLieNearTheOrigin) {
  EXPECT_TRUE(Mentions(Refused(std::string(kMinimal) + "cloth { stand_position_w_m { z: 1e6 } }\n"),
                       "stand_position_w_m must have a magnitude <= 10 m"));
  EXPECT_TRUE(Mentions(Refused(std::string(kMinimal) + "fingers { finger: FINGER_THUMB }\n"
                                                       "device { mock { user { touch_point_w_m { x: -40 } } } }\n"),
                       "touch_point_w_m must have a magnitude <= 10 m"));
}

// The device's pose in W (X_WD) and the bridge's controller-side port: a rotation must be a unit
// quaternion, an origin near W's, a port a port; each refused at its field's line and column.
TEST_F(SceneLoaderTest, DevicePoseAndBridgePortAreCheckedAtTheirFields) {
  const std::string scene = std::string(kMinimal) + "fingers { finger: FINGER_THUMB }\n";
  const auto rotation = Refused(scene + "device { mock {}\n  q_wd { w: 0.5 z: 0.5 } }\n");
  ASSERT_EQ(rotation.size(), 1u);
  EXPECT_EQ(rotation[0].line, 5);
  EXPECT_EQ(rotation[0].column, 3);
  EXPECT_NE(rotation[0].message.find("q_wd must be a unit quaternion"), std::string::npos) << rotation[0].message;
  EXPECT_NE(rotation[0].message.find("got |q| = 0.707"), std::string::npos) << rotation[0].message;
  const auto empty = Refused(scene + "device { mock {} q_wd {} }\n");
  ASSERT_EQ(empty.size(), 1u);
  EXPECT_NE(empty[0].message.find("got |q| = 0"), std::string::npos) << empty[0].message;
  const auto not_a_number = Refused(scene + "device { mock {} q_wd { w: nan } }\n");
  ASSERT_EQ(not_a_number.size(), 1u) << "one issue per field";
  EXPECT_EQ(not_a_number[0].message, "device.q_wd.w must be a finite number, got nan");
  EXPECT_EQ(not_a_number[0].column, 25);
  EXPECT_TRUE(Mentions(Refused(scene + "device { mock {} d_origin_w_m { y: 11 } }\n"),
                       "d_origin_w_m must have a magnitude <= 10 m"));
  const auto infinite = Refused(scene + "device { mock {} d_origin_w_m { z: -inf } }\n");
  ASSERT_EQ(infinite.size(), 1u);
  EXPECT_EQ(infinite[0].message, "device.d_origin_w_m.z must be a finite number, got -inf");
  const auto port = Refused(scene + "device { mock {}\n bridge_controller_port: 70000 }\n");
  ASSERT_EQ(port.size(), 1u);
  EXPECT_EQ(port[0].line, 5);
  EXPECT_EQ(port[0].column, 2);
  EXPECT_EQ(port[0].message, "bridge_controller_port must be 0 (the launcher picks) or 1..65535, got 70000");
  // four decimals are a unit quaternion
  EXPECT_NO_THROW(
      ParseScene(scene + "device { mock {} q_wd { w: 0.7071 z: 0.7071 } bridge_controller_port: 47000 }\n", "t", db_));
}

// Below 1 kHz a command would be older than the controller's host timeout allows for jitter (and
// every bridge tick a stall): the GRAB rates are 1-20 kHz.
TEST_F(SceneLoaderTest, TheBridgeRateIsOneOfTheProtocolsRates) {
  EXPECT_TRUE(
      Mentions(Refused(std::string(kMinimal) + "rates { bridge_hz: 500 }\n"), "bridge_hz must be in [1000, 20000] Hz"));
  EXPECT_NO_THROW(ParseScene(std::string(kMinimal) + "rates { bridge_hz: 1000 }\n", "t", db_));
}

// A 401 x 401 cloth ran at about 1 Hz and exited 0: particles x global rate is capped.
TEST_F(SceneLoaderTest, ClothsTheGlobalLoopCannotStepInTimeAreRefused) {
  const auto cloth = [&](int side, int rate_hz) {
    return std::string(kMinimal) + "cloth { particles_u: " + std::to_string(side) +
           " particles_v: " + std::to_string(side) + " }\nrates { global_hz: " + std::to_string(rate_hz) + " }\n";
  };
  const auto huge = Refused(cloth(401, 100));
  ASSERT_EQ(huge.size(), 1u);
  EXPECT_EQ(huge[0].line, 3);
  EXPECT_EQ(huge[0].column, 9);
  EXPECT_NE(huge[0].message.find("a 401 x 401 cloth at 100 Hz needs 16080100 particle steps per second"),
            std::string::npos)
      << huge[0].message;
  EXPECT_NE(
      huge[0].message.find("use at most 44 x 44 particles at this rate, or lower rates.global_hz to at most 1 Hz"),
      std::string::npos)
      << huge[0].message;
  EXPECT_TRUE(Mentions(Refused(cloth(81, 100)), "lower rates.global_hz to at most 30 Hz"));
  EXPECT_NO_THROW(ParseScene(cloth(81, 30), "ok", db_));
  EXPECT_NO_THROW(ParseScene(cloth(41, 100), "ok", db_));
  EXPECT_NO_THROW(ParseScene(kMinimal, "ok", db_));
  EXPECT_EQ(kMaxParticleStepsPerSecond, 200000.0);
}

TEST_F(SceneLoaderTest, NamesAreBoundedOneLineAndNotPaths) {
  const auto long_name =
      Refused("name: \"" + std::string(1 << 20, 'a') + "\"\nfabric { database_name: \"test_cotton\" }\n");
  ASSERT_EQ(long_name.size(), 1u);
  EXPECT_EQ(long_name[0].line, 1);
  EXPECT_EQ(long_name[0].column, 1);
  EXPECT_EQ(long_name[0].message, "name has 1048576 bytes, at most 100");
  EXPECT_NO_THROW(
      ParseScene("name: \"" + std::string(kMaxSceneNameBytes, 'a') + "\"\nfabric { database_name: \"test_cotton\" }\n",
                 "ok", db_));
  const auto two_lines = Refused("name: \"a\\n!touch x\"\nfabric { database_name: \"test_cotton\" }\n");
  ASSERT_EQ(two_lines.size(), 1u);
  EXPECT_NE(two_lines[0].message.find("one line"), std::string::npos);
  EXPECT_TRUE(Mentions(Refused("name: \"a\\001b\"\nfabric { database_name: \"test_cotton\" }\n"),
                       "name holds a control character"));
  EXPECT_TRUE(Mentions(Refused("name: \"\\377\\376\"\nfabric { database_name: \"test_cotton\" }\n"),
                       "name is not valid UTF-8"));
  const auto climb = Refused("name: \"x\"\nfabric { database_name: \"../fabrics/test_cotton\" }\n");
  ASSERT_EQ(climb.size(), 1u) << "not also 'no fabric'";
  EXPECT_EQ(climb[0].line, 2);
  EXPECT_NE(climb[0].message.find("not a path"), std::string::npos);
  EXPECT_TRUE(Mentions(Refused(std::string(kMinimal) + "hosts { name: \"a/b\" address: \"192.0.2.1\" }\n"),
                       "host name must be letters"));
  EXPECT_TRUE(Mentions(
      Refused(std::string(kMinimal) + "hosts { name: \"" + std::string(65, 'h') + "\" address: \"192.0.2.1\" }\n"),
      "hosts[0].name has 65 bytes, at most 64"));
  EXPECT_TRUE(Mentions(Refused(std::string(kMinimal) + "hosts { name: \"lab\" address: \"a b\" }\n"), "no spaces"));
  EXPECT_TRUE(Mentions(Refused(std::string(kMinimal) + "session_key { env: \"A-B\" }\n"), "env must name"));
}

TEST_F(SceneLoaderTest, OtherStringsAreBoundedAndClean) {
  EXPECT_TRUE(Mentions(Refused(std::string(kMinimal) + "description: \"" + std::string(5000, 'd') + "\"\n"),
                       "description has 5000 bytes, at most 4096"));
  EXPECT_TRUE(Mentions(Refused(std::string(kMinimal) + "description: \"a\\033[2Jb\"\n"), "control character"));
  EXPECT_NO_THROW(ParseScene(std::string(kMinimal) + "description: \"two\\nlines\\tand a tab\"\n", "ok", db_));
  EXPECT_TRUE(Mentions(
      Refused(std::string(kMinimal) + "fingers { finger: FINGER_THUMB }\n"
                                      "device { mock { user { kind: KIND_PLAYBACK playback_csv: \"/dev/zero\" } } }\n"),
      "playback_csv must be a readable file"));
}

// Two fingers on the mock controller (bridge, mock controller, global_sim, local_contact); what
// follows it starts on line 6.
constexpr char kPinch[] =
    "name: \"pinch\"\n"
    "fabric { database_name: \"test_cotton\" }\n"
    "fingers { finger: FINGER_THUMB }\n"
    "fingers { finger: FINGER_INDEX }\n"
    "device { mock {} }\n";

TEST_F(SceneLoaderTest, StallsOfAServiceAndOfAllLoad) {
  const LoadedScene loaded = ParseScene(std::string(kPinch) +
                                            "stalls { service: SERVICE_LOCAL_CONTACT at_s: 1.5 duration_s: 0.1 }\n"
                                            "stalls { all: true at_s: 2 duration_s: 0.03 }\n"
                                            "stalls { service: SERVICE_LOCAL_CONTACT at_s: 2.1 duration_s: 10 }\n"
                                            "stalls { service: SERVICE_MOCK_GRAB at_s: 0 duration_s: 0.001 }\n",
                                        "t", db_);
  ASSERT_EQ(loaded.scene.stalls_size(), 4);
  EXPECT_EQ(loaded.scene.stalls(0).service(), v1::ServicePlacement::SERVICE_LOCAL_CONTACT);
  EXPECT_TRUE(loaded.scene.stalls(1).all());
  EXPECT_EQ(StallTarget(loaded.scene.stalls(1)), "all");
  EXPECT_EQ(StallTarget(loaded.scene.stalls(0)), "local_contact");
}

TEST_F(SceneLoaderTest, AStallsTargetIsOneServiceTheSceneRunsOrAll) {
  const auto only = [&](const std::string& stalls) {
    const auto issues = Refused(std::string(kPinch) + stalls);
    EXPECT_EQ(issues.size(), 1u) << stalls;
    return issues.empty() ? TextIssue{} : issues[0];
  };
  const TextIssue none = only("stalls { at_s: 1 duration_s: 0.1 }\n");
  EXPECT_EQ(none.line, 6);
  EXPECT_EQ(none.column, 1);
  EXPECT_EQ(none.message, "a stall needs a target: `service: SERVICE_...` or `all: true`");
  const TextIssue both = only("stalls { service: SERVICE_LOCAL_CONTACT\n  all: true at_s: 1 duration_s: 0.1 }\n");
  EXPECT_EQ(both.line, 7);
  EXPECT_EQ(both.column, 3);
  EXPECT_EQ(both.message, "give either `service: SERVICE_...` or `all: true`, not both");
  const TextIssue tactile = only("stalls { service: SERVICE_TACTILE at_s: 1 duration_s: 0.1 }\n");
  EXPECT_EQ(tactile.line, 6);
  EXPECT_EQ(tactile.column, 10);
  EXPECT_EQ(tactile.message, "the scene does not run tactile (tactile display off)");
  EXPECT_TRUE(Mentions(Refused(std::string(kPinch) + "stalls { service: SERVICE_LAUNCHER at_s: 1 duration_s: 0.1 }\n"),
                       "the launcher carries the stalls out and cannot pause itself"));
  EXPECT_TRUE(Mentions(Refused(std::string(kPinch) + "viewer { enabled: true }\n"
                                                     "stalls { service: SERVICE_VIEWER at_s: 1 duration_s: 0.1 }\n"),
                       "the viewer only shows the run: a stall pauses a haptex service"));
  // the fabric alone runs only global_sim
  EXPECT_TRUE(
      Mentions(Refused(std::string(kMinimal) + "stalls { service: SERVICE_DEVICE_BRIDGE at_s: 1 duration_s: 1 }\n"),
               "the scene does not run device_bridge (the scene has no fingers)"));
  EXPECT_NO_THROW(
      ParseScene(std::string(kMinimal) + "stalls { service: SERVICE_GLOBAL_SIM at_s: 1 duration_s: 1 }\n", "ok", db_));
  // a value the enum does not define: one issue, the generic check's
  const TextIssue undefined = only("stalls { service: 99 at_s: 1 duration_s: 0.1 }\n");
  EXPECT_NE(undefined.message.find("99 is not a value of Service"), std::string::npos) << undefined.message;
}

TEST_F(SceneLoaderTest, AStallsTimesAreCheckedAtTheirFields) {
  const auto only = [&](const std::string& times) {
    const auto issues = Refused(std::string(kPinch) + "stalls { all: true\n  " + times + " }\n");
    EXPECT_EQ(issues.size(), 1u) << times;
    return issues.empty() ? TextIssue{} : issues[0];
  };
  const TextIssue before = only("at_s: -0.5 duration_s: 0.1");
  EXPECT_EQ(before.line, 7);
  EXPECT_EQ(before.column, 3);
  EXPECT_EQ(before.message, "at_s must be in [0, 604800] s from the run's start (force enabled), got -0.5");
  EXPECT_TRUE(Mentions({only("at_s: 1e300 duration_s: 0.1")}, "at_s must be in [0, 604800] s"));
  const TextIssue zero = only("at_s: 1 duration_s: 0");
  EXPECT_EQ(zero.column, 11);
  EXPECT_EQ(zero.message, "duration_s must be in (0, 10] s, got 0");
  EXPECT_TRUE(Mentions({only("at_s: 1 duration_s: 10.001")}, "duration_s must be in (0, 10] s, got 10.001"));
  EXPECT_TRUE(Mentions({only("at_s: 1 duration_s: -1")}, "duration_s must be in (0, 10] s, got -1"));
  // left out: located at the stall
  const TextIssue missing = only("at_s: 1");
  EXPECT_EQ(missing.line, 6);
  EXPECT_EQ(missing.message, "duration_s must be in (0, 10] s, got 0");
  // not a number: one issue per field, the generic check's
  for (const std::string value : {"nan", "inf", "-inf"}) {
    const TextIssue at = only("at_s: " + value + " duration_s: 0.1");
    EXPECT_EQ(at.message, "stalls[0].at_s must be a finite number, got " + value);
    EXPECT_EQ(at.column, 3);
    const TextIssue duration = only("at_s: 1 duration_s: " + value);
    EXPECT_EQ(duration.message, "stalls[0].duration_s must be a finite number, got " + value);
  }
  // a stall without a target and without times: each problem, though two share a place
  EXPECT_EQ(Refused(std::string(kPinch) + "stalls { }\n").size(), 2u);
}

TEST_F(SceneLoaderTest, StallsOfOneProcessMustNotOverlap) {
  const auto issues = Refused(std::string(kPinch) +
                              "stalls { service: SERVICE_LOCAL_CONTACT at_s: 1.5 duration_s: 0.1 }\n"
                              "stalls { service: SERVICE_LOCAL_CONTACT at_s: 1.55 duration_s: 0.1 }\n");
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].line, 7);
  EXPECT_EQ(issues[0].column, 41);
  EXPECT_EQ(issues[0].message,
            "the stall of local_contact at 1.55 s for 0.1 s overlaps the one of local_contact at 1.5 s for 0.1 s "
            "(line 6): stalls that pause one process (all pauses every one) must not overlap");
  // all pauses every service: it overlaps a stall of any one of them, in either order
  EXPECT_TRUE(
      Mentions(Refused(std::string(kPinch) + "stalls { all: true at_s: 1 duration_s: 2 }\n"
                                             "stalls { service: SERVICE_GLOBAL_SIM at_s: 2.9 duration_s: 1 }\n"),
               "the stall of global_sim at 2.9 s for 1 s overlaps the one of all at 1 s for 2 s"));
  EXPECT_TRUE(Mentions(Refused(std::string(kPinch) + "stalls { service: SERVICE_GLOBAL_SIM at_s: 0.5 duration_s: 1 }\n"
                                                     "stalls { all: true at_s: 1 duration_s: 2 }\n"),
                       "overlaps the one of global_sim"));
  // one after the other, and two services at once, are fine
  EXPECT_NO_THROW(ParseScene(std::string(kPinch) +
                                 "stalls { service: SERVICE_LOCAL_CONTACT at_s: 1.5 duration_s: 0.5 }\n"
                                 "stalls { service: SERVICE_LOCAL_CONTACT at_s: 2 duration_s: 0.1 }\n"
                                 "stalls { service: SERVICE_DEVICE_BRIDGE at_s: 1.5 duration_s: 0.5 }\n"
                                 "stalls { all: true at_s: 2.1 duration_s: 0.1 }\n",
                             "ok", db_));
}

TEST_F(SceneLoaderTest, AtMost32Stalls) {
  std::string stalls;
  for (int i = 0; i < kMaxStalls; ++i) {
    stalls += "stalls { service: SERVICE_GLOBAL_SIM at_s: " + std::to_string(i) + " duration_s: 0.5 }\n";
  }
  EXPECT_NO_THROW(ParseScene(std::string(kPinch) + stalls, "ok", db_));
  const auto issues = Refused(std::string(kPinch) + stalls + "stalls { all: true at_s: 100 duration_s: 0.5 }\n");
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].line, 6 + kMaxStalls);
  EXPECT_EQ(issues[0].message, "at most 32 stalls per scene");
}

TEST_F(SceneLoaderTest, SceneFilesAreCheckedBeforeTheyAreRead) {
  for (const std::string path : {"/dev/zero", "/dev/urandom", "/"}) {
    try {
      LoadScene(path, db_);
      ADD_FAILURE() << path;
    } catch (const TextProtoError& e) {
      EXPECT_NE(std::string(e.what()).find(path + ":1:1: not a regular file"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace haptex::scene
