// haptex launch as a user runs it: the device bridge, the mock controller, tactile and the mock
// pins as real processes over loopback UDP (global_sim and local_contact are --skip'ped: not
// built yet). Checks the run folder, a kill -9 of each service (restarted, in the summary), and
// Ctrl-C (zero force first, exit code 0). Assertions are about behaviour, not timing, so a loaded
// machine only makes them slower.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sched.h>
#include <signal.h>

#include <cmath>
#include <filesystem>
#include <regex>
#include <sstream>
#include <thread>

#include "launch/recording.h"
#include "tests/launch/launch_test_support.h"
#include "tests/support/subprocess.h"

namespace haptex::launch {
namespace {

using namespace std::chrono_literals;
using ::testing::HasSubstr;

// A scene whose services all exist: a rubbing user on the mock controller, tactile on the mock
// pins. The fabric is the database's denim plus surface values for the tactile surface (test
// values: the database has no weave pitches yet).
std::string SceneText(const std::string& name) {
  std::string fabric =
      testing::ReadText(haptex::testing::SourceDir() + "/data/fabrics/wang2011_black_denim_11oz.textproto");
  const std::string weave = "weave {\n  pattern: PATTERN_TWILL\n}";
  const auto at = fabric.find(weave);
  if (at != std::string::npos) {
    fabric.replace(at, weave.size(),
                   "weave { pattern: PATTERN_TWILL warp_pitch_mm: 0.6 weft_pitch_mm: 0.7 yarn_diameter_mm: 0.4 }\n"
                   "surface { smd_um: 5 }");
  }
  return "name: \"" + name + "\"\nfabric { inline_fabric {\n" + fabric +
         "\n} }\n"
         "fingers { finger: FINGER_THUMB }\nfingers { finger: FINGER_INDEX }\n"
         "device { mock { user { kind: KIND_RUB } } }\n"
         "tactile { enabled: true mock_display: true }\n";
}

class LaunchSystemTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing::FreshDir(::testing::UnitTest::GetInstance()->current_test_info()->name());
    scene_ = dir_ + "/scene.textproto";
    testing::WriteText(scene_, SceneText("system_test"));
    run_ = dir_ + "/run";
  }

  std::unique_ptr<haptex::testing::Subprocess> Launch(const std::string& duration,
                                                      const std::vector<std::string>& extra = {}) {
    std::vector<std::string> argv{haptex::testing::BuildDir() + "/cli/haptex",
                                  "launch",
                                  scene_,
                                  "--skip",
                                  "global_sim",
                                  "--skip",
                                  "local_contact",
                                  "--duration",
                                  duration,
                                  "--out",
                                  run_};
    argv.insert(argv.end(), extra.begin(), extra.end());
    return std::make_unique<haptex::testing::Subprocess>(argv);
  }

  static std::string WaitFor(haptex::testing::Subprocess& p, const std::string& pattern) {
    return testing::WaitForOutput(p, pattern);
  }
  std::vector<testing::ForceRow> ForceRows() const { return testing::MockForceRows(run_ + "/mock_grab_forces.csv"); }

  std::string dir_, scene_, run_;
};

