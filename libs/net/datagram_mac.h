#pragma once
// Authentication of a datagram: XChaCha20-Poly1305 (IETF, libsodium) over an empty message with
// the datagram as associated data, a fresh random 24-byte nonce per datagram and a 16-byte tag.
// A standard AEAD construction; Poly1305 makes it several times cheaper per byte than a keyed
// hash. Nonces are a 128-bit random prefix per sender (drawn once) and a 64-bit counter: unique
// without a syscall per datagram, and restarts need no care. Replay is handled by the sequence
// window, not here. Contents are authenticated, not encrypted.

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "libs/net/session_key.h"

namespace haptex::net {

class DatagramMac final {
 public:
  static constexpr std::size_t kNonceBytes = 24;
  static constexpr std::size_t kTagBytes = 16;
  using Tag = std::array<std::uint8_t, kTagBytes>;
  using Nonce = std::array<std::uint8_t, kNonceBytes>;

  /// Derives the MAC key from the session key (never uses the session key directly).
  explicit DatagramMac(const SessionKey& key);

  /// A fresh random nonce (the operating system's CSPRNG: one syscall; see NonceSequence).
  static void NewNonce(std::uint8_t* nonce_out);
  /// The tag over `authenticated` (which may contain the nonce itself).
  void Compute(std::span<const std::uint8_t> authenticated, const std::uint8_t* nonce, std::uint8_t* tag_out) const;
  /// Constant-time verification.
  bool Verify(std::span<const std::uint8_t> authenticated, const std::uint8_t* nonce, const std::uint8_t* tag) const;

 private:
  std::array<std::uint8_t, 32> mac_key_{};
};

/// Unique nonces for one sender: a random prefix drawn at construction and a counter.
class NonceSequence final {
 public:
  NonceSequence();
  void Next(std::uint8_t* nonce_out);

 private:
  std::array<std::uint8_t, DatagramMac::kNonceBytes - 8> prefix_{};
  std::uint64_t counter_ = 0;
};

}  // namespace haptex::net
