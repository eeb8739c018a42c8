#pragma once
// Preallocated buffers for datagrams held by a relay, in two sizes: many small ones for the usual
// datagrams, a few of the largest UDP size. Buffers are reserved at construction and only
// touched when used, so no datagram allocates and unused buffers cost no memory.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

namespace haptex::netsim {

struct PacketPoolSizes {
  std::size_t small_bytes = 2048;
  std::size_t small_count = 8192;
  std::size_t large_bytes = 65536;
  std::size_t large_count = 64;
};

class PacketPool final {
 public:
  /// Throws std::invalid_argument for zero sizes, large_bytes < small_bytes, or more than 2^31
  /// buffers.
  explicit PacketPool(const PacketPoolSizes& sizes);

  /// How many datagrams of `size_bytes` could still be held.
  std::size_t FreeFor(std::size_t size_bytes) const;
  /// A free buffer of at least `size_bytes` (small first), or nullopt.
  std::optional<std::uint32_t> Acquire(std::size_t size_bytes);
  /// The whole buffer behind an id from Acquire.
  std::span<std::uint8_t> Buffer(std::uint32_t id);
  /// Returns a buffer from Acquire.
  void Release(std::uint32_t id);

  std::size_t capacity() const { return sizes_.small_count + sizes_.large_count; }
  std::size_t in_use() const { return capacity() - free_small_.size() - free_large_.size(); }

 private:
  // ids below small_count are small buffers, the rest large
  PacketPoolSizes sizes_;
  std::unique_ptr<std::uint8_t[]> small_;
  std::unique_ptr<std::uint8_t[]> large_;
  std::vector<std::uint32_t> free_small_;
  std::vector<std::uint32_t> free_large_;
};

}  // namespace haptex::netsim
