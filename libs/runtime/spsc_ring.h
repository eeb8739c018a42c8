#pragma once
// A bounded single-producer single-consumer ring for when every item matters (events, frames, or
// ownership handed between threads: items may be move-only, e.g. std::unique_ptr). Lock-free,
// allocation-free; a full ring refuses the push (leaving the item with the caller), and the
// caller counts the drop.

#include <array>
#include <atomic>
#include <cstddef>
#include <utility>

namespace haptex::runtime {

template <class T, std::size_t kCapacity>
class SpscRing final {
  static_assert(kCapacity >= 2 && (kCapacity & (kCapacity - 1)) == 0, "capacity must be a power of two");

 public:
  bool TryPush(const T& item) {
    const std::size_t head = head_.load(std::memory_order_relaxed);
    if (head - tail_.load(std::memory_order_acquire) == kCapacity) return false;
    items_[head & (kCapacity - 1)] = item;
    head_.store(head + 1, std::memory_order_release);
    return true;
  }
  /// Moves `item` in; on a full ring `item` is left as it was.
  bool TryPush(T&& item) {
    const std::size_t head = head_.load(std::memory_order_relaxed);
    if (head - tail_.load(std::memory_order_acquire) == kCapacity) return false;
    items_[head & (kCapacity - 1)] = std::move(item);
    head_.store(head + 1, std::memory_order_release);
    return true;
  }

  bool TryPop(T* item) {
    const std::size_t tail = tail_.load(std::memory_order_relaxed);
    if (tail == head_.load(std::memory_order_acquire)) return false;
    *item = std::move(items_[tail & (kCapacity - 1)]);
    tail_.store(tail + 1, std::memory_order_release);
    return true;
  }

  std::size_t size() const { return head_.load(std::memory_order_acquire) - tail_.load(std::memory_order_acquire); }

 private:
  std::array<T, kCapacity> items_{};
  alignas(64) std::atomic<std::size_t> head_{0};
  alignas(64) std::atomic<std::size_t> tail_{0};
};

}  // namespace haptex::runtime
