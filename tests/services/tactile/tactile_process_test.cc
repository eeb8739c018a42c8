// haptex-tactile as a real process: the test plays local_contact (TouchTrace out) and the pin
// display (PinFrame in) over loopback UDP.

#include <gtest/gtest.h>

#include <csignal>
#include <thread>

#include "libs/net/messenger.h"
#include "libs/net/peer_names.h"
#include "libs/net/udp_address.h"
#include "tests/support/subprocess.h"
#include "tests/support/test_paths.h"

namespace haptex {
namespace {

using namespace std::chrono_literals;

TEST(TactileProcessTest, RendersSlidingAsVibrationAndNoContactAsSilence) {
  const auto key = net::SessionKey::Generate();
  constexpr std::uint64_t kSession = 31;
  net::MessengerConfig config;
  config.identity = {"mock_pins", 0, kSession};
  config.also_known_as = net::peer::AlsoKnownAs("mock_pins");  // tactile's "display"
  net::Messenger display(key, config);
  config.identity = {"local_contact", 0, kSession};
  config.also_known_as = {};
  net::Messenger contact(key, config);
  testing::Subprocess tactile(
      {testing::BuildDir() + "/services/tactile/haptex-tactile", "--session-id", std::to_string(kSession), "--peer",
       "display=" + net::FormatUdpAddress(display.local_endpoint()), "--pattern", "plain", "--warp-pitch-mm", "1",
       "--weft-pitch-mm", "1", "--yarn-mm", "0.6", "--smd-um", "5"},
      {"HAPTEX_SESSION_KEY=" + key.ToHex()});

  // frames arrive without any touch: silent; they tell us the service's address
  net::Messenger::Endpoint service;
  std::uint64_t frames = 0;
  double peak = 0;
  auto drain = [&] {
    display.Drain([&](const v1::Envelope& e, const net::Messenger::Endpoint& from) {
      if (e.body_case() != v1::Envelope::kPinFrame) return;
      service = from;
      ++frames;
      for (const auto& f : e.pin_frame().fingers()) {
        for (float a : f.amplitude_40hz()) peak = std::max<double>(peak, a);
        for (float a : f.amplitude_320hz()) peak = std::max<double>(peak, a);
      }
    });
  };
  for (int i = 0; i < 1000 && frames < 50; ++i) {
    display.WaitReadable(10ms);
    drain();
  }
  ASSERT_GE(frames, 50u) << tactile.Stderr();
  EXPECT_EQ(peak, 0.0);

  // slide at 40 mm/s with 1 N for 0.5 s, TouchTraces at ~1 kHz
  const auto to_tactile = contact.AddPeer("tactile", service);
  v1::TouchTrace trace;
  auto* thumb = trace.add_fingers();
  thumb->set_finger(v1::FINGER_THUMB);
  thumb->set_in_contact(true);
  thumb->set_slip_u_m_per_s(0.04);
  thumb->set_normal_force_n(1.0);
  peak = 0;
  const auto start = std::chrono::steady_clock::now();
  while (std::chrono::steady_clock::now() - start < 500ms) {
    const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    thumb->set_u_m(0.04 * t);
    contact.Send(to_tactile, trace);
    std::this_thread::sleep_for(1ms);
    drain();
  }
  EXPECT_GT(peak, 0.0) << "sliding over a 1 mm weave gave no vibration";

  // lift the finger: silence within the envelope's decay
  thumb->set_in_contact(false);
  for (int i = 0; i < 200; ++i) {
    contact.Send(to_tactile, trace);
    std::this_thread::sleep_for(1ms);
    drain();
  }
  peak = 0;
  for (int i = 0; i < 50; ++i) {
    contact.Send(to_tactile, trace);
    std::this_thread::sleep_for(1ms);
    drain();
  }
  EXPECT_EQ(peak, 0.0);
  tactile.Signal(SIGTERM);
  EXPECT_EQ(tactile.WaitFor(5s), 0);
}

TEST(TactileProcessTest, FabricWithoutSurfaceDataIsRefusedClearly) {
  testing::Subprocess tactile(
      {testing::BuildDir() + "/services/tactile/haptex-tactile", "--peer", "display=127.0.0.1:9", "--scene",
       testing::SourceDir() + "/launch/scenes/hanging.textproto"},
      {"HAPTEX_SESSION_KEY=" + net::SessionKey::Generate().ToHex()});
  EXPECT_EQ(tactile.WaitFor(10s), 2);
  EXPECT_NE(tactile.Stderr().find("lacks warp pitch, weft pitch, yarn diameter, roughness SMD"), std::string::npos)
      << tactile.Stderr();
}

}  // namespace
}  // namespace haptex
