// haptex launch with an impaired link: the launcher puts a `haptex relay` between the bridge and
// local_contact (pinch_stretch's services as real processes over loopback), the run completes,
// the relay's report is in the run folder and summary.json says what was asked and what the
// relay did; a relay that dies is an error of the run. Assertions are about behaviour with
// generous bands, not timing, so a loaded 2-core machine only makes them slower.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <signal.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>

#include "launch/relay_report_reader.h"
#include "libs/base/clock.h"
#include "libs/device/force_safety.h"
#include "tests/launch/launch_test_support.h"
#include "tests/support/subprocess.h"
#include "tests/support/summary_json.h"

namespace haptex::launch {
namespace {

using namespace std::chrono_literals;
using ::testing::HasSubstr;
namespace pb = google::protobuf;

constexpr char kLink[] = "device_bridge-local_contact";

using haptex::testing::At;
using haptex::testing::Number;
using haptex::testing::Object;
using haptex::testing::ParseJson;

// The link's entry in summary.json's network section.
pb::Struct NetworkLink(const pb::Struct& summary) {
  const pb::Value& links = At(Object(summary, "network"), "links");
  EXPECT_EQ(links.list_value().values_size(), 1);
  return links.list_value().values_size() > 0 ? links.list_value().values(0).struct_value() : pb::Struct();
}

class LaunchImpairTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing::FreshDir(::testing::UnitTest::GetInstance()->current_test_info()->name());
    run_ = dir_ + "/run";
  }

  std::unique_ptr<haptex::testing::Subprocess> Launch(const std::string& scene, const std::string& duration,
                                                      const std::vector<std::string>& extra = {}) {
    std::vector<std::string> argv{haptex::testing::BuildDir() + "/cli/haptex",
                                  "launch",
                                  scene,
                                  "--duration",
                                  duration,
                                  "--out",
                                  run_,
                                  "--no-plots"};
    argv.insert(argv.end(), extra.begin(), extra.end());
    return std::make_unique<haptex::testing::Subprocess>(argv);
  }

  // The tail of the mock controller's force log: zero force on both fingers.
  void ExpectEndsAtZeroForce() const {
    const auto rows = testing::MockForceRows(run_ + "/mock_grab_forces.csv");
    ASSERT_GT(rows.size(), 100u);
    for (std::size_t i = rows.size() - 50; i < rows.size(); ++i) {
      EXPECT_EQ(rows[i].thumb_N, 0.0) << "row " << i;
      EXPECT_EQ(rows[i].index_N, 0.0) << "row " << i;
    }
  }

  std::string dir_, run_;
};

// One direction of what the relay achieved: every datagram accounted for, the loss near what was
// asked, the delay near half the round trip.
void ExpectAchieved(const pb::Struct& direction, const std::string& name) {
  SCOPED_TRACE(name);
  const double received = Number(direction, "received");
  const double forwarded = Number(direction, "forwarded");
  const double duplicated = Number(direction, "duplicated");
  const double dropped_total = Number(direction, "dropped_total");
  const double lost = Number(Object(direction, "dropped"), "loss");
  // FingerStates and ForceModels at 1 kHz for seconds; a starved machine sends fewer
  EXPECT_GT(received, 500);
  EXPECT_EQ(forwarded + dropped_total, received + duplicated);
  EXPECT_EQ(duplicated, 0);
  EXPECT_EQ(Number(direction, "in_flight"), 0);
  EXPECT_LE(lost, dropped_total);
  // loss 0.02 per datagram: within 5 binomial standard deviations
  const double sd = std::sqrt(received * 0.02 * 0.98);
  EXPECT_NEAR(lost, 0.02 * received, 5 * sd);
  const pb::Struct& delay = Object(direction, "delay_ms");
  EXPECT_GE(Number(delay, "p50"), 10.0 - 0.01);  // never early (less the receive stamp's conversion)
  EXPECT_LE(Number(delay, "p50"), 10.0 + 15.0);  // a busy relay sends late, not this late at the median
}

