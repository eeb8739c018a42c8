#pragma once
// CRC-32C (Castagnoli), the checksum that protects GRAB datagrams (docs/grab-protocol.md).

#include <cstddef>
#include <cstdint>
#include <span>

namespace haptex::device {

/// CRC-32C of `bytes`: reflected polynomial 0x82F63B78, initial value 0xFFFFFFFF, final XOR
/// 0xFFFFFFFF (so Crc32c("123456789") == 0xE3069283). Table driven, no allocation.
std::uint32_t Crc32c(std::span<const std::byte> bytes);

}  // namespace haptex::device
