#include "libs/mcap/crc32.h"

#include <array>

namespace haptex::mcap {
namespace {

constexpr std::array<std::uint32_t, 256> MakeTable() {
  std::array<std::uint32_t, 256> table{};
  for (std::uint32_t i = 0; i < 256; ++i) {
    std::uint32_t c = i;
    for (int bit = 0; bit < 8; ++bit) c = (c & 1u) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
    table[i] = c;
  }
  return table;
}

constexpr std::array<std::uint32_t, 256> kTable = MakeTable();

}  // namespace

Crc32& Crc32::Update(std::string_view bytes) {
  std::uint32_t c = state_;
  for (char ch : bytes) c = kTable[(c ^ static_cast<std::uint8_t>(ch)) & 0xFFu] ^ (c >> 8);
  state_ = c;
  return *this;
}

}  // namespace haptex::mcap
