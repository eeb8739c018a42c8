#include "libs/net/drop_reason.h"

namespace haptex::net {

std::string_view DropReasonName(DropReason reason) {
  switch (reason) {
    case DropReason::kNone:
      return "accepted";
    case DropReason::kTruncated:
      return "truncated";
    case DropReason::kOversized:
      return "oversized";
    case DropReason::kBadMagic:
      return "bad_magic";
    case DropReason::kBadMac:
      return "bad_mac";
    case DropReason::kUnparsable:
      return "unparsable";
    case DropReason::kWrongVersion:
      return "wrong_version";
    case DropReason::kWrongSession:
      return "wrong_session";
    case DropReason::kWrongDestination:
      return "wrong_destination";
    case DropReason::kMissingSender:
      return "missing_sender";
    case DropReason::kUnknownBody:
      return "unknown_body";
    case DropReason::kStaleEpoch:
      return "stale_epoch";
    case DropReason::kReplayed:
      return "replayed";
    case DropReason::kStale:
      return "stale";
    case DropReason::kTooManySenders:
      return "too_many_senders";
    case DropReason::kSendFailed:
      return "send_failed";
    case DropReason::kCount:
      break;
  }
  return "invalid";
}

std::uint64_t DropCounters::TotalDropped() const {
  std::uint64_t total = 0;
  for (std::size_t i = 1; i < kDropReasonCount; ++i) {
    if (static_cast<DropReason>(i) != DropReason::kSendFailed) total += counts_[i];
  }
  return total;
}

}  // namespace haptex::net
