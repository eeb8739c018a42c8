#include "services/viewer/run_replay.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "libs/mcap/mcap_writer.h"
#include "tests/support/test_paths.h"

namespace haptex::viewer {
namespace {

namespace fs = std::filesystem;

struct RunFolder {
  fs::path dir = fs::temp_directory_path() / ("haptex_replay_test_" + std::to_string(::getpid()) + "_" +
                                              ::testing::UnitTest::GetInstance()->current_test_info()->name());
  RunFolder() {
    fs::remove_all(dir);
    fs::create_directories(dir);
  }
  ~RunFolder() { fs::remove_all(dir); }
  void Write(const std::string& name, const std::string& bytes) const {
    std::ofstream(dir / name, std::ios::binary) << bytes;
  }
};

// `messages` Health messages on one channel
std::string Recording(int messages) {
  std::ostringstream file;
  mcap::McapWriter writer(file);
  const auto schema = writer.AddSchema("haptex.v1.Health", "protobuf", "x");
  const auto channel = writer.AddChannel(schema, "/a/health", "protobuf");
  for (int i = 0; i < messages; ++i) {
    writer.AddMessage({channel, static_cast<std::uint32_t>(i), 10u + i, 10u + i, "payload"});
  }
  writer.Finish();
  return file.str();
}

std::string ThrowsWith(const std::string& run_dir) {
  try {
    LoadRunForReplay(run_dir);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(RunReplayTest, AMissingFolderOrOneWithoutARecordingIsNoRun) {
  EXPECT_NE(ThrowsWith("/no/such/run").find("no such run folder"), std::string::npos);
  RunFolder run;
  run.Write("summary.json", "{}");
  EXPECT_NE(ThrowsWith(run.dir.string()).find("not a haptex run folder: it has no run.mcap"), std::string::npos);
}

TEST(RunReplayTest, ARecordingThatIsNotMcapOrCutShortIsRefusedSayingSo) {
  RunFolder run;
  run.Write("run.mcap", "this is not an MCAP file at all");
  EXPECT_NE(ThrowsWith(run.dir.string()).find("MCAP"), std::string::npos) << ThrowsWith(run.dir.string());
  const std::string bytes = Recording(10);
  run.Write("run.mcap", bytes.substr(0, bytes.size() / 2));
  const std::string error = ThrowsWith(run.dir.string());
  EXPECT_NE(error.find("run.mcap: cut short"), std::string::npos) << error;
}

TEST(RunReplayTest, AnotherProgramsRecordingIsRefused) {
  RunFolder run;
  std::ostringstream file;
  mcap::McapWriter writer(file);
  writer.AddChannel(writer.AddSchema("sensor_msgs.Image", "protobuf", "x"), "/camera/image", "protobuf");
  writer.Finish();
  run.Write("run.mcap", file.str());
  const std::string error = ThrowsWith(run.dir.string());
  EXPECT_NE(error.find("is not a haptex run's recording: channel /camera/image"), std::string::npos) << error;
}

TEST(RunReplayTest, AWholeRunServesItsRecordingAndTheSceneItRan) {
  RunFolder run;
  const std::string bytes = Recording(1);
  run.Write("run.mcap", bytes);
  fs::copy_file(haptex::testing::SourceDir() + "/launch/scenes/demo.textproto", run.dir / "scene.textproto");
  const RunReplay replay = LoadRunForReplay(run.dir.string());
  EXPECT_EQ(replay.messages, 1u);
  EXPECT_EQ(replay.mcap_bytes, bytes);
  EXPECT_EQ(replay.scene_name, "demo");
  const auto session = nlohmann::json::parse(replay.session_json);
  EXPECT_EQ(session["mode"], "replay");
  EXPECT_EQ(session["recording"], "/run.mcap");
  ASSERT_EQ(session["scene"]["fingers"].size(), 2u);
  EXPECT_DOUBLE_EQ(session["scene"]["fingers"][0]["radius_m"].get<double>(), 0.008);
  // the demo's cloth hangs from its top edge: the stand holds the first row of 41
  ASSERT_EQ(session["fixed_particles"].size(), 41u);
  EXPECT_EQ(session["fixed_particles"][40], 40);
}

}  // namespace
}  // namespace haptex::viewer