TEST_F(LaunchSystemTest, RunFolderHasSummaryRecordingsLogsAndPlots) {
  auto launcher = Launch("2");
  const auto code = launcher->WaitFor(120s);
  ASSERT_TRUE(code.has_value()) << launcher->Stdout();
  EXPECT_EQ(*code, 0) << launcher->Stdout() << launcher->Stderr();
  EXPECT_THAT(launcher->Stdout(), HasSubstr("skip   global_sim"));
  EXPECT_THAT(launcher->Stdout(), HasSubstr("start  mock_grab: the scene asks for the mock controller"));

  const std::string summary = testing::ReadText(run_ + "/summary.json");
  EXPECT_THAT(summary, HasSubstr(R"("end_reason":"duration")"));
  EXPECT_THAT(summary, HasSubstr(R"("exit_code":0)"));
  for (const std::string name : {"device_bridge", "mock_grab", "tactile", "mock_pins"}) {
    EXPECT_THAT(summary, ::testing::ContainsRegex("\"name\":\"" + name +
                                                  "\",\"reason\":[^}]*\"started_here\":true,\"health_received\":true"))
        << name;
    EXPECT_THAT(summary, HasSubstr("\"exit\":\"exit 0\"")) << name;
    // logs: the service's own lines
    EXPECT_THAT(testing::ReadText(run_ + "/logs/" + name + ".log"), HasSubstr(name + " receiving on")) << name;
    // recordings: non-empty, whole, and Health from that service
    const Recording r = ReadRecording(run_ + "/recordings/" + name + ".pb");
    EXPECT_GT(r.envelopes.size(), 0u) << name;
    EXPECT_FALSE(r.truncated) << name;
    EXPECT_EQ(r.unparsable, 0u) << name;
    bool health = false;
    for (const auto& e : r.envelopes) health |= e.has_health() && e.health().service() == name && e.sender() == name;
    EXPECT_TRUE(health) << name;
  }
  EXPECT_THAT(summary, HasSubstr(R"("period_p99_us")"));
  EXPECT_THAT(summary, HasSubstr(R"("motion_to_force":{"service":"device_bridge")"));
  EXPECT_THAT(summary, ::testing::ContainsRegex(R"("status_frames_accepted":[1-9])"));
  EXPECT_THAT(summary, HasSubstr(R"("drops":{)"));
  EXPECT_THAT(summary, HasSubstr(R"("launcher_received":{"accepted":)"));  // accepted Health
  EXPECT_THAT(summary, HasSubstr(R"("contact_states":{"note")"));
  EXPECT_THAT(summary, HasSubstr(R"("mock_controller_commanded":{"thumb":{"samples":)"));
  EXPECT_THAT(summary, HasSubstr(R"j("name":"global_sim","why":"--skip (started elsewhere)")j"));
  EXPECT_THAT(summary, HasSubstr(R"("restarts":[])"));
  EXPECT_THAT(summary, HasSubstr(R"("errors":[])"));
  EXPECT_THAT(summary, HasSubstr(R"("friction_ratio":{"skipped":)"));
  EXPECT_TRUE(std::filesystem::exists(run_ + "/plots/forces.png"));
  EXPECT_TRUE(std::filesystem::exists(run_ + "/plots/loop_periods.png"));
  EXPECT_TRUE(std::filesystem::exists(run_ + "/commands.txt"));
  EXPECT_FALSE(ForceRows().empty());
  // run.mcap: the recordings as one MCAP file, counted in the summary
  EXPECT_THAT(summary, ::testing::ContainsRegex(R"("recording":\{"mcap":"run.mcap","messages":[1-9][^}]*)"
                                                R"("channels":\{[^}]*"/device_bridge/finger_states":[1-9])"));
  EXPECT_THAT(launcher->Stdout(), HasSubstr("/run.mcap: "));

  // haptex trace export RUN --csv (reads run.mcap)
  haptex::testing::Subprocess exporter({haptex::testing::BuildDir() + "/cli/haptex", "trace", "export", run_, "--csv"});
  EXPECT_EQ(exporter.WaitFor(60s), 0) << exporter.Stderr();
  EXPECT_THAT(exporter.Stdout(), HasSubstr("run.mcap /device_bridge/*: "));
  EXPECT_THAT(testing::ReadText(run_ + "/csv/health.csv"), HasSubstr("t_s,sender,state"));
  EXPECT_THAT(testing::ReadText(run_ + "/csv/health.csv"), HasSubstr(",device_bridge,STATE_"));
  EXPECT_TRUE(std::filesystem::exists(run_ + "/csv/health_counters.csv"));
}

// --rt-priority: every service runs SCHED_FIFO (where the kernel allows it; CI runs as root), and
// the run still ends cleanly. In pinch_stretch it cut local_contact's overruns from 1.5-4 % to 0.1 %.
TEST_F(LaunchSystemTest, RtPriorityRunsEveryServiceSchedFifo) {
  auto launcher = Launch("0", {"--rt-priority", "10"});
  WaitFor(*launcher, "real-time(:| refused)");
  if (launcher->Stdout().find("real-time refused") != std::string::npos) {
    GTEST_SKIP() << "SCHED_FIFO not permitted here: " << launcher->Stdout();
  }
  // rate-monotonic: the 5 kHz loops at the launcher's priority, the slower ones below (this run
  // skips local_contact and global_sim; service_table_test checks their ranks)
  for (const auto& [service, priority] : std::vector<std::pair<std::string, int>>{
           {"device_bridge", 10}, {"mock_grab", 10}, {"tactile", 8}, {"mock_pins", 8}}) {
    const int pid = testing::RunningServicePid(*launcher, service);
    ASSERT_GT(pid, 0) << service;
    EXPECT_EQ(sched_getscheduler(pid), SCHED_FIFO) << service;
    sched_param param{};
    ASSERT_EQ(sched_getparam(pid, &param), 0) << service;
    EXPECT_EQ(param.sched_priority, priority) << service;
  }
  launcher->Signal(SIGINT);
  const auto code = launcher->WaitFor(90s);
  ASSERT_TRUE(code.has_value()) << launcher->Stdout();
  EXPECT_EQ(*code, 0) << launcher->Stdout() << launcher->Stderr();
}

