// One service process: output to its log, its own environment and process group, exit texts.
#include "launch/child_process.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <thread>

#include "tests/launch/launch_test_support.h"

namespace haptex::launch {
namespace {

using namespace std::chrono_literals;
using ::testing::HasSubstr;

void WaitExit(ChildProcess& child) {
  for (int i = 0; i < 3000 && !child.Poll(); ++i) std::this_thread::sleep_for(10ms);
  ASSERT_TRUE(child.exited());
}

TEST(LaunchChildProcessTest, OutputEnvironmentAndExitCode) {
  const std::string log = testing::FreshDir("child_output") + "/x.log";
  ChildProcess child({"/bin/sh", "-c", "echo out $GREETING; echo err >&2; exit 3"}, {"GREETING=hello"}, log);
  EXPECT_EQ(getpgid(child.pid()), child.pid());  // its own process group
  WaitExit(child);
  EXPECT_EQ(child.exit_text(), "exit 3");
  EXPECT_THAT(testing::ReadText(log), HasSubstr("out hello\nerr\n"));
}

TEST(LaunchChildProcessTest, RestartsAppendToTheLog) {
  const std::string log = testing::FreshDir("child_append") + "/x.log";
  for (const char* word : {"first", "second"}) {
    ChildProcess child({"/bin/echo", word}, {}, log);
    WaitExit(child);
  }
  EXPECT_EQ(testing::ReadText(log), "first\nsecond\n");
}

TEST(LaunchChildProcessTest, MissingExecutableExits127WithAMessage) {
  const std::string log = testing::FreshDir("child_missing") + "/x.log";
  ChildProcess child({"/no/such/haptex-service"}, {}, log);
  WaitExit(child);
  EXPECT_EQ(child.exit_text(), "exit 127");
  EXPECT_THAT(testing::ReadText(log), HasSubstr("cannot execute"));
}

TEST(LaunchChildProcessTest, SignalsAndCleanUp) {
  const std::string log = testing::FreshDir("child_signal") + "/x.log";
  pid_t pid = 0;
  {
    ChildProcess child({"/bin/sleep", "30"}, {}, log);
    pid = child.pid();
    EXPECT_FALSE(child.Poll());
    EXPECT_EQ(child.exit_text(), "running");
    child.Signal(SIGTERM);
    WaitExit(child);
    EXPECT_EQ(child.exit_text(), "signal 15");
  }
  {
    ChildProcess child({"/bin/sleep", "30"}, {}, log);
    pid = child.pid();
  }  // the destructor kills and reaps a child that still runs
  EXPECT_NE(kill(pid, 0), 0);
}

}  // namespace
}  // namespace haptex::launch
