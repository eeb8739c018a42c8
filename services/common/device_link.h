#pragma once
// The raw UDP link between the bridge and the GRAB controller (or its mock), in the controller's
// own fixed binary protocol rather than haptex envelopes: one socket, one configured peer, a fixed
// receive buffer, bounded reads with the kernel's arrival stamps. Used from both ends.

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "libs/net/udp_address.h"
#include "libs/net/udp_endpoint.h"

namespace haptex::services {

class DeviceLink final {
 public:
  /// Binds `bind_address`; datagrams go to `peer_address`. Throws std::invalid_argument /
  /// std::runtime_error for bad or unusable addresses.
  DeviceLink(const std::string& bind_address, const std::string& peer_address)
      : socket_(bind_address), peer_(net::ResolveUdpAddress(peer_address)) {}

  /// Reads up to `max_datagrams` waiting datagrams: handler(std::span<const std::byte> bytes,
  /// std::int64_t arrival_ns, bool from_peer). A datagram larger than the buffer arrives cut (the
  /// protocol's decoder refuses it as too long).
  template <class Handler>
  void Drain(Handler&& handler, int max_datagrams = 64) {
    for (int i = 0; i < max_datagrams; ++i) {
      std::int64_t arrival_ns = 0;
      const auto bytes = socket_.ReceiveOne(rx_, &from_, &arrival_ns);
      if (!bytes) return;
      handler(std::as_bytes(std::span(rx_.data(), std::min(*bytes, rx_.size()))), arrival_ns, from_ == peer_);
    }
  }

  bool Send(std::span<const std::byte> datagram) {
    return socket_.SendTo(std::span(reinterpret_cast<const std::uint8_t*>(datagram.data()), datagram.size()), peer_);
  }

  /// Datagrams the kernel dropped for a full socket queue (a flood on the controller port).
  std::uint64_t kernel_drops() const { return socket_.kernel_drops(); }

  std::string local_address() const { return net::FormatUdpAddress(socket_.local_endpoint()); }

 private:
  net::UdpEndpoint socket_;
  net::UdpEndpoint::Endpoint peer_;
  net::UdpEndpoint::Endpoint from_;
  std::array<std::uint8_t, 2048> rx_{};
};

}  // namespace haptex::services
