#include "libs/net/datagram_mac.h"

#include <sodium.h>

#include "libs/net/sodium_init.h"

namespace haptex::net {

DatagramMac::DatagramMac(const SessionKey& key) {
  EnsureSodiumInitialised();
  static constexpr unsigned char kLabel[] = "haptex datagram mac v1";
  crypto_generichash(mac_key_.data(), mac_key_.size(), kLabel, sizeof(kLabel) - 1,
                     key.bytes().data(), key.bytes().size());
}

void DatagramMac::Compute(std::span<const std::uint8_t> data, std::uint8_t* tag_out) const {
  crypto_generichash(tag_out, kTagBytes, data.data(), data.size(), mac_key_.data(),
                     mac_key_.size());
}

bool DatagramMac::Verify(std::span<const std::uint8_t> data, const std::uint8_t* tag) const {
  Tag expected;
  Compute(data, expected.data());
  return crypto_verify_16(expected.data(), tag) == 0;
}

}  // namespace haptex::net