TEST(LaunchCommandLineTest, RtPriorityOutOfRangeIsRefused) {
  haptex::testing::Subprocess p({haptex::testing::BuildDir() + "/cli/haptex", "launch",
                                 haptex::testing::SourceDir() + "/launch/scenes/demo.textproto", "--dry-run",
                                 "--rt-priority", "100"});
  const auto code = p.WaitFor(60s);
  ASSERT_TRUE(code.has_value());
  EXPECT_NE(*code, 0);
  EXPECT_THAT(p.Stderr() + p.Stdout(), HasSubstr("--rt-priority"));
}

TEST_F(LaunchSystemTest, CtrlCStopsWithZeroForceAndExitCodeZero) {
  auto launcher = Launch("0");
  WaitFor(*launcher, "running \\(until Ctrl-C\\)");
  std::this_thread::sleep_for(500ms);
  launcher->Signal(SIGINT);
  const auto code = launcher->WaitFor(90s);
  ASSERT_TRUE(code.has_value()) << launcher->Stdout();
  EXPECT_EQ(*code, 0) << launcher->Stdout() << launcher->Stderr();
  const std::string out = launcher->Stdout();
  // zero force first, the bridge after the other haptex services, its controller after it
  const auto zero = out.find("device_bridge: zero_force (stopping)");
  const auto pins = out.find("mock_pins: stopped");
  const auto tactile = out.find("tactile: stopped");
  const auto bridge = out.find("device_bridge: stopped");
  const auto mock = out.find("mock_grab: stopped");
  ASSERT_NE(zero, std::string::npos) << out;
  ASSERT_NE(bridge, std::string::npos) << out;
  ASSERT_NE(mock, std::string::npos) << out;
  EXPECT_LT(zero, tactile);
  EXPECT_LT(tactile, bridge);
  EXPECT_LT(pins, bridge);
  EXPECT_LT(bridge, mock);
  EXPECT_THAT(testing::ReadText(run_ + "/summary.json"), HasSubstr(R"("end_reason":"interrupted")"));
  // the force log's tail: zero force on both fingers
  const auto rows = ForceRows();
  ASSERT_GT(rows.size(), 100u);
  for (std::size_t i = rows.size() - 100; i < rows.size(); ++i) {
    EXPECT_EQ(rows[i].thumb_N, 0.0) << "row " << i;
    EXPECT_EQ(rows[i].index_N, 0.0) << "row " << i;
  }
}

// A run folder that cannot take the run's record (a full disk, a folder in the way) is an error
// of the run with the system's reason, never an exit 0 with an empty or missing summary.json.
TEST_F(LaunchSystemTest, ASummaryThatCannotBeWrittenFailsTheRunWithTheReason) {
  std::filesystem::create_directories(run_ + "/summary.json");
  auto launcher = Launch("1", {"--no-plots"});
  const auto code = launcher->WaitFor(120s);
  ASSERT_TRUE(code.has_value()) << launcher->Stdout();
  EXPECT_EQ(*code, 1) << launcher->Stdout() << launcher->Stderr();
  EXPECT_THAT(launcher->Stdout(), HasSubstr("error: cannot write " + run_ + "/summary.json: Is a directory"));
  EXPECT_THAT(launcher->Stdout(), HasSubstr("no summary.json (the error above)"));
  // the services ran and stopped as ever, the device at zero force
  EXPECT_THAT(launcher->Stdout(), HasSubstr("device_bridge: stopped (exit 0"));
  const auto rows = ForceRows();
  ASSERT_FALSE(rows.empty());
  EXPECT_EQ(rows.back().thumb_N, 0.0);
  EXPECT_EQ(rows.back().index_N, 0.0);
}

// A recording the disk refuses: mock_pins records into /dev/full (its recording is a link there,
// as a full disk fails every write). The run goes on, the launcher names the service and fails the
// run, and the device file is not read back as a recording (it would never end).
TEST_F(LaunchSystemTest, ARecordingTheDiskRefusesFailsTheRunAndNamesTheService) {
  std::filesystem::create_directories(run_ + "/recordings");
  std::filesystem::create_symlink("/dev/full", run_ + "/recordings/mock_pins.pb");
  auto launcher = Launch("2", {"--no-plots"});
  const auto code = launcher->WaitFor(120s);
  ASSERT_TRUE(code.has_value()) << launcher->Stdout();
  EXPECT_EQ(*code, 1) << launcher->Stdout() << launcher->Stderr();
  EXPECT_THAT(launcher->Stdout(), ::testing::ContainsRegex("error: mock_pins: [1-9][0-9]* recording writes failed "
                                                           "\\(a full disk\\?\\): .*/recordings is incomplete"));
  const std::string summary = testing::ReadText(run_ + "/summary.json");
  EXPECT_THAT(summary, HasSubstr("recording writes failed"));
  EXPECT_THAT(summary, ::testing::Not(HasSubstr("\"mock_pins.pb\"")));
  // the others recorded as ever, and the device ended at zero force
  EXPECT_GT(ReadRecording(run_ + "/recordings/device_bridge.pb").envelopes.size(), 0u);
  EXPECT_THROW(ReadRecording(run_ + "/recordings/mock_pins.pb"), std::runtime_error);
  const auto rows = ForceRows();
  ASSERT_FALSE(rows.empty());
  EXPECT_EQ(rows.back().thumb_N, 0.0);
}

