#include "libs/runtime/logging.h"

#include <gtest/gtest.h>
#include <spdlog/spdlog.h>

#include <cstdio>
#include <fstream>
#include <sstream>

namespace haptex::runtime {
namespace {

TEST(LoggingTest, ParsesEveryLevelName) {
  EXPECT_EQ(ParseLogLevel("debug"), spdlog::level::debug);
  EXPECT_EQ(ParseLogLevel("warn"), spdlog::level::warn);
  EXPECT_EQ(ParseLogLevel("off"), spdlog::level::off);
}

TEST(LoggingTest, UnknownLevelListsTheValidOnes) {
  try {
    ParseLogLevel("verbose");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'verbose'"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("debug"), std::string::npos);
  }
}

TEST(LoggingTest, NamedLoggerWritesToFileAtItsLevel) {
  const std::string path = ::testing::TempDir() + "/haptex_logging_test.log";
  auto logger = SetupLogging("device_bridge", "info", path);
  EXPECT_EQ(logger->name(), "device_bridge");
  EXPECT_EQ(spdlog::default_logger()->name(), "device_bridge");
  logger->debug("hidden");
  logger->info("shown {}", 42);
  logger->flush();
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_NE(text.str().find("device_bridge info: shown 42"), std::string::npos) << text.str();
  EXPECT_EQ(text.str().find("hidden"), std::string::npos);
  // Setting up again (a restarted component) replaces the logger instead of failing.
  EXPECT_NO_THROW(SetupLogging("device_bridge", "warn"));
  std::remove(path.c_str());
}

}  // namespace
}  // namespace haptex::runtime

#include "haptex/v1/control.pb.h"
#include "libs/runtime/protobuf_log_capture.h"

namespace haptex::runtime {
namespace {

TEST(ProtobufLogCaptureTest, InvalidUtf8IsCountedNotPrinted) {
  CaptureProtobufLogs();
  const std::uint64_t before = CapturedProtobufLogCount();
  // Control.reason is a string field; 0xff is not UTF-8.
  v1::Control control;
  const std::string wire = std::string("\x1a\x02\xff\xfe", 4);
  ::testing::internal::CaptureStderr();
  EXPECT_FALSE(control.ParseFromString(wire));
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
  EXPECT_GT(CapturedProtobufLogCount(), before);
}

}  // namespace
}  // namespace haptex::runtime
