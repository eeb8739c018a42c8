// haptex-mock-pins as a real process, fed over loopback UDP like the tactile service would.

#include <gtest/gtest.h>

#include <unistd.h>

#include <csignal>
#include <regex>
#include <thread>

#include "libs/net/messenger.h"
#include "libs/net/udp_address.h"
#include "tests/services/mock_pins/pin_test_frames.h"
#include "tests/support/subprocess.h"
#include "tests/support/test_paths.h"

namespace haptex::mock_pins {
namespace {

using namespace std::chrono_literals;

constexpr std::uint64_t kSession = 77;

class MockPinsProcessTest : public ::testing::Test {
 protected:
  MockPinsProcessTest() : key_(net::SessionKey::Generate()) {
    net::MessengerConfig config;
    config.identity = {"launcher", 0, kSession};
    launcher_ = std::make_unique<net::Messenger>(key_, config);
    config.identity = {"tactile", 0, kSession};
    tactile_ = std::make_unique<net::Messenger>(key_, config);
  }

  void Start(std::vector<std::string> extra = {}) {
    // ctest runs each case as its own process, in parallel: one file per case
    csv_ = ::testing::TempDir() + "/mock_pins_" + ::testing::UnitTest::GetInstance()->current_test_info()->name() +
           "_" + std::to_string(getpid()) + ".csv";
    std::vector<std::string> argv = {haptex::testing::BuildDir() + "/services/mock_pins/haptex-mock-pins",
                                     "--bind",
                                     "127.0.0.1:0",
                                     "--session-id",
                                     std::to_string(kSession),
                                     "--peer",
                                     "launcher=" + net::FormatUdpAddress(launcher_->local_endpoint()),
                                     "--health-hz",
                                     "20",
                                     "--log-csv",
                                     csv_};
    argv.insert(argv.end(), extra.begin(), extra.end());
    process_ = std::make_unique<haptex::testing::Subprocess>(
        argv, std::vector<std::string>{"HAPTEX_SESSION_KEY=" + key_.ToHex()});
    // the first Health tells us where the display listens
    const auto health = NextHealth(5s);
    ASSERT_TRUE(health.has_value()) << process_->Stderr();
    EXPECT_EQ(health->service(), "mock_pins");
    EXPECT_EQ(health->state(), v1::Health::STATE_READY);
    display_ = tactile_->AddPeer("mock_pins", display_endpoint_);
  }

  std::optional<v1::Health> NextHealth(std::chrono::milliseconds timeout) {
    std::optional<v1::Health> result;
    const auto until = std::chrono::steady_clock::now() + timeout;
    while (!result && std::chrono::steady_clock::now() < until) {
      launcher_->WaitReadable(10ms);
      launcher_->Drain([&](const v1::Envelope& e, const net::Messenger::Endpoint& from) {
        if (e.body_case() == v1::Envelope::kHealth) {
          result = e.health();
          display_endpoint_ = from;
        }
      });
    }
    return result;
  }

  std::uint64_t Counter(const v1::Health& h, const std::string& name) {
    for (const auto& c : h.counters()) {
      if (c.name() == name) return c.value();
    }
    ADD_FAILURE() << "no counter " << name;
    return 0;
  }

  // Waits for a Health whose counter reached `value`.
  std::optional<v1::Health> HealthWith(const std::string& counter, std::uint64_t value) {
    const auto until = std::chrono::steady_clock::now() + 10s;
    while (std::chrono::steady_clock::now() < until) {
      if (auto h = NextHealth(200ms); h && Counter(*h, counter) >= value) return h;
    }
    return std::nullopt;
  }

  net::SessionKey key_;
  std::unique_ptr<net::Messenger> launcher_;
  std::unique_ptr<net::Messenger> tactile_;
  std::unique_ptr<haptex::testing::Subprocess> process_;
  net::Messenger::Endpoint display_endpoint_;
  net::Messenger::PeerId display_ = 0;
  std::string csv_;
};

TEST_F(MockPinsProcessTest, PlaysValidFramesRefusesBadOnesAndRecordsThem) {
  Start();
  for (std::uint64_t i = 1; i <= 10; ++i) ASSERT_TRUE(tactile_->Send(display_, testing::RampFrame(i)));
  auto bad = testing::RampFrame(11);
  bad.mutable_fingers(0)->set_amplitude_40hz(0, 7.0f);
  ASSERT_TRUE(tactile_->Send(display_, bad));
  const auto health = HealthWith("frames_rejected", 1);
  ASSERT_TRUE(health.has_value());
  EXPECT_EQ(Counter(*health, "frames_played"), 10u);

  process_->Signal(SIGTERM);
  EXPECT_EQ(process_->WaitFor(5s), 0);
  // 10 frames x 2 fingers x 24 pins, plus the header
  const std::string csv = haptex::testing::ReadFileOrEmpty(csv_);
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 1 + 10 * 2 * 24) << csv.substr(0, 200);
  EXPECT_NE(csv.find(",10,thumb,23,1,0\n"), std::string::npos);
}

TEST_F(MockPinsProcessTest, GarbageAndForgeriesAreDroppedAndCounted) {
  Start();
  net::UdpEndpoint attacker("127.0.0.1:0");
  const std::vector<std::uint8_t> junk(300, 0x42);
  for (int i = 0; i < 50; ++i) attacker.SendTo(junk, display_endpoint_);
  net::MessengerConfig config;
  config.identity = {"tactile", 0, kSession};
  net::Messenger forger(net::SessionKey::Generate(), config);
  const auto to_display = forger.AddPeer("mock_pins", display_endpoint_);
  for (int i = 0; i < 5; ++i) forger.Send(to_display, testing::RampFrame(100 + static_cast<std::uint64_t>(i)));
  const auto health = HealthWith("datagrams_dropped", 55);
  ASSERT_TRUE(health.has_value()) << "the display did not count 55 drops";
  EXPECT_EQ(Counter(*health, "frames_played"), 0u);
}

TEST_F(MockPinsProcessTest, ControlShutdownStopsItCleanly) {
  Start();
  v1::Control control;
  control.set_command(v1::Control::COMMAND_SHUTDOWN);
  control.set_target_service("mock_pins");
  const auto to_display = launcher_->AddPeer("mock_pins", display_endpoint_);
  ASSERT_TRUE(launcher_->Send(to_display, control));
  EXPECT_EQ(process_->WaitFor(5s), 0) << process_->Stderr();
}

TEST(MockPinsOptionsTest, MissingKeyOrBadPeerIsExitCode2) {
  const std::string binary = haptex::testing::BuildDir() + "/services/mock_pins/haptex-mock-pins";
  haptex::testing::Subprocess no_key({binary}, {"HAPTEX_SESSION_KEY="});
  EXPECT_EQ(no_key.WaitFor(5s), 2);
  EXPECT_NE(no_key.Stderr().find("no session key"), std::string::npos) << no_key.Stderr();
  haptex::testing::Subprocess bad_peer({binary, "--peer", "launcher"},
                                       {"HAPTEX_SESSION_KEY=" + net::SessionKey::Generate().ToHex()});
  EXPECT_EQ(bad_peer.WaitFor(5s), 2);
  EXPECT_NE(bad_peer.Stderr().find("NAME=HOST:PORT"), std::string::npos) << bad_peer.Stderr();
}

}  // namespace
}  // namespace haptex::mock_pins
