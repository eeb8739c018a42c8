#include "libs/runtime/rt_event_log.h"

#include <gtest/gtest.h>
#include <spdlog/sinks/ostream_sink.h>
#include <spdlog/spdlog.h>

#include <sstream>
#include <thread>

#include "tests/support/allocation_counter.h"

namespace haptex::runtime {
namespace {

std::shared_ptr<spdlog::logger> StreamLogger(std::ostringstream* out) {
  auto sink = std::make_shared<spdlog::sinks::ostream_sink_mt>(*out);
  auto logger = std::make_shared<spdlog::logger>("rt_test", sink);
  logger->set_pattern("%l %v");
  logger->set_level(spdlog::level::trace);
  return logger;
}

TEST(RtEventLogTest, FlushWritesEventsInOrder) {
  RtEventLog log;
  log.Push(RtLogLevel::kWarn, "overrun", 3);
  log.Push(RtLogLevel::kError, "nan force", 1);
  std::ostringstream out;
  auto logger = StreamLogger(&out);
  EXPECT_EQ(log.Flush(*logger), 2u);
  EXPECT_EQ(out.str(), "warning overrun 3\nerror nan force 1\n");
  EXPECT_EQ(log.Flush(*logger), 0u);
}

TEST(RtEventLogTest, PushDoesNotAllocateAndFullRingCountsDrops) {
  if (!testing::AllocationCountingSupported()) GTEST_SKIP();
  RtEventLog log;
  testing::AllocationCounter counter;
  for (std::size_t i = 0; i < RtEventLog::kCapacity + 10; ++i) log.Push(RtLogLevel::kInfo, "tick", 1);
  EXPECT_EQ(counter.count(), 0);
  EXPECT_EQ(log.dropped(), 10u);
}

TEST(RtEventLogTest, FlusherThreadWritesWhatTheLoopPushed) {
  RtEventLog log;
  std::ostringstream out;
  {
    LogFlusher flusher(&log, StreamLogger(&out), 5);
    for (int i = 0; i < 10; ++i) log.Push(RtLogLevel::kInfo, "event", i);
  }  // the destructor flushes what is left
  std::string text = out.str();
  EXPECT_NE(text.find("info event 0"), std::string::npos);
  EXPECT_NE(text.find("info event 9"), std::string::npos);
}

}  // namespace
}  // namespace haptex::runtime
