#pragma once
// Latest-value hand-off from one writer thread to one reader thread (a triple buffer): the writer
// never waits, the reader gets the newest complete value, nothing is ever torn. For state such as
// finger poses where only the newest value matters.

#include <array>
#include <atomic>
#include <cstdint>
#include <type_traits>

namespace haptex::runtime {

template <class T>
class LatestMailbox final {
  static_assert(std::is_copy_assignable_v<T>, "mailbox values are copied");

 public:
  LatestMailbox() = default;
  explicit LatestMailbox(const T& initial) { slots_.fill(initial); }
  LatestMailbox(const LatestMailbox&) = delete;
  LatestMailbox& operator=(const LatestMailbox&) = delete;

  /// Writer thread only. Copy assignment of T must not allocate for the hot path to stay clean.
  void Write(const T& value) {
    slots_[back_] = value;
    const std::uint8_t previous = middle_.exchange(static_cast<std::uint8_t>(back_ | kFresh),
                                                   std::memory_order_acq_rel);
    back_ = previous & kIndexMask;
  }

  /// Reader thread only. Copies the newest value into *out; false when nothing new was written
  /// since the last successful Read.
  bool Read(T* out) {
    if ((middle_.load(std::memory_order_acquire) & kFresh) == 0) return false;
    const std::uint8_t previous = middle_.exchange(front_, std::memory_order_acq_rel);
    front_ = previous & kIndexMask;
    *out = slots_[front_];
    return true;
  }

 private:
  static constexpr std::uint8_t kFresh = 0x4;
  static constexpr std::uint8_t kIndexMask = 0x3;

  std::array<T, 3> slots_{};
  std::uint8_t back_ = 0;                 // writer's slot
  std::uint8_t front_ = 1;                // reader's slot
  std::atomic<std::uint8_t> middle_{2};   // the slot in between, plus the fresh flag
};

}  // namespace haptex::runtime
