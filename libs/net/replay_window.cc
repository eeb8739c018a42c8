#include "libs/net/replay_window.h"

#include <algorithm>
#include <cstring>

namespace haptex::net {

DropReason ReplayWindow::Check(std::uint64_t sequence) {
  if (sequence == 0) return DropReason::kStale;
  if (sequence > highest_) {
    const std::uint64_t shift = sequence - highest_;
    seen_ = shift >= kWindow ? 0 : seen_ << shift;
    seen_ |= 1;
    highest_ = sequence;
    return DropReason::kNone;
  }
  const std::uint64_t age = highest_ - sequence;
  if (age >= kWindow) return DropReason::kStale;
  const std::uint64_t bit = std::uint64_t{1} << age;
  if (seen_ & bit) return DropReason::kReplayed;
  seen_ |= bit;
  return DropReason::kNone;
}

DropReason SenderTable::Check(std::string_view sender, std::uint64_t epoch, std::uint64_t sequence) {
  if (sender.empty() || sender.size() > kMaxNameBytes || epoch == 0) {
    return DropReason::kMissingSender;
  }
  Entry* entry = nullptr;
  for (std::size_t i = 0; i < used_; ++i) {
    Entry& e = entries_[i];
    if (e.name_length == sender.size() && std::memcmp(e.name.data(), sender.data(), sender.size()) == 0) {
      entry = &e;
      break;
    }
  }
  if (entry == nullptr) {
    if (used_ == kMaxSenders) return DropReason::kTooManySenders;
    // take a slot only for a datagram that passes, so bad first datagrams cannot fill the table
    ReplayWindow fresh;
    const DropReason reason = fresh.Check(sequence);
    if (reason != DropReason::kNone) return reason;
    entry = &entries_[used_++];
    std::copy(sender.begin(), sender.end(), entry->name.begin());
    entry->name_length = static_cast<std::uint8_t>(sender.size());
    entry->epoch = epoch;
    entry->window = fresh;
    return DropReason::kNone;
  } else if (epoch < entry->epoch) {
    return DropReason::kStaleEpoch;
  } else if (epoch > entry->epoch) {
    // Check the new epoch's first sequence before committing, so a bad datagram cannot reset us.
    ReplayWindow fresh;
    const DropReason reason = fresh.Check(sequence);
    if (reason != DropReason::kNone) return reason;
    entry->epoch = epoch;
    entry->window = fresh;
    ++restarts_;
    return DropReason::kNone;
  }
  return entry->window.Check(sequence);
}

}  // namespace haptex::net
