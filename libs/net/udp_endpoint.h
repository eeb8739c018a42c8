#pragma once
// A non-blocking UDP socket over Asio: bind, send to an endpoint, receive what is waiting.
// No allocation per datagram; the caller owns the buffers.

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

#include <asio/io_context.hpp>
#include <asio/ip/udp.hpp>

namespace haptex::net {

class UdpEndpoint final {
 public:
  using Endpoint = asio::ip::udp::endpoint;

  /// Binds to "host:port" (port 0: any free port). The socket is close-on-exec: processes this one
  /// starts do not inherit it. Throws std::runtime_error with the address and the system's reason
  /// when the bind fails.
  explicit UdpEndpoint(std::string_view bind_address);
  UdpEndpoint(const UdpEndpoint&) = delete;
  UdpEndpoint& operator=(const UdpEndpoint&) = delete;

  Endpoint local_endpoint() const { return local_; }
  std::uint16_t local_port() const { return local_.port(); }

  /// Receives one waiting datagram into `buffer`; nullopt when none is waiting. The returned size
  /// is the datagram's real size, which exceeds buffer.size() when it was cut (oversized).
  std::optional<std::size_t> ReceiveOne(std::span<std::uint8_t> buffer, Endpoint* from);

  /// Same, and *arrival_ns is when the kernel received the datagram, on the steady clock
  /// (SO_TIMESTAMPNS, converted), so latency counts the time a datagram waited in the socket.
  /// Falls back to the time of the call when the kernel gives no timestamp.
  std::optional<std::size_t> ReceiveOne(std::span<std::uint8_t> buffer, Endpoint* from, std::int64_t* arrival_ns);

  /// Sends without blocking; false when the kernel refuses (buffer full, unreachable, too large).
  bool SendTo(std::span<const std::uint8_t> datagram, const Endpoint& to);

  /// Datagrams the kernel dropped because this socket's receive queue was full (SO_RXQ_OVFL), as
  /// of the last datagram received: a flood, or a reader too slow for its traffic.
  std::uint64_t kernel_drops() const { return kernel_drops_; }

  /// Blocks until a datagram is waiting or the timeout passes (for threads that only receive).
  bool WaitReadable(std::chrono::milliseconds timeout);

  /// The socket's descriptor, for waiting on several endpoints at once (poll).
  int native_handle() { return socket_.native_handle(); }

 private:
  std::optional<std::size_t> Receive(std::span<std::uint8_t> buffer, Endpoint* from, std::int64_t* arrival_ns);

  asio::io_context io_;
  asio::ip::udp::socket socket_;
  Endpoint local_;
  bool timestamps_enabled_ = false;
  std::uint64_t kernel_drops_ = 0;
  std::uint32_t last_kernel_drop_count_ = 0;
};

}  // namespace haptex::net