TEST_F(LaunchImpairTest, ImpairedLinkRunsThroughARelayAndIsReported) {
  auto launcher = Launch(testing::ShippedScenePath("pinch_stretch"), "4",
                         {"--impair", std::string(kLink) + ":rtt_ms=20,loss=0.02,seed=1"});
  const auto code = launcher->WaitFor(180s);
  ASSERT_TRUE(code.has_value()) << launcher->Stdout();
  EXPECT_EQ(*code, 0) << launcher->Stdout() << launcher->Stderr();
  const std::string out = launcher->Stdout();
  EXPECT_THAT(out, HasSubstr("impair device_bridge-local_contact (--impair): rtt_ms=20,loss=0.02,seed=1; through a "
                             "relay on local"));
  // the relay starts before the services and stops after them
  const auto relay_started = out.find("relay device_bridge-local_contact: started");
  const auto bridge_started = out.find("device_bridge: started");
  const auto mock_stopped = out.find("mock_grab: stopped");
  const auto relay_stopped = out.find("relay device_bridge-local_contact: stopped (exit 0 after SIGTERM)");
  ASSERT_NE(relay_started, std::string::npos) << out;
  ASSERT_NE(relay_stopped, std::string::npos) << out;
  EXPECT_LT(relay_started, bridge_started);
  EXPECT_LT(mock_stopped, relay_stopped);
  EXPECT_THAT(out, HasSubstr("network device_bridge-local_contact: forward received "));

  // the relay's own report, written on SIGTERM
  const std::string report_path = run_ + "/network/device_bridge-local_contact.json";
  ASSERT_TRUE(std::filesystem::exists(report_path)) << out;
  const RelayResult report = ReadRelayReport(report_path);
  EXPECT_GT(report.forward.received, 0u);
  EXPECT_THAT(testing::ReadText(run_ + "/logs/relay_device_bridge-local_contact.log"),
              HasSubstr("relay: listening on"));
  EXPECT_THAT(testing::ReadText(run_ + "/commands.txt"), HasSubstr("relay device_bridge-local_contact (local): "));

  const pb::Struct summary = ParseJson(testing::ReadText(run_ + "/summary.json"));
  EXPECT_EQ(At(summary, "end_reason").string_value(), "duration");
  EXPECT_EQ(At(summary, "errors").list_value().values_size(), 0) << testing::ReadText(run_ + "/summary.json");
  const pb::Struct link = NetworkLink(summary);
  EXPECT_EQ(At(link, "link").string_value(), kLink);
  EXPECT_EQ(At(link, "source").string_value(), "--impair");
  EXPECT_EQ(At(link, "exit").string_value(), "exit 0");
  EXPECT_EQ(At(link, "report").string_value(), report_path);

  // asked: the round trip split in two, the loss and the seeds
  const pb::Struct& asked = Object(link, "asked");
  EXPECT_EQ(At(asked, "text").string_value(), "rtt_ms=20,loss=0.02,seed=1");
  EXPECT_EQ(Number(asked, "rtt_ms"), 20.0);
  for (const char* direction : {"forward", "back"}) {
    EXPECT_EQ(Number(Object(asked, direction), "delay_ms"), 10.0) << direction;
    EXPECT_EQ(Number(Object(asked, direction), "loss"), 0.02) << direction;
  }
  EXPECT_EQ(Number(Object(asked, "forward"), "seed"), 1.0);
  EXPECT_EQ(Number(Object(asked, "back"), "seed"), 2.0);

  // achieved: the same numbers as the relay's report, consistent with what was asked
  const pb::Struct& achieved = Object(link, "achieved");
  EXPECT_EQ(Number(Object(achieved, "forward"), "received"), static_cast<double>(report.forward.received));
  ExpectAchieved(Object(achieved, "forward"), "forward: FingerStates");
  ExpectAchieved(Object(achieved, "back"), "back: ForceModels");

  ExpectEndsAtZeroForce();
}

TEST_F(LaunchImpairTest, ARelayThatDiesIsAnErrorOfTheRun) {
  // the same link from the scene's network section
  const std::string scene = dir_ + "/scene.textproto";
  testing::WriteText(scene,
                     testing::ReadText(testing::ShippedScenePath("pinch_stretch")) +
                         "network { links { a: SERVICE_DEVICE_BRIDGE b: SERVICE_LOCAL_CONTACT delay_ms: 2 } }\n");
  auto launcher = Launch(scene, "0");
  testing::WaitForOutput(*launcher, "running \\(until Ctrl-C\\)");
  EXPECT_THAT(launcher->Stdout(), HasSubstr("impair device_bridge-local_contact (scene): delay_ms=2"));
  const std::string pid =
      testing::WaitForOutput(*launcher, "relay device_bridge-local_contact: started \\(pid ([0-9]+)");
  ASSERT_FALSE(pid.empty());
  ASSERT_EQ(kill(std::stoi(pid), SIGKILL), 0);
  testing::WaitForOutput(*launcher, "relay device_bridge-local_contact: died \\(signal 9\\)");
  std::this_thread::sleep_for(300ms);
  launcher->Signal(SIGINT);
  const auto code = launcher->WaitFor(90s);
  ASSERT_TRUE(code.has_value()) << launcher->Stdout();
  EXPECT_EQ(*code, 1) << launcher->Stdout() << launcher->Stderr();

  const std::string text = testing::ReadText(run_ + "/summary.json");
  EXPECT_THAT(text, HasSubstr("relay device_bridge-local_contact died (signal 9): the link is cut from then on"));
  EXPECT_THAT(text, HasSubstr(R"("service":"relay device_bridge-local_contact","kind":"died","detail":"signal 9")"));
  const pb::Struct link = NetworkLink(ParseJson(text));
  EXPECT_EQ(At(link, "source").string_value(), "scene");
  EXPECT_EQ(At(link, "exit").string_value(), "signal 9");
  EXPECT_THAT(At(Object(link, "achieved"), "note").string_value(), HasSubstr("relay report"));  // none, or cut
  // the services were stopped as ever, the device at zero force
  EXPECT_THAT(launcher->Stdout(), HasSubstr("device_bridge: stopped (exit 0"));
  ExpectEndsAtZeroForce();
}

