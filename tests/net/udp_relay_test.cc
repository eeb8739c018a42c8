// The relay runtime in-process: real sockets on loopback, the relay's loop on a thread.

#include "libs/net/udp_relay.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstring>
#include <memory>
#include <optional>
#include <stdexcept>
#include <thread>
#include <vector>

#include "libs/net/udp_address.h"
#include "tests/support/allocation_counter.h"

namespace haptex::net {
namespace {

using namespace std::chrono_literals;
using netsim::DropCause;

std::int64_t NowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

// A datagram carrying its index and when it was sent.
std::vector<std::uint8_t> Stamped(std::uint64_t index, std::size_t size = 16) {
  std::vector<std::uint8_t> bytes(std::max<std::size_t>(size, 16));
  const std::int64_t now_ns = NowNs();
  std::memcpy(bytes.data(), &index, 8);
  std::memcpy(bytes.data() + 8, &now_ns, 8);
  return bytes;
}

struct Received {
  std::uint64_t index;
  std::int64_t sent_ns;
  std::int64_t received_ns;
  std::size_t size;
  UdpEndpoint::Endpoint from;
};

// Reads datagrams until `count` arrived or nothing came for `quiet`.
std::vector<Received> ReceiveUpTo(UdpEndpoint* socket, std::size_t count, std::chrono::milliseconds quiet = 2000ms) {
  std::vector<Received> out;
  std::vector<std::uint8_t> buffer(70000);
  while (out.size() < count && socket->WaitReadable(quiet)) {
    Received r{};
    while (const auto size = socket->ReceiveOne(buffer, &r.from)) {
      r.received_ns = NowNs();
      r.size = *size;
      if (*size >= 16) {
        std::memcpy(&r.index, buffer.data(), 8);
        std::memcpy(&r.sent_ns, buffer.data() + 8, 8);
      }
      out.push_back(r);
    }
  }
  return out;
}

class UdpRelayTest : public ::testing::Test {
 protected:
  UdpRelayConfig BaseConfig() {
    UdpRelayConfig config;
    config.listen_address = "127.0.0.1:0";
    config.to_address = FormatUdpAddress(server_.local_endpoint());
    config.upstream_bind_address = "127.0.0.1:0";
    config.buffers = {.small_bytes = 2048, .small_count = 1024, .large_bytes = 65536, .large_count = 8};
    return config;
  }

  void Create(const UdpRelayConfig& config) { relay_ = std::make_unique<UdpRelay>(config); }
  void Start(const UdpRelayConfig& config) {
    Create(config);
    thread_ = std::thread([this] { relay_->Run([this] { return stop_.load(); }); });
  }
  // Runs the relay on this thread for its configured duration: what was sent before is taken in
  // by the first receive, before the loop looks at anything else.
  void RunCreated() {
    relay_->Run([] { return false; });
  }

  void Stop() {
    stop_.store(true);
    if (thread_.joinable()) thread_.join();
  }

  void TearDown() override { Stop(); }

  void SendToRelay(UdpEndpoint* from, const std::vector<std::uint8_t>& bytes) {
    ASSERT_TRUE(from->SendTo(bytes, relay_->listen_endpoint()));
  }

