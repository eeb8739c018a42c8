// `haptex view RUN_FOLDER` as a user meets it: a run folder that is missing, not a run, cut short
// or another program's recording is refused with exit code 2 and says why; a whole run is served.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "libs/mcap/mcap_writer.h"
#include "tests/support/subprocess.h"
#include "tests/support/test_paths.h"

namespace haptex {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

testing::Finished View(const std::string& run_dir) {
  return testing::RunToEnd({testing::BuildDir() + "/cli/haptex", "view", run_dir, "--port", "0", "--seconds", "0.5"});
}

// An MCAP file of `messages` messages on one channel of `topic`, schema `schema_name`.
std::string Recording(const std::string& topic, const std::string& schema_name, int messages) {
  std::ostringstream file;
  mcap::McapWriter writer(file);
  const auto schema = writer.AddSchema(schema_name, "protobuf", "x");
  const auto channel = writer.AddChannel(schema, topic, "protobuf");
  for (int i = 0; i < messages; ++i) writer.AddMessage({channel, static_cast<std::uint32_t>(i), 10u + i, 10u + i, ""});
  writer.Finish();
  return file.str();
}

class ViewCommandTest : public ::testing::Test {
 protected:
  void SetUp() override {
    fs::remove_all(run_);
    fs::create_directories(run_);
    fs::copy_file(testing::SourceDir() + "/launch/scenes/demo.textproto", run_ / "scene.textproto");
  }
  void TearDown() override { fs::remove_all(run_); }
  void WriteMcap(const std::string& bytes) const { std::ofstream(run_ / "run.mcap", std::ios::binary) << bytes; }

  fs::path run_ = fs::temp_directory_path() / ("haptex_view_test_" + std::to_string(::getpid()) + "_" +
                                               ::testing::UnitTest::GetInstance()->current_test_info()->name());
};

TEST_F(ViewCommandTest, AWholeRunIsServed) {
  WriteMcap(Recording("/local_contact/health", "haptex.v1.Health", 3));
  const testing::Finished r = View(run_.string());
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("(demo, 3 messages) on http://127.0.0.1:"));
}

TEST_F(ViewCommandTest, AMissingFolderOrOneThatIsNoRunIsRefused) {
  testing::Finished r = View((run_ / "nothing").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_THAT(r.err, HasSubstr("no such run folder"));
  r = View(run_.string());  // a scene, no recording
  EXPECT_EQ(r.code, 2);
  EXPECT_THAT(r.err, HasSubstr("is not a haptex run folder: it has no run.mcap"));
}

TEST_F(ViewCommandTest, ARecordingCutShortOrNotMcapIsRefused) {
  const std::string whole = Recording("/local_contact/health", "haptex.v1.Health", 50);
  WriteMcap(whole.substr(0, whole.size() / 2));
  testing::Finished r = View(run_.string());
  EXPECT_EQ(r.code, 2);
  EXPECT_THAT(r.err, HasSubstr("run.mcap: cut short"));
  WriteMcap("{\"not\": \"an MCAP file\"}");
  r = View(run_.string());
  EXPECT_EQ(r.code, 2);
  EXPECT_THAT(r.err, HasSubstr("not an MCAP file"));
}

// Valid MCAP, another program's: refused at the command, not left to fail in the page.
TEST_F(ViewCommandTest, AnotherProgramsRecordingIsRefused) {
  for (const auto& [topic, schema, why] : std::vector<std::tuple<std::string, std::string, std::string>>{
           {"/camera/image", "sensor_msgs.Image", "\"image\" is no Envelope body"},
           {"camera", "haptex.v1.Health", "the topic is not /<service>/<body>"},
           {"/local_contact/health", "haptex.v1.ForceModel", "its schema is not haptex.v1.Health"}}) {
    WriteMcap(Recording(topic, schema, 2));
    const testing::Finished r = View(run_.string());
    EXPECT_EQ(r.code, 2) << topic;
    EXPECT_THAT(r.err, HasSubstr("is not a haptex run's recording: channel " + topic + ": " + why));
  }
}

}  // namespace
}  // namespace haptex
