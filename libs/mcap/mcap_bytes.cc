#include "libs/mcap/mcap_bytes.h"

#include <limits>

#include "libs/mcap/mcap_error.h"

namespace haptex::mcap {

void ByteWriter::String(std::string_view text) {
  if (text.size() > std::numeric_limits<std::uint32_t>::max()) {
    throw McapError("a field of " + std::to_string(text.size()) + " bytes is longer than a uint32 length says");
  }
  U32(static_cast<std::uint32_t>(text.size()));
  Raw(text);
}

std::string_view ByteReader::Take(std::uint64_t n, std::string_view field) {
  if (n > remaining()) {
    throw McapError(std::string(what_) + " record: " + std::string(field) + " needs " + std::to_string(n) +
                        " bytes, only " + std::to_string(remaining()) + " left in the record",
                    offset());
  }
  const std::string_view out = bytes_.substr(at_, static_cast<std::size_t>(n));
  at_ += static_cast<std::size_t>(n);
  return out;
}

std::uint64_t ByteReader::Little(int bytes) {
  const std::string_view field = Take(static_cast<std::uint64_t>(bytes), "an integer field");
  std::uint64_t v = 0;
  for (int i = 0; i < bytes; ++i) v |= static_cast<std::uint64_t>(static_cast<std::uint8_t>(field[i])) << (8 * i);
  return v;
}

}  // namespace haptex::mcap