// The bridge's entry in summary.json.
pb::Struct BridgeSummary(const pb::Struct& summary) {
  return haptex::testing::ServiceSummary(summary, "device_bridge");
}

// The force both fingers were commanded, by seconds since the mock's first row.
struct Felt {
  std::vector<double> t_s, force_N;
};
Felt ReadFelt(const std::string& run) {
  Felt felt;
  const auto rows = testing::MockForceRows(run + "/mock_grab_forces.csv");
  for (const auto& r : rows) {
    felt.t_s.push_back((r.t_ns - rows.front().t_ns) * 1e-9);
    felt.force_N.push_back(std::max(r.thumb_N, r.index_N));
  }
  return felt;
}

// What a campus link did to the pinch before the link was made delay-robust: an oscillation between 0
// and 10 N with peaks of 14-17 N. Through a 50 ms, 5 % lossy relay on both of the bridge's links the
// pinch holds, its peak stays near the squeeze, nothing is reported slow and the run ends at zero.
TEST_F(LaunchImpairTest, APinchThroughA50MsLossyLinkHoldsAndEndsAtZero) {
  const std::string each = ":rtt_ms=50,jitter_ms=2,loss=0.05,seed=";
  auto launcher =
      Launch(testing::ShippedScenePath("pinch_stretch"), "7",
             {"--impair", std::string(kLink) + each + "1", "--impair", "device_bridge-global_sim" + each + "3"});
  const auto code = launcher->WaitFor(180s);
  ASSERT_TRUE(code.has_value()) << launcher->Stdout();
  EXPECT_EQ(*code, 0) << launcher->Stdout() << launcher->Stderr();

  const Felt felt = ReadFelt(run_);
  std::vector<double> held;
  double peak_N = 0.0;
  for (std::size_t i = 0; i < felt.t_s.size(); ++i) {
    peak_N = std::max(peak_N, felt.force_N[i]);
    if (felt.t_s[i] >= 4.0 && felt.t_s[i] <= 6.5) held.push_back(felt.force_N[i]);
  }
  ASSERT_FALSE(held.empty());
  std::vector<double> sorted = held;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  const double median_N = sorted[sorted.size() / 2];
  const auto steady =
      std::count_if(held.begin(), held.end(), [&](double f) { return std::abs(f - median_N) <= 0.3 * median_N; });
  // how firmly and steadily it holds is the in-process test's (DelayedPinchTest): here it is reported
  std::cout << "[measured] 50 ms / 5 %: held median " << median_N << " N, within 30 % for "
            << 100.0 * static_cast<double>(steady) / static_cast<double>(held.size()) << " % of the hold, peak "
            << peak_N << " N\n";
  EXPECT_LE(peak_N, device::kDevicePeakForce_N + 1e-3);
  const pb::Struct bridge = BridgeSummary(ParseJson(testing::ReadText(run_ + "/summary.json")));
  haptex::testing::ExpectResumesWithinTheirBound(bridge);
  // the relay delays by 50 ms: no host makes the round trip shorter
  const double round_trip_ms = Number(Object(Object(bridge, "latencies"), "haptic_round_trip"), "p50_us") * 1e-3;
  std::cout << "[measured] haptic round trip p50 " << round_trip_ms << " ms\n";
  EXPECT_GE(round_trip_ms, 50.0 - 1.0);
  ExpectEndsAtZeroForce();
}

