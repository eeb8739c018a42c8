// haptex launch --stall: the launcher pauses services on purpose (SIGSTOP, then SIGCONT) in a real
// run of pinch_stretch, as a host that pauses would. Asserted is what holds whatever the host does:
// the run ends by its duration with exit code 0, summary.json lists each stall as carried out and
// paused at least as long as planned (a stopped process cannot run less), no service was taken for
// dead or silent and restarted, and every service stopped on its SHUTDOWN. No timing figures and no
// forces: the machine is shared and noisy.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "tests/launch/launch_test_support.h"
#include "tests/support/subprocess.h"
#include "tests/support/summary_json.h"

namespace haptex::launch {
namespace {

using namespace std::chrono_literals;
using ::testing::HasSubstr;
namespace pb = google::protobuf;

using haptex::testing::At;
using haptex::testing::Number;
using haptex::testing::ParseJson;
using haptex::testing::ServiceSummary;

constexpr const char* kServices[] = {"device_bridge", "mock_grab", "global_sim", "local_contact"};

class LaunchStallTest : public ::testing::Test {
 protected:
  void SetUp() override {
    run_ = testing::FreshDir(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "/run";
  }

  // pinch_stretch for `duration`, with `extra` options; returns its summary.json, parsed.
  pb::Struct Run(const std::string& duration, const std::vector<std::string>& extra) {
    std::vector<std::string> argv{haptex::testing::BuildDir() + "/cli/haptex",
                                  "launch",
                                  testing::ShippedScenePath("pinch_stretch"),
                                  "--duration",
                                  duration,
                                  "--out",
                                  run_,
                                  "--no-plots"};
    argv.insert(argv.end(), extra.begin(), extra.end());
    haptex::testing::Subprocess launcher(argv);
    const auto code = launcher.WaitFor(180s);
    out_ = launcher.Stdout();
    EXPECT_TRUE(code.has_value()) << out_;
    EXPECT_EQ(code.value_or(-1), 0) << out_ << launcher.Stderr();
    return ParseJson(testing::ReadText(run_ + "/summary.json"));
  }

  // Every service ran once, was never restarted, and ended on its SHUTDOWN with exit code 0.
  void ExpectNoRestartAndCleanStops(const pb::Struct& summary) const {
    EXPECT_EQ(At(summary, "end_reason").string_value(), "duration");
    EXPECT_EQ(At(summary, "restarts").list_value().values_size(), 0) << out_;
    EXPECT_THAT(out_, ::testing::Not(HasSubstr(": died (")));
    for (const std::string name : kServices) {
      const pb::Struct service = ServiceSummary(summary, name);
      EXPECT_EQ(Number(service, "restarts"), 0.0) << name;
      EXPECT_EQ(At(service, "pids").list_value().values_size(), 1) << name;
      EXPECT_EQ(At(service, "exit").string_value(), "exit 0") << name;
      EXPECT_THAT(out_, HasSubstr(name + ": stopped (exit 0 after SHUTDOWN)")) << name;
    }
  }

  std::string run_, out_;
};

// The stall's entry: carried out here, started no earlier than planned, paused no less.
pb::Struct ExpectCarriedOut(const pb::Value& entry, const std::string& target, double at_s, double duration_s,
                            int processes) {
  const pb::Struct& stall = entry.struct_value();
  SCOPED_TRACE(target);
  EXPECT_EQ(At(stall, "target").string_value(), target);
  EXPECT_EQ(At(stall, "source").string_value(), "--stall");
  EXPECT_TRUE(At(stall, "started_here").bool_value());
  EXPECT_EQ(Number(stall, "at_s"), at_s);
  EXPECT_EQ(Number(stall, "duration_s"), duration_s);
  EXPECT_EQ(At(stall, "started_s").kind_case(), pb::Value::kNumberValue);
  EXPECT_GE(Number(stall, "started_s"), at_s);
  EXPECT_EQ(At(stall, "paused_s").kind_case(), pb::Value::kNumberValue);
  EXPECT_GE(Number(stall, "paused_s"), duration_s);
  EXPECT_EQ(At(stall, "pids").list_value().values_size(), processes);
  EXPECT_EQ(stall.fields().count("note"), 0u) << "cut short or missed";
  return stall;
}

TEST_F(LaunchStallTest, AServiceAndEveryServicePausedOnPurposeAndTheRunEndsCleanly) {
  const pb::Struct summary = Run("3", {"--stall", "local_contact@1.5s:100ms", "--stall", "all@2s:30ms"});
  EXPECT_THAT(out_, HasSubstr("stall local_contact@1.5s:100ms (--stall): SIGSTOP to local_contact"));
  EXPECT_THAT(out_, HasSubstr("stall all@2s:30ms (--stall): SIGSTOP to every service started here but the viewer "
                              "(device_bridge, mock_grab, global_sim, local_contact)"));
  const pb::ListValue& stalls = At(summary, "stalls").list_value();
  ASSERT_EQ(stalls.values_size(), 2) << out_;
  const pb::Struct one = ExpectCarriedOut(stalls.values(0), "local_contact", 1.5, 0.1, 1);
  ExpectCarriedOut(stalls.values(1), "all", 2.0, 0.03, 4);
  // the process it paused is local_contact's
  const pb::Struct contact = ServiceSummary(summary, "local_contact");
  ASSERT_EQ(At(contact, "pids").list_value().values_size(), 1);
  EXPECT_EQ(At(one, "pids").list_value().values(0).number_value(),
            Number(At(contact, "pids").list_value().values(0).struct_value(), "pid"));
  // each stall is an event, at its start and at its end, planned and actual
  EXPECT_THAT(out_, ::testing::ContainsRegex("local_contact: stall \\(planned at 1.500 s for 0.100 s; paused at "
                                             "[0-9.]+ s \\(pid [0-9]+\\)\\)"));
  EXPECT_THAT(out_, ::testing::ContainsRegex("local_contact: stall_end \\(planned at 1.500 s for 0.100 s; paused at "
                                             "[0-9.]+ s for [0-9.]+ s\\)"));
  EXPECT_THAT(out_, ::testing::ContainsRegex("all: stall_end \\(planned at 2.000 s for 0.030 s; paused at "
                                             "[0-9.]+ s for [0-9.]+ s\\)"));
  ExpectNoRestartAndCleanStops(summary);
}

// A stall longer than --silent-after: the paused service is not taken for silent and restarted.
TEST_F(LaunchStallTest, AStallLongerThanTheSilenceThresholdIsNoSilence) {
  const pb::Struct summary = Run("4", {"--silent-after", "1", "--stall", "global_sim@0.5s:2500ms"});
  const pb::ListValue& stalls = At(summary, "stalls").list_value();
  ASSERT_EQ(stalls.values_size(), 1) << out_;
  ExpectCarriedOut(stalls.values(0), "global_sim", 0.5, 2.5, 1);
  EXPECT_THAT(out_, ::testing::Not(HasSubstr("silent for")));
  ExpectNoRestartAndCleanStops(summary);
}

}  // namespace
}  // namespace haptex::launch
