#include "libs/net/datagram_mac.h"

#include <sodium.h>

#include <algorithm>

#include "libs/net/sodium_init.h"

namespace haptex::net {

static_assert(DatagramMac::kNonceBytes == crypto_aead_xchacha20poly1305_ietf_NPUBBYTES);
static_assert(DatagramMac::kTagBytes == crypto_aead_xchacha20poly1305_ietf_ABYTES);

DatagramMac::DatagramMac(const SessionKey& key) {
  EnsureSodiumInitialised();
  static constexpr unsigned char kLabel[] = "haptex datagram mac v2";
  crypto_generichash(mac_key_.data(), mac_key_.size(), kLabel, sizeof(kLabel) - 1, key.bytes().data(),
                     key.bytes().size());
}

void DatagramMac::NewNonce(std::uint8_t* nonce_out) {
  EnsureSodiumInitialised();
  randombytes_buf(nonce_out, kNonceBytes);
}

void DatagramMac::Compute(std::span<const std::uint8_t> authenticated, const std::uint8_t* nonce,
                          std::uint8_t* tag_out) const {
  // the message is empty; libsodium still wants valid pointers for it
  unsigned char empty = 0;
  unsigned long long tag_bytes = 0;
  crypto_aead_xchacha20poly1305_ietf_encrypt_detached(&empty, tag_out, &tag_bytes, &empty, 0, authenticated.data(),
                                                      authenticated.size(), /*nsec=*/nullptr, nonce, mac_key_.data());
}

bool DatagramMac::Verify(std::span<const std::uint8_t> authenticated, const std::uint8_t* nonce,
                         const std::uint8_t* tag) const {
  unsigned char empty = 0;
  return crypto_aead_xchacha20poly1305_ietf_decrypt_detached(&empty, /*nsec=*/nullptr, &empty, 0, tag,
                                                             authenticated.data(), authenticated.size(), nonce,
                                                             mac_key_.data()) == 0;
}

NonceSequence::NonceSequence() {
  EnsureSodiumInitialised();
  randombytes_buf(prefix_.data(), prefix_.size());
}

void NonceSequence::Next(std::uint8_t* nonce_out) {
  std::copy(prefix_.begin(), prefix_.end(), nonce_out);
  ++counter_;
  for (std::size_t i = 0; i < 8; ++i) {
    nonce_out[prefix_.size() + i] = static_cast<std::uint8_t>(counter_ >> (8 * i));
  }
}

}  // namespace haptex::net
