// Recordings: services/common's EnvelopeRecorder writes length-delimited Envelopes off the loop
// (no allocation, drops counted); launch's reader parses them back, and survives a cut file.
#include "launch/recording.h"

#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

#include "libs/net/messenger.h"
#include "services/common/envelope_recorder.h"
#include "services/common/service_context.h"
#include "tests/launch/launch_test_support.h"
#include "tests/support/allocation_counter.h"

namespace haptex::launch {
namespace {

v1::Health MakeHealth(int ticks) {
  v1::Health h;
  h.set_service("device_bridge");
  h.set_state(v1::Health::STATE_READY);
  auto* loop = h.add_loops();
  loop->set_name("device_bridge");
  loop->set_ticks(static_cast<std::uint64_t>(ticks));
  return h;
}

TEST(LaunchRecordingTest, RoundTripKeepsHeaderAndBodies) {
  const std::string path = testing::FreshDir("recording_round_trip") + "/bridge.pb";
  v1::FingerStates states;
  states.set_controller_sequence(7);
  states.add_fingers()->set_finger(v1::FINGER_THUMB);
  {
    services::EnvelopeRecorder recorder(path, "device_bridge", 1234, 99);
    EXPECT_TRUE(recorder.Record(MakeHealth(5), 1000));
    EXPECT_TRUE(recorder.Record(states, 2000));
    EXPECT_EQ(recorder.recorded(), 2u);
  }
  const Recording r = ReadRecording(path);
  ASSERT_EQ(r.envelopes.size(), 2u);
  EXPECT_FALSE(r.truncated);
  EXPECT_EQ(r.unparsable, 0u);
  const v1::Envelope& first = r.envelopes[0];
  EXPECT_EQ(first.version(), 1u);
  EXPECT_EQ(first.session_id(), 99u);
  EXPECT_EQ(first.sender(), "device_bridge");
  EXPECT_EQ(first.sender_epoch(), 1234u);
  EXPECT_EQ(first.sequence(), 1u);
  EXPECT_EQ(first.send_time_ns(), 1000);
  EXPECT_EQ(first.health().loops(0).ticks(), 5u);
  EXPECT_EQ(r.envelopes[1].sequence(), 2u);
  EXPECT_EQ(r.envelopes[1].finger_states().controller_sequence(), 7u);
  EXPECT_EQ(EarliestSendTimeNs({r}), 1000);
}

TEST(LaunchRecordingTest, MessagesOfAnySizeAreKeptWholeAndInOrderAcrossWraps) {
  const std::string path = testing::FreshDir("recording_sizes") + "/global_sim.pb";
  // patch-sized, health-sized and in between; four times the ring in all (four wraps at varied
  // offsets), at a pace the writer (every 10 ms) keeps up with: nothing may be lost
  const std::array<std::size_t, 3> sizes{150000, 40, 6000};
  const int count = 3 * static_cast<int>(4 * services::EnvelopeRecorder::kRingBytes / (150000 + 40 + 6000));
  {
    services::EnvelopeRecorder recorder(path, "global_sim", 1, 1);
    for (int i = 0; i < count; ++i) {
      v1::Health h;
      h.set_last_error(std::string(sizes[static_cast<std::size_t>(i) % 3], static_cast<char>('a' + i % 26)));
      bool kept = recorder.Record(h, i);
      for (int wait = 0; !kept && wait < 2000; ++wait) {  // only if the writer fell behind
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
        kept = recorder.Record(h, i);
      }
      ASSERT_TRUE(kept) << "record " << i;
      if (i % 20 == 0) std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    EXPECT_EQ(recorder.recorded(), static_cast<std::uint64_t>(count));
  }
  const Recording r = ReadRecording(path);
  ASSERT_EQ(r.envelopes.size(), static_cast<std::size_t>(count));
  EXPECT_FALSE(r.truncated);
  for (int i = 0; i < count; ++i) {
    const v1::Envelope& e = r.envelopes[static_cast<std::size_t>(i)];
    EXPECT_EQ(e.send_time_ns(), i);
    ASSERT_EQ(e.health().last_error().size(), sizes[static_cast<std::size_t>(i) % 3]);
    EXPECT_EQ(e.health().last_error().back(), static_cast<char>('a' + i % 26));
  }
}

TEST(LaunchRecordingTest, RecordDoesNotAllocateAfterWarmUp) {
  if (!haptex::testing::AllocationCountingSupported()) GTEST_SKIP() << "allocation counting unsupported here";
  const std::string path = testing::FreshDir("recording_alloc") + "/r.pb";
  services::EnvelopeRecorder recorder(path, "tactile", 1, 1);
  const v1::Health health = MakeHealth(3);
  recorder.Record(health, 1);
  haptex::testing::AllocationCounter counter;
  for (int i = 0; i < 100; ++i) recorder.Record(health, i);
  EXPECT_EQ(counter.count(), 0);
}

TEST(LaunchRecordingTest, OversizedAndOverflowingMessagesAreDroppedAndCounted) {
  const std::string path = testing::FreshDir("recording_drops") + "/r.pb";
  std::uint64_t accepted = 0;
  {
    services::EnvelopeRecorder recorder(path, "x", 1, 1);
    v1::Health too_big;
    too_big.set_last_error(std::string(services::EnvelopeRecorder::kMaxRecordBytes, 'e'));
    EXPECT_FALSE(recorder.Record(too_big, 1));
    EXPECT_EQ(recorder.dropped(), 1u);
    // a burst of large messages (patch-sized) beyond the ring, faster than the writer drains it,
    // drops some and keeps the rest whole, across the ring's wrap
    v1::Health big;
    big.set_last_error(std::string(100000, 'p'));
    const std::size_t burst = 4 * services::EnvelopeRecorder::kRingBytes / 100000;
    for (std::size_t i = 0; i < burst; ++i) accepted += recorder.Record(big, 2) ? 1 : 0;
    EXPECT_GT(accepted, 0u);
    EXPECT_EQ(recorder.recorded(), accepted);
  }
  EXPECT_EQ(ReadRecording(path).envelopes.size(), accepted);
}

TEST(LaunchRecordingTest, ACutFileKeepsTheWholeRecords) {
  const std::string dir = testing::FreshDir("recording_cut");
  {
    services::EnvelopeRecorder recorder(dir + "/a.pb", "x", 1, 1);
    for (int i = 0; i < 3; ++i) recorder.Record(MakeHealth(i), i);
  }
  const auto size = std::filesystem::file_size(dir + "/a.pb");
  std::filesystem::resize_file(dir + "/a.pb", size - 3);
  std::ofstream(dir + "/notes.txt") << "not a recording";
  const auto all = ReadRecordings(dir);
  ASSERT_EQ(all.size(), 1u);
  EXPECT_TRUE(all[0].truncated);
  EXPECT_EQ(all[0].envelopes.size(), 2u);
  EXPECT_THROW(ReadRecording(dir + "/missing.pb"), std::runtime_error);
  EXPECT_TRUE(ReadRecordings(dir + "/no_such_folder").empty());
}

TEST(LaunchRecordingTest, ServiceContextRecordsWhatItSendsAndItsHealth) {
  const net::SessionKey key = net::SessionKey::Generate();
  setenv("HAPTEX_SESSION_KEY", key.ToHex().c_str(), 1);
  net::MessengerConfig peer_config;
  peer_config.identity = {"launcher", 0, key.DerivedSessionId()};
  net::Messenger launcher(key, peer_config);
  const std::string path = testing::FreshDir("context_record") + "/tactile.pb";
  {
    services::ServiceOptions options;
    options.record_path = path;
    options.health_hz = 1000;
    options.log_level = "off";
    options.peers = {"launcher=127.0.0.1:" + std::to_string(launcher.local_port())};
    services::ServiceContext context("tactile", options);
    v1::PinFrame frame;
    frame.set_frame_index(42);
    EXPECT_TRUE(context.Send(context.RequirePeer("launcher"), frame));
    context.Tick(context.start_ns() + 2'000'000);  // a Health is due: sent and recorded
  }
  int received = 0;
  launcher.WaitReadable(std::chrono::milliseconds(500));
  launcher.Drain([&](const v1::Envelope&, const net::Messenger::Endpoint&) { ++received; });
  EXPECT_GE(received, 1);
  const Recording r = ReadRecording(path);
  ASSERT_EQ(r.envelopes.size(), 2u);
  EXPECT_EQ(r.envelopes[0].pin_frame().frame_index(), 42u);
  EXPECT_EQ(r.envelopes[0].sender(), "tactile");
  EXPECT_GT(r.envelopes[0].sender_epoch(), 0u);
  EXPECT_EQ(r.envelopes[0].session_id(), key.DerivedSessionId());
  EXPECT_EQ(r.envelopes[1].health().service(), "tactile");
}

// A recording the disk refuses (here /dev/full, which fails every write as a full disk does) is
// counted in the service's Health (record_write_errors), which the launcher turns into an error
// of the run: the service itself runs on.
TEST(LaunchRecordingTest, ARecordingTheDiskRefusesIsCountedInHealth) {
  const net::SessionKey key = net::SessionKey::Generate();
  setenv("HAPTEX_SESSION_KEY", key.ToHex().c_str(), 1);
  net::MessengerConfig peer_config;
  peer_config.identity = {"launcher", 0, key.DerivedSessionId()};
  net::Messenger launcher(key, peer_config);
  services::ServiceOptions options;
  options.record_path = "/dev/full";
  options.health_hz = 1000;
  options.log_level = "off";
  options.peers = {"launcher=127.0.0.1:" + std::to_string(launcher.local_port())};
  services::ServiceContext context("tactile", options);
  // more than the file's buffer, so the writer's writes reach the device
  for (int i = 0; i < 300; ++i) {
    v1::PinFrame frame;
    frame.set_frame_index(static_cast<std::uint64_t>(i));
    context.Send(context.RequirePeer("launcher"), frame);
  }
  double write_errors = 0.0;
  for (int attempt = 1; attempt <= 50 && write_errors == 0.0; ++attempt) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    context.Tick(context.start_ns() + attempt * 2'000'000);
    launcher.WaitReadable(std::chrono::milliseconds(100));
    launcher.Drain([&](const v1::Envelope& e, const net::Messenger::Endpoint&) {
      if (!e.has_health()) return;
      for (const v1::Counter& c : e.health().counters()) {
        if (c.name() == "record_write_errors") write_errors = std::max(write_errors, static_cast<double>(c.value()));
      }
    });
  }
  EXPECT_GT(write_errors, 0.0);
}

}  // namespace
}  // namespace haptex::launch
