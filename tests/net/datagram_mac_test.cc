#include "libs/net/datagram_mac.h"

#include <gtest/gtest.h>

#include <vector>

namespace haptex::net {
namespace {

TEST(DatagramMacTest, VerifiesOwnTagAndRejectsAnyChange) {
  const DatagramMac mac(SessionKey::Generate());
  std::vector<std::uint8_t> data(1024);
  for (std::size_t i = 0; i < data.size(); ++i) data[i] = static_cast<std::uint8_t>(i * 7);
  DatagramMac::Tag tag;
  mac.Compute(data, tag.data());
  EXPECT_TRUE(mac.Verify(data, tag.data()));

  for (std::size_t i : {std::size_t{0}, std::size_t{500}, data.size() - 1}) {
    auto altered = data;
    altered[i] ^= 0x01;
    EXPECT_FALSE(mac.Verify(altered, tag.data())) << "byte " << i;
  }
  auto bad_tag = tag;
  bad_tag[15] ^= 0x80;
  EXPECT_FALSE(mac.Verify(data, bad_tag.data()));
}

TEST(DatagramMacTest, OtherKeyFails) {
  const DatagramMac mac(SessionKey::Generate());
  const DatagramMac other(SessionKey::Generate());
  const std::vector<std::uint8_t> data(64, 0x5a);
  DatagramMac::Tag tag;
  mac.Compute(data, tag.data());
  EXPECT_FALSE(other.Verify(data, tag.data()));
}

}  // namespace
}  // namespace haptex::net
