#include "libs/net/datagram_mac.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

namespace haptex::net {
namespace {

TEST(DatagramMacTest, VerifiesOwnTagAndRejectsAnyChange) {
  const DatagramMac mac(SessionKey::Generate());
  std::vector<std::uint8_t> data(1024);
  for (std::size_t i = 0; i < data.size(); ++i) data[i] = static_cast<std::uint8_t>(i * 7);
  DatagramMac::Nonce nonce;
  DatagramMac::NewNonce(nonce.data());
  DatagramMac::Tag tag;
  mac.Compute(data, nonce.data(), tag.data());
  EXPECT_TRUE(mac.Verify(data, nonce.data(), tag.data()));

  for (std::size_t i : {std::size_t{0}, std::size_t{500}, data.size() - 1}) {
    auto altered = data;
    altered[i] ^= 0x01;
    EXPECT_FALSE(mac.Verify(altered, nonce.data(), tag.data())) << "byte " << i;
  }
  auto bad_tag = tag;
  bad_tag[15] ^= 0x80;
  EXPECT_FALSE(mac.Verify(data, nonce.data(), bad_tag.data()));
  auto other_nonce = nonce;
  other_nonce[0] ^= 1;
  EXPECT_FALSE(mac.Verify(data, other_nonce.data(), tag.data()));
}

TEST(DatagramMacTest, OtherKeyFails) {
  const DatagramMac mac(SessionKey::Generate());
  const DatagramMac other(SessionKey::Generate());
  const std::vector<std::uint8_t> data(64, 0x5a);
  DatagramMac::Nonce nonce;
  DatagramMac::NewNonce(nonce.data());
  DatagramMac::Tag tag;
  mac.Compute(data, nonce.data(), tag.data());
  EXPECT_FALSE(other.Verify(data, nonce.data(), tag.data()));
}

TEST(NonceSequenceTest, NoncesNeverRepeatWithinOrAcrossSequences) {
  NonceSequence first, second;
  DatagramMac::Nonce a, b, c;
  first.Next(a.data());
  first.Next(b.data());
  second.Next(c.data());
  EXPECT_NE(a, b);  // counter
  EXPECT_NE(a, c);  // random prefix
  EXPECT_TRUE(std::equal(a.begin(), a.begin() + 16, b.begin()));
}

TEST(DatagramMacTest, NoncesAreFresh) {
  DatagramMac::Nonce a, b;
  DatagramMac::NewNonce(a.data());
  DatagramMac::NewNonce(b.data());
  EXPECT_NE(a, b);
}

}  // namespace
}  // namespace haptex::net
