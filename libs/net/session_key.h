#pragma once
// The 32-byte key every haptex datagram is authenticated with.

#include <array>
#include <cstdint>
#include <string>
#include <string_view>

namespace haptex::net {

class SessionKey final {
 public:
  static constexpr std::size_t kBytes = 32;

  /// Parses 64 hex digits (surrounding whitespace allowed). Throws std::invalid_argument with a
  /// clear message otherwise.
  static SessionKey FromHex(std::string_view hex);
  /// A fresh random key from the operating system's CSPRNG.
  static SessionKey Generate();

  std::string ToHex() const;
  const std::array<std::uint8_t, kBytes>& bytes() const { return bytes_; }

  /// A session id derived from the key, for tools that have no launcher to assign one.
  std::uint64_t DerivedSessionId() const;

 private:
  SessionKey() = default;
  std::array<std::uint8_t, kBytes> bytes_{};
};

}  // namespace haptex::net
