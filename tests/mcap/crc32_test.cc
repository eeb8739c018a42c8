#include "libs/mcap/crc32.h"

#include <gtest/gtest.h>

#include <string>

namespace haptex::mcap {
namespace {

// The CRC-32 check values everyone publishes for this polynomial (zlib's crc32, IEEE 802.3).
TEST(McapCrc32Test, KnownVectors) {
  EXPECT_EQ(Crc32Of(""), 0x00000000u);
  EXPECT_EQ(Crc32Of("a"), 0xE8B7BE43u);
  EXPECT_EQ(Crc32Of("123456789"), 0xCBF43926u);
  EXPECT_EQ(Crc32Of("The quick brown fox jumps over the lazy dog"), 0x414FA339u);
  EXPECT_EQ(Crc32Of(std::string(32, '\0')), 0x190A55ADu);
  EXPECT_EQ(Crc32Of(std::string(32, '\xFF')), 0xFF6CAB0Bu);
}

TEST(McapCrc32Test, PiecesGiveTheSameCrcAsTheWhole) {
  const std::string text = "The quick brown fox jumps over the lazy dog";
  for (std::size_t cut = 0; cut <= text.size(); ++cut) {
    Crc32 crc;
    crc.Update(std::string_view(text).substr(0, cut)).Update(std::string_view(text).substr(cut));
    EXPECT_EQ(crc.value(), 0x414FA339u) << "cut at " << cut;
  }
}

}  // namespace
}  // namespace haptex::mcap
