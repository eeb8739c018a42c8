#pragma once
// Message authentication code over a datagram: keyed BLAKE2b (libsodium crypto_generichash),
// 16-byte tag. A MAC needs no nonce, so restarts and retransmissions are safe; replay is handled
// by the sequence window, not here.

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "libs/net/session_key.h"

namespace haptex::net {

class DatagramMac final {
 public:
  static constexpr std::size_t kTagBytes = 16;
  using Tag = std::array<std::uint8_t, kTagBytes>;

  /// Derives the MAC key from the session key (never uses the session key directly).
  explicit DatagramMac(const SessionKey& key);

  void Compute(std::span<const std::uint8_t> data, std::uint8_t* tag_out) const;
  /// Constant-time comparison.
  bool Verify(std::span<const std::uint8_t> data, const std::uint8_t* tag) const;

 private:
  std::array<std::uint8_t, 32> mac_key_{};
};

}  // namespace haptex::net
