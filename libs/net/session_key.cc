#include "libs/net/session_key.h"

#include <sodium.h>

#include <stdexcept>

#include "libs/net/sodium_init.h"

namespace haptex::net {

SessionKey SessionKey::FromHex(std::string_view hex) {
  while (!hex.empty() && (hex.front() == ' ' || hex.front() == '\n' || hex.front() == '\t' || hex.front() == '\r')) {
    hex.remove_prefix(1);
  }
  while (!hex.empty() && (hex.back() == ' ' || hex.back() == '\n' || hex.back() == '\t' || hex.back() == '\r')) {
    hex.remove_suffix(1);
  }
  if (hex.size() != 2 * kBytes) {
    throw std::invalid_argument("session key must be " + std::to_string(2 * kBytes) + " hex digits, got " +
                                std::to_string(hex.size()) + " characters");
  }
  SessionKey key;
  for (std::size_t i = 0; i < kBytes; ++i) {
    auto nibble = [&](char c) -> int {
      if (c >= '0' && c <= '9') return c - '0';
      if (c >= 'a' && c <= 'f') return c - 'a' + 10;
      if (c >= 'A' && c <= 'F') return c - 'A' + 10;
      throw std::invalid_argument(std::string("session key has a non-hex character '") + c + "'");
    };
    key.bytes_[i] = static_cast<std::uint8_t>(nibble(hex[2 * i]) * 16 + nibble(hex[2 * i + 1]));
  }
  return key;
}

SessionKey SessionKey::Generate() {
  EnsureSodiumInitialised();
  SessionKey key;
  randombytes_buf(key.bytes_.data(), key.bytes_.size());
  return key;
}

std::string SessionKey::ToHex() const {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string out;
  out.reserve(2 * kBytes);
  for (std::uint8_t b : bytes_) {
    out.push_back(kDigits[b >> 4]);
    out.push_back(kDigits[b & 0xf]);
  }
  return out;
}

std::uint64_t SessionKey::DerivedSessionId() const {
  EnsureSodiumInitialised();
  // A keyed hash of a fixed label: the id reveals nothing about the key.
  static constexpr unsigned char kLabel[] = "haptex session id v1";
  std::array<std::uint8_t, 8> out{};
  crypto_generichash(out.data(), out.size(), kLabel, sizeof(kLabel) - 1, bytes_.data(), bytes_.size());
  std::uint64_t id = 0;
  for (std::uint8_t b : out) id = (id << 8) | b;
  return id == 0 ? 1 : id;
}

}  // namespace haptex::net
