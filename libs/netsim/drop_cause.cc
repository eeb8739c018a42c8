#include "libs/netsim/drop_cause.h"

namespace haptex::netsim {

std::string_view DropCauseName(DropCause cause) {
  switch (cause) {
    case DropCause::kLoss:
      return "loss";
    case DropCause::kBurstLoss:
      return "burst_loss";
    case DropCause::kQueueOverflow:
      return "queue_overflow";
    case DropCause::kOversize:
      return "oversize";
    case DropCause::kSendFailed:
      return "send_failed";
    case DropCause::kNoDestination:
      return "no_destination";
    case DropCause::kUnsentAtStop:
      return "unsent_at_stop";
    case DropCause::kOutage:
      return "outage";
  }
  return "unknown";
}

std::uint64_t DropCounts::Total() const {
  std::uint64_t total = 0;
  for (const std::uint64_t count : counts_) total += count;
  return total;
}

}  // namespace haptex::netsim