// 300 ms is beyond what the bridge renders (device.max_model_age_s, 150 ms): no force at all, the
// bridge DEGRADED with the reason, and the launcher says so.
TEST_F(LaunchImpairTest, ALinkTooSlowGivesNoForceAndTheLauncherSaysWhy) {
  auto launcher =
      Launch(testing::ShippedScenePath("pinch_stretch"), "5", {"--impair", std::string(kLink) + ":rtt_ms=300,seed=1"});
  const auto code = launcher->WaitFor(180s);
  ASSERT_TRUE(code.has_value()) << launcher->Stdout();
  EXPECT_EQ(*code, 0) << launcher->Stdout() << launcher->Stderr();
  const Felt felt = ReadFelt(run_);
  ASSERT_GT(felt.force_N.size(), 1000u);
  EXPECT_EQ(*std::max_element(felt.force_N.begin(), felt.force_N.end()), 0.0) << "a 300 ms link was rendered";
  EXPECT_THAT(launcher->Stdout(), HasSubstr("device_bridge: degraded (haptic link too slow: round trip "));
  const pb::Struct bridge = BridgeSummary(ParseJson(testing::ReadText(run_ + "/summary.json")));
  EXPECT_EQ(At(bridge, "state").string_value(), "STATE_DEGRADED");
  EXPECT_THAT(At(bridge, "last_error").string_value(), HasSubstr("haptic link too slow"));
  EXPECT_GE(Number(Object(bridge, "counters"), "slow_link_events"), 1.0);
}

// The link goes dead for a second (the relay drops every datagram both ways: 100 % loss), then
// comes back. The force goes within the bridge's staleness limit and ramp (plus a loaded host's
// margin) of the last model's arrival, and the bridge renders models again afterwards.
TEST_F(LaunchImpairTest, ADeadLinkTakesTheForceAwayAndTheBridgeRendersAgainAfterIt) {
  // The pinch holds from about 3.5 s after the mock starts; the relay counts from the first
  // datagram, which a loaded host's slow start may put well before that: 2 s of margin.
  auto launcher = Launch(testing::ShippedScenePath("pinch_stretch"), "9",
                         {"--impair", std::string(kLink) + ":rtt_ms=20,seed=1,outage_after_s=5.5,outage_s=1"});
  const auto code = launcher->WaitFor(180s);
  ASSERT_TRUE(code.has_value()) << launcher->Stdout();
  EXPECT_EQ(*code, 0) << launcher->Stdout() << launcher->Stderr();

  // when each direction died, on the steady clock the force log uses
  const pb::Struct relay = ParseJson(testing::ReadText(run_ + "/network/" + kLink + ".json"));
  const pb::Struct& forward = Object(relay, "forward");
  const pb::Struct& back = Object(relay, "back");
  EXPECT_GT(Number(Object(forward, "dropped"), "outage"), 0) << "the link never died";
  const double dead_ns = Number(forward, "outage_from_steady_ns");
  const double models_stop_ns = std::min(Number(back, "outage_from_steady_ns"), dead_ns + (10.0 + 50.0) * 1e6);
  const double back_ns = dead_ns + 1e9;
  ASSERT_GT(dead_ns, 0.0);

  // How soon the force goes is the watchdog's 20 ms, asserted where time is simulated
  // (in_process_system_test, ACutNetworkTakesTheForceAway...). Here: no force through the dead
  // link's second once any pause of the host (tens of ms) is long past.
  const auto rows = testing::MockForceRows(run_ + "/mock_grab_forces.csv");
  double before_N = 0.0, after_N = 0.0, first_zero_ns = -1.0;
  int late_nonzero = 0;
  for (const auto& r : rows) {
    const double f = std::max(r.thumb_N, r.index_N);
    if (r.t_ns < dead_ns && r.t_ns >= dead_ns - 300e6) before_N = std::max(before_N, f);
    if (r.t_ns >= dead_ns && first_zero_ns < 0.0 && f == 0.0) first_zero_ns = r.t_ns;
    if (r.t_ns > models_stop_ns + 300e6 && r.t_ns < back_ns) late_nonzero += f > 0.0;
    if (r.t_ns >= back_ns) after_N = std::max(after_N, f);
  }
  std::cout << "[measured] dead link: force zero " << (first_zero_ns - models_stop_ns) * 1e-6
            << " ms after the models stopped (held up to " << before_N << " N before, " << after_N
            << " N after the link came back)\n";
  EXPECT_EQ(late_nonzero, 0) << "force while the link was dead";
  const pb::Struct bridge = BridgeSummary(ParseJson(testing::ReadText(run_ + "/summary.json")));
  EXPECT_EQ(At(bridge, "state").string_value(), "STATE_READY") << "the bridge did not recover";
  haptex::testing::ExpectResumesWithinTheirBound(bridge);
  ExpectEndsAtZeroForce();
}

}  // namespace
}  // namespace haptex::launch
