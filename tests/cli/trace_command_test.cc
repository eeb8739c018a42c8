// `haptex trace export`: a run folder's run.mcap first, an .mcap path, the .pb recordings as the
// fallback; a missing, cut or foreign input is a clear error and a nonzero exit.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>

#include "launch/run_mcap.h"
#include "libs/mcap/mcap_writer.h"
#include "tests/support/subprocess.h"
#include "tests/support/test_paths.h"

namespace haptex::cli {
namespace {

using ::testing::HasSubstr;
namespace fs = std::filesystem;

struct Result {
  int code = -1;
  std::string out, err;
};

Result Export(const std::vector<std::string>& args) {
  std::vector<std::string> argv{haptex::testing::BuildDir() + "/cli/haptex", "trace", "export"};
  argv.insert(argv.end(), args.begin(), args.end());
  haptex::testing::Subprocess p(argv);
  const auto code = p.WaitFor(std::chrono::seconds(60));
  return {code.value_or(-1), p.Stdout(), p.Stderr()};
}

std::vector<launch::Recording> Recordings() {
  launch::Recording bridge;
  for (int i = 0; i < 3; ++i) {
    v1::Envelope e;
    e.set_sender("device_bridge");
    e.set_send_time_ns(1'000'000'000 + i * 1'000'000);
    e.mutable_finger_states()->set_controller_sequence(i);
    e.mutable_finger_states()->add_fingers()->set_finger(v1::FINGER_THUMB);  // a row per finger
    bridge.envelopes.push_back(e);
  }
  return {bridge};
}

void WriteBytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

class TraceCommandTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = ::testing::TempDir() + "/trace_command_" + std::to_string(getpid()) + "_" +
           ::testing::UnitTest::GetInstance()->current_test_info()->name();
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  std::string dir_;
};

TEST_F(TraceCommandTest, ReadsARunFoldersRunMcap) {
  launch::WriteRunMcap(Recordings(), dir_ + "/run.mcap");
  const Result r = Export({dir_, "--csv"});
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("run.mcap /device_bridge/*: 3 messages"));
  EXPECT_THAT(r.out, HasSubstr("finger_states.csv (3 rows)"));
  EXPECT_TRUE(fs::exists(dir_ + "/csv/finger_states.csv"));
}

TEST_F(TraceCommandTest, ReadsAnMcapPathAndWritesBesideIt) {
  launch::WriteRunMcap(Recordings(), dir_ + "/other.mcap");
  const Result r = Export({dir_ + "/other.mcap", "--csv"});
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir_ + "/csv/finger_states.csv"));
}

TEST_F(TraceCommandTest, FallsBackToThePbRecordings) {
  fs::create_directories(dir_ + "/recordings");
  // length-delimited Envelopes, as services write them (a one-byte varint: each is short)
  std::string pb;
  const auto recordings = Recordings();
  for (const v1::Envelope& e : recordings[0].envelopes) {
    const std::string bytes = e.SerializeAsString();
    ASSERT_LT(bytes.size(), 128u);
    pb += static_cast<char>(bytes.size());
    pb += bytes;
  }
  WriteBytes(dir_ + "/recordings/device_bridge.pb", pb);
  const Result r = Export({dir_, "--csv"});
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("device_bridge.pb: 3 messages"));
}

TEST_F(TraceCommandTest, MissingCutAndForeignInputsAreClearErrors) {
  Result r = Export({dir_ + "/missing.mcap", "--csv"});
  EXPECT_NE(r.code, 0);
  EXPECT_THAT(r.err, HasSubstr("cannot read " + dir_ + "/missing.mcap"));

  r = Export({dir_ + "/no_such_run", "--csv"});
  EXPECT_NE(r.code, 0);
  EXPECT_THAT(r.err, HasSubstr("no run folder"));

  const std::string bytes = launch::MakeRunMcap(Recordings(), nullptr);
  for (std::size_t size : {std::size_t{0}, std::size_t{7}, std::size_t{40}, bytes.size() / 2, bytes.size() - 1}) {
    WriteBytes(dir_ + "/run.mcap", bytes.substr(0, size));
    r = Export({dir_, "--csv"});
    EXPECT_EQ(r.code, 1) << "cut to " << size;
    EXPECT_THAT(r.err, HasSubstr("haptex: MCAP: " + dir_ + "/run.mcap: ")) << "cut to " << size;
  }

  WriteBytes(dir_ + "/text.mcap", "not mcap at all\n");
  r = Export({dir_ + "/text.mcap", "--csv"});
  EXPECT_NE(r.code, 0);
  EXPECT_THAT(r.err, HasSubstr("not an MCAP file"));

  std::ofstream camera(dir_ + "/camera.mcap", std::ios::binary);
  mcap::McapWriter w(camera);
  const auto c = w.AddChannel(w.AddSchema("sensor_msgs.Image", "protobuf", ""), "/camera/image", "protobuf");
  w.AddMessage({c, 0, 1, 1, ""});
  w.Finish();
  camera.close();
  r = Export({dir_ + "/camera.mcap", "--csv"});
  EXPECT_NE(r.code, 0);
  EXPECT_THAT(r.err, HasSubstr("not a haptex run's MCAP"));
}

}  // namespace
}  // namespace haptex::cli
