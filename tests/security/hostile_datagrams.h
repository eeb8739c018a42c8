#pragma once
// What an attacker on the loopback sends to a haptex port, datagram by datagram, each with the
// drop reason the receiver must count it under. With the session key it also holds what a
// captured datagram gives: authentic envelopes to replay, to send to the wrong destination, from
// an old epoch. Every kind is counted under exactly one reason, so a campaign can compare the
// receiver's counters with what it sent.

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "libs/net/drop_reason.h"
#include "libs/net/session_key.h"

namespace haptex::security {

struct HostileDatagram {
  std::vector<std::uint8_t> bytes;
  net::DropReason expected = net::DropReason::kNone;  ///< kNone: authentic and harmless, accepted
};

/// Per kind: `count` datagrams (replays and stale ones come after the originals they repeat).
struct HostileMix {
  int garbage = 20;            ///< random bytes without the magic: bad_magic
  int truncated = 20;          ///< shorter than the framing: truncated
  int oversized = 2;           ///< over the 60,000-byte maximum: oversized
  int bit_flips = 20;          ///< an authentic datagram with one bit flipped: bad_mac
  int wrong_key = 20;          ///< sealed with another key: bad_mac
  int unparsable = 20;         ///< authentic bytes that are no Envelope: unparsable
  int wrong_version = 20;      ///< Envelope.version 2: wrong_version
  int wrong_session = 20;      ///< another session id: wrong_session
  int wrong_destination = 20;  ///< addressed to another service: wrong_destination
  int missing_sender = 20;     ///< no sender name: missing_sender
  int unknown_body = 20;       ///< no body: unknown_body
  int replays = 20;            ///< originals (accepted), then each again: replayed
  int stale = 5;               ///< originals pushed out of the 64-wide window, then again: stale
  int stale_epoch = 20;        ///< the intruder from an earlier start: stale_epoch
};

/// The datagrams of `mix` addressed to `destination` (a name the receiver answers to), in send
/// order, from a sender named `intruder` the receiver has not heard before. Authentic ones carry a
/// NetProbe, which no service acts on.
std::vector<HostileDatagram> HostileEnvelopes(const net::SessionKey& key, const std::string& destination,
                                              const std::string& intruder, const HostileMix& mix, std::mt19937& rng);

/// Sum of `expected` over datagrams, per reason.
std::vector<std::uint64_t> ExpectedDrops(const std::vector<HostileDatagram>& datagrams);

/// GRAB protocol datagrams from a stranger: half well-formed frames (a StatusFrame to a host, a
/// CommandFrame asking 20 N with force enabled to a controller, sequences far ahead), half
/// garbage. A receiver that takes frames only from its configured peer counts every one as from
/// a stranger.
std::vector<std::vector<std::uint8_t>> ForgedStatusFrames(int count, std::mt19937& rng);
std::vector<std::vector<std::uint8_t>> ForgedCommandFrames(int count, std::mt19937& rng);

}  // namespace haptex::security
