#pragma once
// Datagram framing: magic, nonce, one serialized haptex.v1.Envelope, and a tag over all three.
//
//   offset 0        4 bytes   magic "HPX" + framing version 0x02
//   offset 4        24 bytes  random nonce
//   offset 28       n bytes   Envelope (protobuf wire format)
//   offset 28 + n   16 bytes  XChaCha20-Poly1305 tag with bytes [0, 28 + n) as associated data
//
// Opening checks, in order: size, magic, MAC, parse, version, session, body, sender epoch and
// sequence window. Only authenticated bytes are parsed. Neither side allocates per datagram once
// warmed up (the caller provides the Envelope, typically on a reset arena).

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <google/protobuf/message_lite.h>

#include "haptex/v1/envelope.pb.h"
#include "libs/net/datagram_mac.h"
#include "libs/net/drop_reason.h"
#include "libs/net/envelope_body.h"
#include "libs/net/replay_window.h"
#include "libs/net/session_key.h"

namespace haptex::net {

inline constexpr std::array<std::uint8_t, 4> kDatagramMagic = {'H', 'P', 'X', 0x02};
inline constexpr std::uint32_t kEnvelopeVersion = 1;
inline constexpr std::size_t kDatagramHeaderBytes = kDatagramMagic.size() + DatagramMac::kNonceBytes;
inline constexpr std::size_t kDatagramOverheadBytes = kDatagramHeaderBytes + DatagramMac::kTagBytes;
/// Largest payload of one IPv4 UDP datagram.
inline constexpr std::size_t kMaxUdpPayloadBytes = 65507;

/// Who sends: the name, start epoch and session written into every outgoing Envelope.
struct SenderIdentity {
  std::string name;              // e.g. "device_bridge"; at most SenderTable::kMaxNameBytes
  std::uint64_t epoch = 0;       // start time [ns since the Unix epoch]; must be > 0
  std::uint64_t session_id = 0;  // must be > 0
};

class EnvelopeSealer final {
 public:
  /// Throws std::invalid_argument for an empty or too long name, or a zero epoch or session.
  EnvelopeSealer(const SessionKey& key, SenderIdentity identity);

  /// Writes a datagram carrying `body` into `out`. Returns its size, or 0 when it does not fit
  /// (nothing is consumed from the sequence then).
  /// `destination`: the receiver's name (Envelope.destination), at most SenderTable::kMaxNameBytes.
  template <class Body>
  std::size_t Seal(const Body& body, std::int64_t send_time_ns, std::string_view destination,
                   std::span<std::uint8_t> out) {
    return SealBody(body, EnvelopeBody<Body>::kFieldNumber, send_time_ns, destination, out);
  }

  /// Same, for a body chosen at run time (field number of the Envelope oneof).
  std::size_t SealBody(const google::protobuf::MessageLite& body, int body_field_number, std::int64_t send_time_ns,
                       std::string_view destination, std::span<std::uint8_t> out);

  /// Seals an Envelope whose header fields are written by the caller, as is (tests and tools
  /// that need to forge old epochs or foreign sessions).
  std::size_t SealRaw(const v1::Envelope& envelope, std::span<std::uint8_t> out);

  std::uint64_t next_sequence() const { return next_sequence_; }
  const SenderIdentity& identity() const { return identity_; }

 private:
  DatagramMac mac_;
  NonceSequence nonces_;
  SenderIdentity identity_;
  std::uint64_t next_sequence_ = 1;
};

class EnvelopeOpener final {
 public:
  EnvelopeOpener(const SessionKey& key, std::uint64_t session_id, std::size_t max_datagram_bytes = 60000);

  /// Authenticates, parses into *envelope and checks it. Counts the outcome.
  DropReason Open(std::span<const std::uint8_t> datagram, v1::Envelope* envelope);

  /// The names this receiver answers to (Envelope.destination): an envelope addressed to another
  /// is dropped as wrong_destination. None (the default): not checked (tools reading any).
  void AcceptDestinations(std::vector<std::string> names) { destinations_ = std::move(names); }

  /// Counts a datagram rejected before it reached Open (e.g. larger than the receive buffer).
  void CountDrop(DropReason reason) { counters_.Add(reason); }

  const DropCounters& counters() const { return counters_; }
  const SenderTable& senders() const { return senders_; }
  std::size_t max_datagram_bytes() const { return max_datagram_bytes_; }

 private:
  DropReason Classify(std::span<const std::uint8_t> datagram, v1::Envelope* envelope);

  DatagramMac mac_;
  std::uint64_t session_id_;
  std::size_t max_datagram_bytes_;
  SenderTable senders_;
  DropCounters counters_;
  std::vector<std::string> destinations_;
};

}  // namespace haptex::net
