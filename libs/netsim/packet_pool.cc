#include "libs/netsim/packet_pool.h"

#include <stdexcept>

namespace haptex::netsim {

PacketPool::PacketPool(const PacketPoolSizes& sizes) : sizes_(sizes) {
  if (sizes.small_bytes == 0 || sizes.large_bytes < sizes.small_bytes || sizes.small_count + sizes.large_count == 0) {
    throw std::invalid_argument("packet pool: buffer sizes and counts must be > 0, large >= small");
  }
  if (sizes.small_count + sizes.large_count > (std::size_t{1} << 31)) {
    throw std::invalid_argument("packet pool: at most 2^31 buffers");
  }
  // default-initialised on purpose: pages are only touched (committed) when a buffer is used
  small_.reset(new std::uint8_t[sizes.small_bytes * sizes.small_count]);
  large_.reset(new std::uint8_t[sizes.large_bytes * sizes.large_count]);
  free_small_.reserve(sizes.small_count);
  free_large_.reserve(sizes.large_count);
  // reversed, so buffers are handed out from id 0 up
  for (std::size_t i = sizes.small_count; i-- > 0;) free_small_.push_back(static_cast<std::uint32_t>(i));
  for (std::size_t i = sizes.large_count; i-- > 0;) {
    free_large_.push_back(static_cast<std::uint32_t>(sizes.small_count + i));
  }
}

std::size_t PacketPool::FreeFor(std::size_t size_bytes) const {
  if (size_bytes > sizes_.large_bytes) return 0;
  return (size_bytes <= sizes_.small_bytes ? free_small_.size() : 0) + free_large_.size();
}

std::optional<std::uint32_t> PacketPool::Acquire(std::size_t size_bytes) {
  if (size_bytes <= sizes_.small_bytes && !free_small_.empty()) {
    const std::uint32_t id = free_small_.back();
    free_small_.pop_back();
    return id;
  }
  if (size_bytes <= sizes_.large_bytes && !free_large_.empty()) {
    const std::uint32_t id = free_large_.back();
    free_large_.pop_back();
    return id;
  }
  return std::nullopt;
}

std::span<std::uint8_t> PacketPool::Buffer(std::uint32_t id) {
  if (id < sizes_.small_count) return {small_.get() + id * sizes_.small_bytes, sizes_.small_bytes};
  return {large_.get() + (id - sizes_.small_count) * sizes_.large_bytes, sizes_.large_bytes};
}

void PacketPool::Release(std::uint32_t id) { (id < sizes_.small_count ? free_small_ : free_large_).push_back(id); }

}  // namespace haptex::netsim
