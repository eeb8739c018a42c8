#pragma once
// Copies waiting for their release time, earliest first; copies due at the same time leave in
// the order they were scheduled (so a relay without jitter or reordering is FIFO). Fixed
// capacity: no allocation after construction.

#include <cstddef>
#include <cstdint>
#include <vector>

namespace haptex::netsim {

struct ScheduledCopy {
  std::int64_t release_ns = 0;
  std::int64_t arrival_ns = 0;
  std::uint64_t sequence = 0;  // the model's Decision::sequence
  std::uint32_t buffer = 0;    // the caller's handle to the bytes (e.g. a PacketPool id)
  std::uint32_t size_bytes = 0;
};

class ReleaseQueue final {
 public:
  explicit ReleaseQueue(std::size_t capacity);

  /// False (and nothing queued) when full.
  bool Push(const ScheduledCopy& copy);
  /// The earliest copy; the queue must not be empty.
  const ScheduledCopy& Top() const { return heap_.front().copy; }
  /// Removes and returns the earliest copy; the queue must not be empty.
  ScheduledCopy Pop();

  bool empty() const { return heap_.empty(); }
  std::size_t size() const { return heap_.size(); }
  std::size_t capacity() const { return capacity_; }

 private:
  struct Entry {
    ScheduledCopy copy;
    std::uint64_t order;  // push count: ties leave first-in first-out
  };
  static bool Later(const Entry& a, const Entry& b);

  std::size_t capacity_;
  std::vector<Entry> heap_;  // reserved to capacity_ up front
  std::uint64_t pushed_ = 0;
};

}  // namespace haptex::netsim
