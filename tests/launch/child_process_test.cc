// One service process: output to its log, its own environment and process group, exit texts.
#include "launch/child_process.h"

#include <fcntl.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <thread>

#include "libs/net/udp_endpoint.h"
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

// The file descriptors a running process holds, from /proc (read from outside the process).
std::set<int> OpenDescriptors(pid_t pid) {
  std::set<int> fds;
  for (const auto& entry : std::filesystem::directory_iterator("/proc/" + std::to_string(pid) + "/fd")) {
    fds.insert(std::stoi(entry.path().filename().string()));
  }
  return fds;
}

std::string Command(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/comm");
  std::string name;
  std::getline(in, name);
  return name;
}

TEST(LaunchChildProcessTest, ChildInheritsOnlyStandardStreams) {
  const std::string log = testing::FreshDir("child_fds") + "/x.log";
  // What a launcher holds when it starts a service: its UDP socket (close-on-exec) and, say, a
  // file opened without O_CLOEXEC.
  net::UdpEndpoint health("127.0.0.1:0");
  const int plain = open("/dev/null", O_RDONLY);
  ASSERT_GE(plain, 3);
  ChildProcess child({"/bin/sleep", "30"}, {}, log);
  // the fork holds the launcher's descriptors until it has closed them and run sleep
  for (int i = 0; i < 500 && Command(child.pid()) != "sleep"; ++i) std::this_thread::sleep_for(10ms);
  ASSERT_EQ(Command(child.pid()), "sleep");
  EXPECT_EQ(OpenDescriptors(child.pid()), (std::set<int>{0, 1, 2}));
  close(plain);
}

}  // namespace
}  // namespace haptex::launch