  UdpEndpoint server_{"127.0.0.1:0"};
  UdpEndpoint client_{"127.0.0.1:0"};
  std::unique_ptr<UdpRelay> relay_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

TEST_F(UdpRelayTest, ForwardsToTheServerAndRepliesToTheLastClient) {
  Start(BaseConfig());
  constexpr int kN = 200;
  for (int i = 0; i < kN; ++i) SendToRelay(&client_, Stamped(static_cast<std::uint64_t>(i), 100));
  const auto at_server = ReceiveUpTo(&server_, kN);
  ASSERT_EQ(at_server.size(), static_cast<std::size_t>(kN));
  for (int i = 0; i < kN; ++i) {
    EXPECT_EQ(at_server[static_cast<std::size_t>(i)].index, static_cast<std::uint64_t>(i));  // FIFO
    EXPECT_EQ(at_server[static_cast<std::size_t>(i)].size, 100u);
  }
  // the server answers whoever sent: the relay's upstream socket
  EXPECT_EQ(at_server[0].from, relay_->upstream_endpoint());
  for (const Received& r : at_server) ASSERT_TRUE(server_.SendTo(Stamped(r.index), r.from));
  const auto at_client = ReceiveUpTo(&client_, kN);
  EXPECT_EQ(at_client.size(), static_cast<std::size_t>(kN));
  EXPECT_EQ(at_client[0].from, relay_->listen_endpoint());
  Stop();
  EXPECT_EQ(relay_->forward_stats().received, static_cast<std::uint64_t>(kN));
  EXPECT_EQ(relay_->forward_stats().forwarded, static_cast<std::uint64_t>(kN));
  EXPECT_EQ(relay_->back_stats().forwarded, static_cast<std::uint64_t>(kN));
  EXPECT_EQ(relay_->forward_stats().dropped.Total(), 0u);
}

TEST_F(UdpRelayTest, AServerSendingToTheFixedUpstreamPortReachesBackTo) {
  UdpRelayConfig config = BaseConfig();
  config.back_to_address = FormatUdpAddress(client_.local_endpoint());
  Start(config);
  // no client traffic at all: the server sends to the relay as its configured peer
  for (int i = 0; i < 50; ++i) {
    ASSERT_TRUE(server_.SendTo(Stamped(static_cast<std::uint64_t>(i)), relay_->upstream_endpoint()));
  }
  EXPECT_EQ(ReceiveUpTo(&client_, 50).size(), 50u);
  Stop();
  EXPECT_EQ(relay_->back_stats().forwarded, 50u);
  EXPECT_EQ(relay_->forward_stats().received, 0u);
}

TEST_F(UdpRelayTest, RepliesBeforeAnyClientAreCountedAsNoDestination) {
  UdpRelayConfig config = BaseConfig();
  config.duration_s = 0.1;
  Create(config);
  for (int i = 0; i < 5; ++i) ASSERT_TRUE(server_.SendTo(Stamped(0), relay_->upstream_endpoint()));
  RunCreated();
  EXPECT_EQ(relay_->back_stats().received, 5u);
  EXPECT_EQ(relay_->back_stats().dropped.Get(DropCause::kNoDestination), 5u);
  EXPECT_TRUE(ReceiveUpTo(&client_, 1, 50ms).empty());
}

TEST_F(UdpRelayTest, DelayIsAtLeastTheConfiguredDelay) {
  UdpRelayConfig config = BaseConfig();
  config.forward.delay_ms = 30;
  config.forward.jitter_ms = 5;
  Start(config);
  for (int i = 0; i < 20; ++i) {
    SendToRelay(&client_, Stamped(static_cast<std::uint64_t>(i)));
    std::this_thread::sleep_for(1ms);
  }
  const auto at_server = ReceiveUpTo(&server_, 20);
  ASSERT_EQ(at_server.size(), 20u);
  // lower bound only: sent before the relay's receive stamp, received after its release; 25 ms
  // less a microsecond for moving the kernel's stamp onto the steady clock
  for (const Received& r : at_server) EXPECT_GE(r.received_ns - r.sent_ns, 25'000'000 - 1'000);
  Stop();
  EXPECT_GE(relay_->forward_stats().delay.min_ns(), 25'000'000);
}

TEST_F(UdpRelayTest, CopiesHeldAtStopAreCounted) {
  UdpRelayConfig config = BaseConfig();
  config.forward.delay_ms = 60000;
  config.duration_s = 0.05;
  Create(config);
  for (int i = 0; i < 7; ++i) SendToRelay(&client_, Stamped(0));
  RunCreated();
  EXPECT_EQ(relay_->forward_stats().received, 7u);
  EXPECT_EQ(relay_->forward_stats().dropped.Get(DropCause::kUnsentAtStop), 7u);
  EXPECT_EQ(relay_->forward_stats().in_flight(), 0u);
}

TEST_F(UdpRelayTest, OversizeAndFullBuffersAreCountedNotFatal) {
  UdpRelayConfig config = BaseConfig();
  config.forward.max_datagram_bytes = 1000;
  config.forward.delay_ms = 60000;  // hold everything: the buffers fill
  config.buffers = {.small_bytes = 2048, .small_count = 10, .large_bytes = 65536, .large_count = 1};
  config.duration_s = 0.05;
  Create(config);
  SendToRelay(&client_, Stamped(0, 1001));
  SendToRelay(&client_, Stamped(0, 60000));
  for (int i = 0; i < 20; ++i) SendToRelay(&client_, Stamped(0, 500));
  RunCreated();
  const netsim::ImpairmentStats& stats = relay_->forward_stats();
  EXPECT_EQ(stats.received, 22u);
  EXPECT_EQ(stats.dropped.Get(DropCause::kOversize), 2u);
  EXPECT_EQ(stats.dropped.Get(DropCause::kQueueOverflow), 9u);  // 11 buffers in all
  EXPECT_EQ(stats.dropped.Get(DropCause::kUnsentAtStop), 11u);
}

TEST_F(UdpRelayTest, BadConfigurationIsRefusedAtConstruction) {
  UdpRelayConfig config = BaseConfig();
  config.forward.loss = 2.0;
  EXPECT_THROW(UdpRelay{config}, std::invalid_argument);
  config = BaseConfig();
  config.to_address = "127.0.0.1";  // no port
  EXPECT_THROW(UdpRelay{config}, std::invalid_argument);
  config = BaseConfig();
  config.duration_s = -1;
  EXPECT_THROW(UdpRelay{config}, std::invalid_argument);
}

TEST_F(UdpRelayTest, StopsByItselfAfterTheDuration) {
  UdpRelayConfig config = BaseConfig();
  config.duration_s = 0.05;
  UdpRelay relay(config);
  relay.Run([] { return false; });  // returns: the duration ended
  SUCCEED();
}

TEST_F(UdpRelayTest, RelayLoopDoesNotAllocatePerDatagram) {
  if (!testing::AllocationCountingSupported()) GTEST_SKIP() << "allocation counting unavailable";
  UdpRelayConfig config = BaseConfig();
  config.forward.delay_ms = 1;
  config.forward.jitter_ms = 0.5;
  config.forward.jitter_distribution = netsim::JitterDistribution::kNormal;
  config.forward.duplicate = 0.1;
  config.forward.reorder = 0.1;
  UdpRelay relay(config);
  constexpr int kN = 100;  // queued before the loop runs: within a default receive buffer
  for (int i = 0; i < kN; ++i) {
    ASSERT_TRUE(client_.SendTo(Stamped(static_cast<std::uint64_t>(i), 300), relay.listen_endpoint()));
  }
  // the loop runs on this thread: count from its first look at the stop condition
  std::optional<testing::AllocationCounter> counter;
  std::vector<std::uint8_t> buffer(2048);
  const std::int64_t give_up_ns = NowNs() + 5'000'000'000;
  relay.Run([&] {
    if (!counter) counter.emplace();
    UdpEndpoint::Endpoint from;
    while (server_.ReceiveOne(buffer, &from)) {
    }
    return (relay.forward_stats().in_flight() == 0 && relay.forward_stats().received == kN) || NowNs() > give_up_ns;
  });
  ASSERT_TRUE(counter.has_value());
  EXPECT_EQ(counter->count(), 0);
  EXPECT_EQ(relay.forward_stats().received, static_cast<std::uint64_t>(kN));
  EXPECT_EQ(relay.forward_stats().forwarded, kN + relay.forward_stats().duplicated);
}

}  // namespace
}  // namespace haptex::net
