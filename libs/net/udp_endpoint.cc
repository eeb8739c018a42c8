#include "libs/net/udp_endpoint.h"

#include <poll.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include <stdexcept>
#include <string>

#include "libs/base/clock.h"
#include "libs/net/udp_address.h"

namespace haptex::net {

UdpEndpoint::UdpEndpoint(std::string_view bind_address) : socket_(io_) {
  const Endpoint endpoint = ResolveUdpAddress(bind_address);
  asio::error_code error;
  // Close-on-exec from its first instant (SOCK_CLOEXEC: no window for a fork in another thread),
  // so no process this one starts inherits the socket. Asio's open() would not set it.
  const int fd =
      ::socket(endpoint.protocol().family(), endpoint.protocol().type() | SOCK_CLOEXEC, endpoint.protocol().protocol());
  if (fd < 0) {
    error = asio::error_code(errno, asio::error::get_system_category());
  } else {
    socket_.assign(endpoint.protocol(), fd, error);
    if (error) ::close(fd);
  }
  if (!error) socket_.bind(endpoint, error);
  if (error) {
    throw std::runtime_error("cannot bind UDP " + std::string(bind_address) + ": " + error.message());
  }
  socket_.non_blocking(true);
  // Room for bursts (a ClothFrame in chunks); the kernel caps this at net.core.rmem_max.
  asio::error_code ignored;
  socket_.set_option(asio::socket_base::receive_buffer_size(4 << 20), ignored);
  socket_.set_option(asio::socket_base::send_buffer_size(4 << 20), ignored);
  local_ = socket_.local_endpoint();
  // the kernel reports, with each datagram, how many it dropped for a full receive queue
  const int on = 1;
  setsockopt(socket_.native_handle(), SOL_SOCKET, SO_RXQ_OVFL, &on, sizeof(on));
}

std::optional<std::size_t> UdpEndpoint::ReceiveOne(std::span<std::uint8_t> buffer, Endpoint* from) {
  return Receive(buffer, from, nullptr);
}

std::optional<std::size_t> UdpEndpoint::ReceiveOne(std::span<std::uint8_t> buffer, Endpoint* from,
                                                   std::int64_t* arrival_ns) {
  if (!timestamps_enabled_) {
    const int on = 1;
    setsockopt(socket_.native_handle(), SOL_SOCKET, SO_TIMESTAMPNS, &on, sizeof(on));
    timestamps_enabled_ = true;
  }
  return Receive(buffer, from, arrival_ns);
}

std::optional<std::size_t> UdpEndpoint::Receive(std::span<std::uint8_t> buffer, Endpoint* from,
                                                std::int64_t* arrival_ns) {
  for (;;) {
    iovec io{buffer.data(), buffer.size()};
    alignas(cmsghdr) char control[CMSG_SPACE(sizeof(timespec)) + CMSG_SPACE(sizeof(std::uint32_t))];
    sockaddr_storage address{};
    msghdr message{};
    message.msg_name = &address;
    message.msg_namelen = sizeof(address);
    message.msg_iov = &io;
    message.msg_iovlen = 1;
    message.msg_control = control;
    message.msg_controllen = sizeof(control);
    // MSG_TRUNC makes the kernel report the full size of a datagram larger than the buffer.
    const ssize_t bytes = recvmsg(socket_.native_handle(), &message, MSG_TRUNC | MSG_DONTWAIT);
    if (bytes < 0) {
      // ICMP errors of earlier sends (connection refused) surface here; skip them.
      if (errno == EINTR || errno == ECONNREFUSED) continue;
      return std::nullopt;
    }
    from->resize(message.msg_namelen);
    std::memcpy(from->data(), &address, message.msg_namelen);
    std::int64_t steady_now_ns = 0, real_now_ns = 0;
    if (arrival_ns != nullptr) {
      // the kernel stamps in CLOCK_REALTIME; move it onto the steady clock by the clocks' offset now
      timespec real_now{};
      clock_gettime(CLOCK_REALTIME, &real_now);
      steady_now_ns = base::SteadyNowNs();
      real_now_ns = std::int64_t{real_now.tv_sec} * 1000000000 + real_now.tv_nsec;
      *arrival_ns = steady_now_ns;
    }
    for (cmsghdr* c = CMSG_FIRSTHDR(&message); c != nullptr; c = CMSG_NXTHDR(&message, c)) {
      if (c->cmsg_level != SOL_SOCKET) continue;
      if (c->cmsg_type == SCM_TIMESTAMPNS && arrival_ns != nullptr) {
        timespec stamp{};
        std::memcpy(&stamp, CMSG_DATA(c), sizeof(stamp));
        *arrival_ns = steady_now_ns - (real_now_ns - (std::int64_t{stamp.tv_sec} * 1000000000 + stamp.tv_nsec));
      } else if (c->cmsg_type == SO_RXQ_OVFL) {
        // the socket's drop count since it was opened (32 bits, wraps): add what is new
        std::uint32_t dropped = 0;
        std::memcpy(&dropped, CMSG_DATA(c), sizeof(dropped));
        kernel_drops_ += static_cast<std::uint32_t>(dropped - last_kernel_drop_count_);
        last_kernel_drop_count_ = dropped;
      }
    }
    return static_cast<std::size_t>(bytes);
  }
}

bool UdpEndpoint::SendTo(std::span<const std::uint8_t> datagram, const Endpoint& to) {
  asio::error_code error;
  const std::size_t sent = socket_.send_to(asio::buffer(datagram.data(), datagram.size()), to, 0, error);
  return !error && sent == datagram.size();
}

bool UdpEndpoint::WaitReadable(std::chrono::milliseconds timeout) {
  pollfd fd{};
  fd.fd = socket_.native_handle();
  fd.events = POLLIN;
  return ::poll(&fd, 1, static_cast<int>(timeout.count())) > 0;
}

}  // namespace haptex::net
