#pragma once
// CRC-32 as MCAP uses it (the zlib / IEEE 802.3 one: reflected polynomial 0xEDB88320, initial
// value and final XOR 0xFFFFFFFF). Feed bytes in pieces; value() is the CRC of all of them.

#include <cstdint>
#include <string_view>

namespace haptex::mcap {

class Crc32 {
 public:
  Crc32& Update(std::string_view bytes);
  std::uint32_t value() const { return ~state_; }

 private:
  std::uint32_t state_ = 0xFFFFFFFFu;
};

/// The CRC-32 of `bytes`.
inline std::uint32_t Crc32Of(std::string_view bytes) { return Crc32().Update(bytes).value(); }

}  // namespace haptex::mcap
