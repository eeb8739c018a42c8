#include "libs/net/udp_endpoint.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>

#include <optional>

#include <chrono>
#include <stdexcept>
#include <thread>
#include <vector>

#include "libs/base/clock.h"

namespace haptex::net {
namespace {

TEST(UdpEndpointTest, SendsAndReceivesOnLoopback) {
  UdpEndpoint a("127.0.0.1:0");
  UdpEndpoint b("127.0.0.1:0");
  ASSERT_NE(b.local_port(), 0);
  const std::vector<std::uint8_t> payload = {1, 2, 3, 4, 5};
  ASSERT_TRUE(a.SendTo(payload, b.local_endpoint()));
  ASSERT_TRUE(b.WaitReadable(std::chrono::milliseconds(2000)));
  std::vector<std::uint8_t> buffer(64);
  UdpEndpoint::Endpoint from;
  const auto bytes = b.ReceiveOne(buffer, &from);
  ASSERT_TRUE(bytes.has_value());
  EXPECT_EQ(*bytes, payload.size());
  EXPECT_EQ(from.port(), a.local_port());
  EXPECT_FALSE(b.ReceiveOne(buffer, &from).has_value());  // non-blocking: nothing more waiting
}

TEST(UdpEndpointTest, ReportsTheRealSizeOfADatagramLargerThanTheBuffer) {
  UdpEndpoint a("127.0.0.1:0");
  UdpEndpoint b("127.0.0.1:0");
  const std::vector<std::uint8_t> payload(3000, 0xab);
  ASSERT_TRUE(a.SendTo(payload, b.local_endpoint()));
  ASSERT_TRUE(b.WaitReadable(std::chrono::milliseconds(2000)));
  std::vector<std::uint8_t> buffer(100);
  UdpEndpoint::Endpoint from;
  const auto bytes = b.ReceiveOne(buffer, &from);
  ASSERT_TRUE(bytes.has_value());
  EXPECT_EQ(*bytes, 3000u);
}

TEST(UdpEndpointTest, ArrivalTimeIsWhenTheKernelReceivedNotWhenWeRead) {
  UdpEndpoint a("127.0.0.1:0");
  UdpEndpoint b("127.0.0.1:0");
  std::vector<std::uint8_t> buffer(64);
  UdpEndpoint::Endpoint from;
  std::int64_t arrival = 0;
  EXPECT_FALSE(b.ReceiveOne(buffer, &from, &arrival).has_value());  // enables timestamps
  // Linux turns receive timestamps on for the whole stack through deferred work: until that has
  // run, a datagram is stamped when it is read. So a warm-up datagram first, and a few tries.
  ASSERT_TRUE(a.SendTo(std::vector<std::uint8_t>{0}, b.local_endpoint()));
  ASSERT_TRUE(b.WaitReadable(std::chrono::milliseconds(2000)));
  ASSERT_EQ(b.ReceiveOne(buffer, &from, &arrival), 1u);
  bool stamped_on_arrival = false;
  for (int attempt = 0; attempt < 3 && !stamped_on_arrival; ++attempt) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    const std::int64_t sent = base::SteadyNowNs();
    ASSERT_TRUE(a.SendTo(std::vector<std::uint8_t>{1, 2, 3}, b.local_endpoint()));
    std::this_thread::sleep_for(std::chrono::milliseconds(30));  // the datagram waits in the socket
    const std::int64_t read = base::SteadyNowNs();
    ASSERT_EQ(b.ReceiveOne(buffer, &from, &arrival), 3u);
    EXPECT_EQ(from.port(), a.local_port());
    EXPECT_GE(arrival, sent - 1'000'000);  // clock conversion tolerance
    EXPECT_LE(arrival, read + 1'000'000);
    stamped_on_arrival = arrival < read - 20'000'000;
  }
  EXPECT_TRUE(stamped_on_arrival) << "arrival should be ~30 ms before the read";
}

// A flood that overflows the socket's queue: every datagram sent is either read or counted as
// dropped by the kernel, on both receive paths.
TEST(UdpEndpointTest, CountsWhatTheKernelDroppedForAFullQueue) {
  for (const bool stamped : {false, true}) {
    SCOPED_TRACE(stamped ? "with arrival stamps" : "without");
    UdpEndpoint sender("127.0.0.1:0");
    UdpEndpoint receiver("127.0.0.1:0");
    const std::vector<std::uint8_t> payload(1400, 7);
    constexpr int kSent = 8000;  // 11 MB against a receive queue of a few MB
    int refused = 0;
    for (int i = 0; i < kSent; ++i) refused += sender.SendTo(payload, receiver.local_endpoint()) ? 0 : 1;
    std::vector<std::uint8_t> buffer(2048);
    UdpEndpoint::Endpoint from;
    std::int64_t arrival_ns = 0;
    int read = 0;
    const auto receive = [&] {
      return stamped ? receiver.ReceiveOne(buffer, &from, &arrival_ns) : receiver.ReceiveOne(buffer, &from);
    };
    while (receive()) ++read;
    // the kernel tells the count with the next datagram queued after the drops
    ASSERT_TRUE(sender.SendTo(payload, receiver.local_endpoint()));
    ASSERT_TRUE(receiver.WaitReadable(std::chrono::milliseconds(2000)));
    ASSERT_TRUE(receive());
    EXPECT_GT(receiver.kernel_drops(), 0u) << "the queue did not overflow: the test would prove nothing";
    EXPECT_EQ(static_cast<std::uint64_t>(read) + receiver.kernel_drops(), static_cast<std::uint64_t>(kSent - refused));
  }
}

TEST(UdpEndpointTest, BindFailureNamesTheAddress) {
  UdpEndpoint taken("127.0.0.1:0");
  const std::string address = "127.0.0.1:" + std::to_string(taken.local_port());
  try {
    UdpEndpoint second(address);
    FAIL() << "bound a taken port";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(address), std::string::npos) << e.what();
  }
}

TEST(UdpEndpointTest, WaitReadableTimesOut) {
  UdpEndpoint a("127.0.0.1:0");
  EXPECT_FALSE(a.WaitReadable(std::chrono::milliseconds(5)));
}

// The descriptor of this process's IPv4 UDP socket bound to `port`, if any.
std::optional<int> SocketBoundTo(std::uint16_t port) {
  for (int fd = 0; fd < 4096; ++fd) {
    sockaddr_in address{};
    socklen_t length = sizeof(address);
    if (getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length) == 0 && address.sin_family == AF_INET &&
        ntohs(address.sin_port) == port) {
      return fd;
    }
  }
  return std::nullopt;
}

TEST(UdpEndpointTest, SocketIsCloseOnExec) {
  UdpEndpoint endpoint("127.0.0.1:0");
  const std::optional<int> fd = SocketBoundTo(endpoint.local_port());
  ASSERT_TRUE(fd.has_value());
  const int flags = fcntl(*fd, F_GETFD);
  ASSERT_NE(flags, -1);
  EXPECT_NE(flags & FD_CLOEXEC, 0);
}

}  // namespace
}  // namespace haptex::net
