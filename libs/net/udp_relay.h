#pragma once
// A user-space network impairment relay between a client side and a server side, each direction
// impaired by its own netsim::ImpairmentModel (delay, jitter, loss, bursts, reordering,
// duplication, rate limit).
//
//   clients --> listen socket ==forward==> upstream socket --> `to` (the server side)
//   clients <-- listen socket <==back===== upstream socket <-- anyone (the server side)
//
// Replies go to `back_to` when set, else to the last client seen: haptex services send to the
// peer on their command line, not to the source of what they received, so a service configured
// to send to the relay's fixed upstream port (`upstream_bind`) reaches a client named by
// `back_to`. One thread; buffers preallocated; steady-clock times, from the kernel's receive
// stamp to the send.

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "libs/net/udp_endpoint.h"
#include "libs/netsim/impairment_config.h"
#include "libs/netsim/impairment_model.h"
#include "libs/netsim/packet_pool.h"
#include "libs/netsim/release_queue.h"

namespace haptex::net {

struct UdpRelayConfig {
  std::string listen_address;         // host:port clients send to
  std::string to_address;             // host:port of the server side
  std::string upstream_bind_address;  // empty: any address of to's family, a free port
  std::string back_to_address;        // empty: replies go to the last client seen
  netsim::ImpairmentConfig forward;   // listen -> to
  netsim::ImpairmentConfig back;      // server side -> client
  std::uint64_t forward_seed = 1;
  std::uint64_t back_seed = 2;
  double duration_s = 0.0;          // 0: until stopped
  netsim::PacketPoolSizes buffers;  // per direction
};

class UdpRelay final {
 public:
  using Endpoint = UdpEndpoint::Endpoint;

  /// Validates the configuration and binds both sockets. Throws std::invalid_argument for a bad
  /// address or impairment parameter, std::runtime_error when a socket cannot be bound.
  explicit UdpRelay(const UdpRelayConfig& config);
  UdpRelay(const UdpRelay&) = delete;
  UdpRelay& operator=(const UdpRelay&) = delete;

  Endpoint listen_endpoint() const { return listen_.local_endpoint(); }
  Endpoint upstream_endpoint() const { return upstream_.local_endpoint(); }

  /// Relays until stop_requested() is true (asked at least every 100 ms) or duration_s has
  /// passed. Copies still held then are counted as unsent_at_stop. Faults (bad datagrams, full
  /// buffers, refused sends) are counted, never thrown.
  void Run(const std::function<bool()>& stop_requested);

  const netsim::ImpairmentStats& forward_stats() const { return forward_.model.stats(); }
  const netsim::ImpairmentStats& back_stats() const { return back_.model.stats(); }

 private:
  struct Direction {
    Direction(const netsim::ImpairmentConfig& config, std::uint64_t seed, const netsim::PacketPoolSizes& buffers,
              UdpEndpoint* in_socket, UdpEndpoint* out_socket, std::optional<Endpoint> fixed_destination);
    netsim::ImpairmentModel model;
    netsim::PacketPool pool;
    netsim::ReleaseQueue queue;
    UdpEndpoint* in;
    UdpEndpoint* out;
    std::optional<Endpoint> destination;  // nullopt: the last client seen
  };

  void ReceiveBatch(Direction* direction);
  void SendDue(Direction* direction, std::int64_t now_ns);
  void DropHeld(Direction* direction);

  UdpEndpoint listen_;
  UdpEndpoint upstream_;
  Direction forward_;
  Direction back_;
  std::optional<Endpoint> last_client_;
  std::int64_t duration_ns_;
  std::vector<std::uint8_t> scratch_;  // one received datagram, before it is copied to the pool
};

}  // namespace haptex::net
