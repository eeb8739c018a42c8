#pragma once
// Why a received datagram was dropped. Every drop is counted; none throws or blocks.

#include <array>
#include <cstddef>
#include <cstdint>
#include <string_view>

namespace haptex::net {

enum class DropReason : std::uint8_t {
  kNone = 0,          // accepted
  kTruncated,         // shorter than magic + MAC
  kOversized,         // longer than the configured maximum datagram
  kBadMagic,          // not a haptex datagram (or another wire version of the framing)
  kBadMac,            // authentication failed: wrong key or altered bytes
  kUnparsable,        // authentic but not a valid Envelope
  kWrongVersion,      // Envelope.version differs from ours
  kWrongSession,      // authentic datagram of another session (e.g. an old run)
  kWrongDestination,  // authentic, but addressed to another service (a replay across destinations)
  kMissingSender,     // no sender name or epoch
  kUnknownBody,       // no body we know (a newer schema, or empty)
  kStaleEpoch,        // from an earlier start of a sender we have heard since it restarted
  kReplayed,          // sequence already seen
  kStale,             // sequence older than the replay window
  kTooManySenders,    // the sender table is full
  kSendFailed,        // outgoing: the socket refused (would block, unreachable, too large)
  kCount
};

inline constexpr std::size_t kDropReasonCount = static_cast<std::size_t>(DropReason::kCount);

/// Stable lower_snake_case name, as printed in Health and summaries.
std::string_view DropReasonName(DropReason reason);

/// One counter per reason (kNone counts accepted datagrams).
class DropCounters {
 public:
  void Add(DropReason reason) { ++counts_[static_cast<std::size_t>(reason)]; }
  std::uint64_t Get(DropReason reason) const { return counts_[static_cast<std::size_t>(reason)]; }
  std::uint64_t accepted() const { return Get(DropReason::kNone); }
  /// Every dropped datagram, whatever the reason (kSendFailed excluded: it is outgoing).
  std::uint64_t TotalDropped() const;

 private:
  std::array<std::uint64_t, kDropReasonCount> counts_{};
};

}  // namespace haptex::net
