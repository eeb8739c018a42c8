#pragma once
// One service's authenticated UDP link: a UdpEndpoint, an EnvelopeSealer for what it sends, an
// EnvelopeOpener for what it receives, and fixed buffers. After warm-up neither Send nor Drain
// allocates: received Envelopes live on an arena over a preallocated block, reset per datagram.
//
// Threads: one thread may send while another drains (they touch disjoint state, and the kernel
// socket allows it); two threads must not both send or both drain.

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <google/protobuf/arena.h>

#include "libs/base/clock.h"
#include "libs/net/envelope_codec.h"
#include "libs/net/udp_endpoint.h"

namespace haptex::net {

struct MessengerConfig {
  std::string bind_address = "127.0.0.1:0";
  SenderIdentity identity;                 // identity.epoch 0: the current wall time
  std::size_t max_datagram_bytes = 60000;  // larger datagrams are dropped as oversized
  std::size_t arena_bytes = 1 << 20;       // holds the largest Envelope parsed
  // Names besides identity.name that peers address this messenger by (Envelope.destination), e.g.
  // the device bridge is local_contact's "bridge"; anything addressed otherwise is dropped.
  std::vector<std::string> also_known_as;
};

class Messenger final {
 public:
  using Endpoint = UdpEndpoint::Endpoint;
  using PeerId = std::size_t;
  static constexpr std::size_t kDefaultDrainBound = 64;

  /// Binds the socket. Throws std::invalid_argument / std::runtime_error for a bad configuration.
  Messenger(const SessionKey& key, MessengerConfig config);
  Messenger(const Messenger&) = delete;
  Messenger& operator=(const Messenger&) = delete;

  /// Names a peer once at configuration time; the hot path then sends by PeerId.
  PeerId AddPeer(std::string_view name, std::string_view address);
  PeerId AddPeer(std::string_view name, const Endpoint& endpoint);
  const std::string& peer_name(PeerId peer) const { return peers_.at(peer).name; }

  /// Seals `body` in an Envelope and sends it. False (and counted) when it does not fit or the
  /// socket refuses; never blocks.
  template <class Body>
  bool Send(PeerId peer, const Body& body) {
    return SendTo(peers_[peer].endpoint, peers_[peer].name, body);
  }
  /// To an address that is no configured peer (a reply), addressed to `destination` (the name the
  /// receiver answers to, e.g. the sender name of the datagram replied to).
  template <class Body>
  bool SendTo(const Endpoint& to, std::string_view destination, const Body& body) {
    const std::size_t bytes = sealer_.Seal(body, base::SteadyNowNs(), destination, send_buffer_);
    return Transmit(bytes, to);
  }
  /// Same, for a body chosen at run time (`body_field_number`: its field in the Envelope oneof).
  bool SendBody(PeerId peer, const google::protobuf::MessageLite& body, int body_field_number) {
    const std::size_t bytes =
        sealer_.SealBody(body, body_field_number, base::SteadyNowNs(), peers_[peer].name, send_buffer_);
    return Transmit(bytes, peers_[peer].endpoint);
  }

  /// Receives waiting datagrams, at most max_datagrams of them (accepted or dropped) and, when
  /// `until_ns` is given, only until the steady clock passes it (checked every 8 datagrams), and
  /// calls handler(const v1::Envelope&, const Endpoint& from) for each accepted one. The Envelope
  /// is valid during the call only. Returns the number accepted. The bounds keep a flood from
  /// holding a hot loop: what is left waits for the next call.
  template <class Handler>
  std::size_t Drain(Handler&& handler, std::size_t max_datagrams = kDefaultDrainBound,
                    std::int64_t until_ns = std::numeric_limits<std::int64_t>::max()) {
    std::size_t accepted = 0;
    Endpoint from;
    for (std::size_t i = 0; i < max_datagrams; ++i) {
      if (i % 8 == 7 && until_ns != std::numeric_limits<std::int64_t>::max() && base::SteadyNowNs() >= until_ns) break;
      const v1::Envelope* envelope = nullptr;
      const Received received = ReceiveOne(&from, &envelope);
      if (received == Received::kNothingWaiting) break;
      if (received == Received::kDropped) continue;
      ++accepted;
      handler(*envelope, from);
    }
    return accepted;
  }

  /// Blocks until a datagram waits or the timeout passes (receive-only threads).
  bool WaitReadable(std::chrono::milliseconds timeout) { return endpoint_.WaitReadable(timeout); }

  /// Counters of the draining thread (read them there, or after it stopped).
  const DropCounters& received() const { return opener_.counters(); }
  std::uint64_t sent() const { return sent_; }
  std::uint64_t send_failures() const { return send_failures_; }
  /// Bytes on the wire (UDP payload) of the last datagram sent.
  std::size_t last_sent_bytes() const { return last_sent_bytes_; }
  std::uint64_t sender_restarts() const { return opener_.senders().restarts(); }
  /// Datagrams the kernel dropped for a full socket queue before this messenger could read them.
  std::uint64_t kernel_drops() const { return endpoint_.kernel_drops(); }
  Endpoint local_endpoint() const { return endpoint_.local_endpoint(); }
  std::uint16_t local_port() const { return endpoint_.local_port(); }
  const SenderIdentity& identity() const { return sealer_.identity(); }

 private:
  struct Peer {
    std::string name;
    Endpoint endpoint;
  };
  enum class Received { kNothingWaiting, kDropped, kAccepted };

  bool Transmit(std::size_t bytes, const Endpoint& to);
  Received ReceiveOne(Endpoint* from, const v1::Envelope** envelope);

  UdpEndpoint endpoint_;
  EnvelopeSealer sealer_;
  EnvelopeOpener opener_;
  std::vector<Peer> peers_;
  std::vector<std::uint8_t> send_buffer_;
  std::vector<std::uint8_t> receive_buffer_;
  std::vector<char> arena_block_;
  std::unique_ptr<google::protobuf::Arena> arena_;
  std::uint64_t sent_ = 0;
  std::uint64_t send_failures_ = 0;
  std::size_t last_sent_bytes_ = 0;
};

/// Newest-wins gate for a state channel: accepts an Envelope only if it is newer than the last
/// one accepted (same sender epoch and higher sequence, or a later epoch).
class NewestWins final {
 public:
  bool Accept(const v1::Envelope& envelope);

 private:
  std::uint64_t epoch_ = 0;
  std::uint64_t sequence_ = 0;
};

/// Nanoseconds since the Unix epoch, for sender epochs.
std::uint64_t WallClockNs();

}  // namespace haptex::net