TEST_F(LaunchSystemTest, ARunFolderThatCannotTakeItsFirstFileStartsNothing) {
  std::filesystem::create_directories(run_ + "/commands.txt");
  auto launcher = Launch("1", {"--no-plots"});
  const auto code = launcher->WaitFor(60s);
  ASSERT_TRUE(code.has_value()) << launcher->Stdout();
  EXPECT_EQ(*code, 1) << launcher->Stdout() << launcher->Stderr();
  EXPECT_THAT(launcher->Stderr(), HasSubstr("haptex: cannot write " + run_ + "/commands.txt: Is a directory"));
  EXPECT_THAT(launcher->Stdout(), ::testing::Not(HasSubstr(": started (pid")));
  EXPECT_FALSE(std::filesystem::exists(run_ + "/mock_grab_forces.csv"));
}

class LaunchKillTest : public LaunchSystemTest, public ::testing::WithParamInterface<const char*> {};

TEST_P(LaunchKillTest, KilledServiceIsRestartedAndInTheSummary) {
  const std::string name = GetParam();
  auto launcher = Launch("0");
  WaitFor(*launcher, "running \\(until Ctrl-C\\)");
  const int pid = std::stoi(WaitFor(*launcher, name + ": started \\(pid ([0-9]+)"));
  ASSERT_GT(pid, 1);
  const auto killed_at = std::chrono::steady_clock::now();
  ASSERT_EQ(kill(pid, SIGKILL), 0);
  const std::string after = WaitFor(*launcher, name + ": restarted \\(after signal 9, ready ([0-9.]+) s after it died");
  std::cout << name << " killed: ready again " << after
            << " s after it died (launcher's clock); seen by the test after "
            << std::chrono::duration<double>(std::chrono::steady_clock::now() - killed_at).count() << " s\n";
  if (name != "device_bridge") {
    // the device was held at zero force while it restarted
    EXPECT_THAT(launcher->Stdout(), HasSubstr("device_bridge: zero_force (restarting " + name + ")"));
    WaitFor(*launcher, "device_bridge: enable_force \\(" + name + " is back\\)");
  }
  std::this_thread::sleep_for(300ms);
  launcher->Signal(SIGINT);
  const auto code = launcher->WaitFor(90s);
  ASSERT_TRUE(code.has_value());
  EXPECT_EQ(*code, 0) << launcher->Stdout();
  const std::string summary = testing::ReadText(run_ + "/summary.json");
  EXPECT_THAT(summary, HasSubstr("\"restarts\":[{\"t_s\":"));
  EXPECT_THAT(summary, ::testing::ContainsRegex("\"service\":\"" + name + "\",\"detail\":\"after signal 9"));
  EXPECT_THAT(summary, ::testing::ContainsRegex("\"name\":\"" + name + "\",[^}]*\"restarts\":1,"));
  EXPECT_THAT(summary, HasSubstr("\"kind\":\"died\",\"detail\":\"signal 9\""));
  // the killed instance's recording is kept (whole records only); the restarted one writes beside it
  EXPECT_EQ(ReadRecording(run_ + "/recordings/" + name + ".pb").unparsable, 0u);
  const Recording r = ReadRecording(run_ + "/recordings/" + name + ".restart1.pb");
  EXPECT_GT(r.envelopes.size(), 0u);
  EXPECT_EQ(r.unparsable, 0u);
  EXPECT_FALSE(r.truncated);
  // what the fingers felt: zero after the kill (a dead bridge: the controller's own host watchdog)
  const auto rows = ForceRows();
  ASSERT_FALSE(rows.empty());
  EXPECT_EQ(rows.back().thumb_N, 0.0);
  EXPECT_EQ(rows.back().index_N, 0.0);
}

INSTANTIATE_TEST_SUITE_P(EachService, LaunchKillTest,
                         ::testing::Values("device_bridge", "mock_grab", "tactile", "mock_pins"),
                         [](const auto& param_info) { return std::string(param_info.param); });

}  // namespace
}  // namespace haptex::launch
