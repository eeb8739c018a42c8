#pragma once
// Sliding-window replay protection per sender (RFC 4303 style): accepts each sequence number once,
// in any order within the last kWindow numbers; older ones are stale.

#include <array>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "libs/net/drop_reason.h"

namespace haptex::net {

class ReplayWindow final {
 public:
  static constexpr std::uint64_t kWindow = 64;

  /// Returns kNone and records the sequence, or kReplayed / kStale without recording.
  DropReason Check(std::uint64_t sequence);
  /// Forgets everything (the sender restarted).
  void Reset() {
    highest_ = 0;
    seen_ = 0;
  }
  std::uint64_t highest() const { return highest_; }

 private:
  std::uint64_t highest_ = 0;  // 0: nothing seen yet (sequences start at 1)
  std::uint64_t seen_ = 0;     // bit i: highest_ - i was seen
};

/// Replay windows for a bounded number of senders, identified by name and start epoch.
/// Fixed capacity: no allocation after construction.
class SenderTable final {
 public:
  static constexpr std::size_t kMaxSenders = 32;
  static constexpr std::size_t kMaxNameBytes = 47;

  /// Checks (sender, epoch, sequence). A larger epoch than known resets the sender's window
  /// (counted in restarts()); a smaller one is kStaleEpoch.
  DropReason Check(std::string_view sender, std::uint64_t epoch, std::uint64_t sequence);
  std::uint64_t restarts() const { return restarts_; }
  std::size_t size() const { return used_; }

 private:
  struct Entry {
    std::array<char, kMaxNameBytes + 1> name{};
    std::uint8_t name_length = 0;
    std::uint64_t epoch = 0;
    ReplayWindow window;
  };
  std::array<Entry, kMaxSenders> entries_{};
  std::size_t used_ = 0;
  std::uint64_t restarts_ = 0;
};

}  // namespace haptex::net
