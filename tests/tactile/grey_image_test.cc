#include "libs/tactile/grey_image.h"

#include <sstream>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

namespace haptex::tactile {
namespace {

std::uint32_t ReadU32Be(const std::string& s, std::size_t at) {
  return (static_cast<std::uint32_t>(static_cast<unsigned char>(s[at])) << 24) |
         (static_cast<std::uint32_t>(static_cast<unsigned char>(s[at + 1])) << 16) |
         (static_cast<std::uint32_t>(static_cast<unsigned char>(s[at + 2])) << 8) |
         static_cast<std::uint32_t>(static_cast<unsigned char>(s[at + 3]));
}

TEST(GreyImageTest, ReadsPlainPgmWithComments) {
  std::istringstream in("P2\n# a comment\n3 2\n# another\n10\n0 5 10\n1 2 3\n");
  const GreyImage image = ReadPgm(in);
  EXPECT_EQ(image.width, 3);
  EXPECT_EQ(image.height, 2);
  EXPECT_EQ(image.max_value, 10);
  EXPECT_EQ(image.pixels, (std::vector<std::uint16_t>{0, 5, 10, 1, 2, 3}));
}

TEST(GreyImageTest, BinaryRoundTrip8And16Bit) {
  for (const int max_value : {255, 1000}) {
    GreyImage image;
    image.width = 3;
    image.height = 2;
    image.max_value = max_value;
    image.pixels = {0, 1, 2, 100, 200, static_cast<std::uint16_t>(max_value)};
    std::stringstream buffer;
    WritePgm(image, buffer);
    const GreyImage back = ReadPgm(buffer);
    EXPECT_EQ(back.pixels, image.pixels);
    EXPECT_EQ(back.max_value, max_value);
  }
}

TEST(GreyImageTest, MalformedPgmThrows) {
  for (const std::string bad : {"P6\n1 1\n255\nx", "P5\n2 2\n255\nab", "P2\n2 1\n10\n3 11\n", "P5\n-1 2\n255\n"}) {
    std::istringstream in(bad);
    EXPECT_THROW(ReadPgm(in), std::runtime_error) << bad;
  }
}

TEST(GreyImageTest, HeightMapFromImageScalesGreyToRelief) {
  GreyImage image;
  image.width = 2;
  image.height = 2;
  image.max_value = 100;
  image.pixels = {0, 100, 50, 25};
  const HeightMap map = HeightMapFromGreyImage(image, 1e-5, 40.0);
  EXPECT_DOUBLE_EQ(map.height_um()(1, 0), 40.0);
  EXPECT_DOUBLE_EQ(map.height_um()(0, 1), 20.0);
  EXPECT_DOUBLE_EQ(map.height_um()(1, 1), 10.0);
}

TEST(GreyImageTest, ArrayToImageStretchesToFullRange) {
  Eigen::ArrayXXd a(2, 1);
  a << -3.0, 5.0;
  const GreyImage image = GreyImageFromArray(a);
  EXPECT_EQ(image.pixels, (std::vector<std::uint16_t>{0, 255}));
}

TEST(GreyImageTest, PngHasValidChunksAndStoredData) {
  GreyImage image;
  image.width = 4;
  image.height = 3;
  image.pixels = {0, 10, 20, 30, 40, 50, 60, 70, 80, 90, 100, 255};
  std::stringstream buffer;
  WritePng(image, buffer);
  const std::string png = buffer.str();
  ASSERT_GT(png.size(), 8u + 25u + 12u);
  EXPECT_EQ(png.substr(1, 3), "PNG");
  EXPECT_EQ(png.substr(12, 4), "IHDR");
  EXPECT_EQ(ReadU32Be(png, 16), 4u);
  EXPECT_EQ(ReadU32Be(png, 20), 3u);
  // IEND is always the same 12 bytes, CRC included.
  EXPECT_EQ(png.substr(png.size() - 8, 4), "IEND");
  EXPECT_EQ(ReadU32Be(png, png.size() - 4), 0xAE426082u);
  // IDAT: zlib header, one final stored block holding 3 rows of (filter byte + 4 pixels).
  const std::size_t idat = 8 + 25;
  EXPECT_EQ(png.substr(idat + 4, 4), "IDAT");
  EXPECT_EQ(static_cast<unsigned char>(png[idat + 8]), 0x78);
  EXPECT_EQ(static_cast<unsigned char>(png[idat + 10]), 1);         // BFINAL, stored
  EXPECT_EQ(static_cast<unsigned char>(png[idat + 11]), 15);        // LEN = 3 * 5
  EXPECT_EQ(static_cast<unsigned char>(png[idat + 15 + 14]), 255);  // last pixel of the last row
}

}  // namespace
}  // namespace haptex::tactile
