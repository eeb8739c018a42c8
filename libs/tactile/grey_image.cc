#include "libs/tactile/grey_image.h"

#include <array>
#include <cctype>
#include <fstream>
#include <istream>
#include <ostream>
#include <stdexcept>

namespace haptex::tactile {
namespace {

constexpr int kMaxDimension = 1 << 15;

void SkipSpaceAndComments(std::istream& in) {
  while (true) {
    const int c = in.peek();
    if (c == '#') {
      while (in && in.get() != '\n') {
      }
    } else if (c != EOF && std::isspace(c)) {
      in.get();
    } else {
      return;
    }
  }
}

int ReadHeaderInt(std::istream& in, const char* what) {
  SkipSpaceAndComments(in);
  long value = -1;
  if (!(in >> value)) throw std::runtime_error(std::string("PGM: cannot read ") + what);
  return static_cast<int>(value);
}

std::uint32_t Crc32(const std::uint8_t* data, std::size_t n, std::uint32_t crc) {
  static const std::array<std::uint32_t, 256> table = [] {
    std::array<std::uint32_t, 256> t{};
    for (std::uint32_t i = 0; i < 256; ++i) {
      std::uint32_t c = i;
      for (int k = 0; k < 8; ++k) c = (c & 1U) ? 0xEDB88320U ^ (c >> 1) : c >> 1;
      t[i] = c;
    }
    return t;
  }();
  crc = ~crc;
  for (std::size_t i = 0; i < n; ++i) crc = table[(crc ^ data[i]) & 0xFFU] ^ (crc >> 8);
  return ~crc;
}

void PutU32Be(std::vector<std::uint8_t>& out, std::uint32_t v) {
  out.push_back(static_cast<std::uint8_t>(v >> 24));
  out.push_back(static_cast<std::uint8_t>(v >> 16));
  out.push_back(static_cast<std::uint8_t>(v >> 8));
  out.push_back(static_cast<std::uint8_t>(v));
}

void WriteChunk(std::ostream& out, const char type[4], const std::vector<std::uint8_t>& data) {
  std::vector<std::uint8_t> chunk;
  PutU32Be(chunk, static_cast<std::uint32_t>(data.size()));
  for (int i = 0; i < 4; ++i) chunk.push_back(static_cast<std::uint8_t>(type[i]));
  chunk.insert(chunk.end(), data.begin(), data.end());
  // The CRC covers the type and the data, not the length.
  PutU32Be(chunk, Crc32(chunk.data() + 4, chunk.size() - 4, 0));
  out.write(reinterpret_cast<const char*>(chunk.data()), static_cast<std::streamsize>(chunk.size()));
}

void CheckImage(const GreyImage& image) {
  if (image.width <= 0 || image.height <= 0 || image.max_value < 1 || image.max_value > 65535 ||
      image.pixels.size() != static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height)) {
    throw std::invalid_argument("GreyImage: inconsistent size or max_value");
  }
}

}  // namespace

GreyImage ReadPgm(std::istream& in) {
  char magic[2] = {0, 0};
  in.read(magic, 2);
  if (!in || magic[0] != 'P' || (magic[1] != '2' && magic[1] != '5')) {
    throw std::runtime_error("PGM: not a P2 or P5 file");
  }
  GreyImage image;
  image.width = ReadHeaderInt(in, "width");
  image.height = ReadHeaderInt(in, "height");
  image.max_value = ReadHeaderInt(in, "max value");
  if (image.width <= 0 || image.height <= 0 || image.width > kMaxDimension || image.height > kMaxDimension) {
    throw std::runtime_error("PGM: bad image size");
  }
  if (image.max_value < 1 || image.max_value > 65535) throw std::runtime_error("PGM: bad max value");
  const std::size_t count = static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height);
  image.pixels.resize(count);
  if (magic[1] == '2') {
    for (std::size_t i = 0; i < count; ++i) {
      const int v = ReadHeaderInt(in, "pixel");
      if (v < 0 || v > image.max_value) throw std::runtime_error("PGM: pixel value out of range");
      image.pixels[i] = static_cast<std::uint16_t>(v);
    }
    return image;
  }
  // P5: exactly one whitespace byte separates the header from the samples.
  if (!std::isspace(in.get())) throw std::runtime_error("PGM: missing separator after header");
  const bool wide = image.max_value > 255;
  std::vector<unsigned char> raw(count * (wide ? 2 : 1));
  in.read(reinterpret_cast<char*>(raw.data()), static_cast<std::streamsize>(raw.size()));
  if (static_cast<std::size_t>(in.gcount()) != raw.size()) throw std::runtime_error("PGM: truncated pixel data");
  for (std::size_t i = 0; i < count; ++i) {
    const int v = wide ? (raw[2 * i] << 8) | raw[2 * i + 1] : raw[i];
    if (v > image.max_value) throw std::runtime_error("PGM: pixel value out of range");
    image.pixels[i] = static_cast<std::uint16_t>(v);
  }
  return image;
}

GreyImage ReadPgmFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("PGM: cannot open " + path);
  return ReadPgm(in);
}

void WritePgm(const GreyImage& image, std::ostream& out) {
  CheckImage(image);
  out << "P5\n" << image.width << ' ' << image.height << '\n' << image.max_value << '\n';
  const bool wide = image.max_value > 255;
  std::vector<unsigned char> raw;
  raw.reserve(image.pixels.size() * (wide ? 2 : 1));
  for (std::uint16_t v : image.pixels) {
    if (wide) raw.push_back(static_cast<unsigned char>(v >> 8));
    raw.push_back(static_cast<unsigned char>(v & 0xFFU));
  }
  out.write(reinterpret_cast<const char*>(raw.data()), static_cast<std::streamsize>(raw.size()));
}

void WritePgmFile(const GreyImage& image, const std::string& path) {
  std::ofstream out(path, std::ios::binary);
  if (!out) throw std::runtime_error("PGM: cannot create " + path);
  WritePgm(image, out);
  if (!out) throw std::runtime_error("PGM: write failed for " + path);
}

void WritePng(const GreyImage& image, std::ostream& out) {
  CheckImage(image);
  if (image.max_value > 255) throw std::invalid_argument("WritePng: only 8-bit images");
  static constexpr std::uint8_t kSignature[8] = {137, 80, 78, 71, 13, 10, 26, 10};
  out.write(reinterpret_cast<const char*>(kSignature), 8);

  std::vector<std::uint8_t> header;
  PutU32Be(header, static_cast<std::uint32_t>(image.width));
  PutU32Be(header, static_cast<std::uint32_t>(image.height));
  header.insert(header.end(), {8, 0, 0, 0, 0});  // 8 bits, grey, deflate, filter 0, no interlace
  WriteChunk(out, "IHDR", header);

  // Raw scanlines, each led by filter type 0, scaled to 0..255.
  std::vector<std::uint8_t> raw;
  raw.reserve(static_cast<std::size_t>(image.height) * (static_cast<std::size_t>(image.width) + 1));
  for (int y = 0; y < image.height; ++y) {
    raw.push_back(0);
    for (int x = 0; x < image.width; ++x) {
      const unsigned v = image.pixels[static_cast<std::size_t>(y) * static_cast<std::size_t>(image.width) +
                                      static_cast<std::size_t>(x)];
      raw.push_back(static_cast<std::uint8_t>(v * 255U / static_cast<unsigned>(image.max_value)));
    }
  }
  // zlib stream made of stored (uncompressed) deflate blocks, then Adler-32.
  std::vector<std::uint8_t> z = {0x78, 0x01};
  std::size_t pos = 0;
  do {
    const std::size_t len = std::min<std::size_t>(65535, raw.size() - pos);
    const bool last = pos + len == raw.size();
    z.push_back(last ? 1 : 0);
    z.push_back(static_cast<std::uint8_t>(len & 0xFFU));
    z.push_back(static_cast<std::uint8_t>(len >> 8));
    z.push_back(static_cast<std::uint8_t>(~len & 0xFFU));
    z.push_back(static_cast<std::uint8_t>((~len >> 8) & 0xFFU));
    z.insert(z.end(), raw.begin() + static_cast<std::ptrdiff_t>(pos),
             raw.begin() + static_cast<std::ptrdiff_t>(pos + len));
    pos += len;
  } while (pos < raw.size());
  std::uint32_t a = 1, b = 0;
  for (std::uint8_t v : raw) {
    a = (a + v) % 65521U;
    b = (b + a) % 65521U;
  }
  PutU32Be(z, (b << 16) | a);
  WriteChunk(out, "IDAT", z);
  WriteChunk(out, "IEND", {});
}

void WritePngFile(const GreyImage& image, const std::string& path) {
  std::ofstream out(path, std::ios::binary);
  if (!out) throw std::runtime_error("PNG: cannot create " + path);
  WritePng(image, out);
  if (!out) throw std::runtime_error("PNG: write failed for " + path);
}

HeightMap HeightMapFromGreyImage(const GreyImage& image, double pixel_size_m, double relief_um) {
  CheckImage(image);
  Eigen::ArrayXXd h(image.width, image.height);
  const double scale = relief_um / image.max_value;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      h(x, y) = scale * image.pixels[static_cast<std::size_t>(y) * static_cast<std::size_t>(image.width) +
                                     static_cast<std::size_t>(x)];
    }
  }
  return HeightMap(std::move(h), pixel_size_m);
}

GreyImage GreyImageFromArray(const Eigen::ArrayXXd& values) {
  GreyImage image;
  image.width = static_cast<int>(values.rows());
  image.height = static_cast<int>(values.cols());
  image.max_value = 255;
  image.pixels.resize(static_cast<std::size_t>(values.size()));
  const double lo = values.minCoeff();
  const double span = values.maxCoeff() - lo;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const double t = span > 0.0 ? (values(x, y) - lo) / span : 0.0;
      image.pixels[static_cast<std::size_t>(y) * static_cast<std::size_t>(image.width) + static_cast<std::size_t>(x)] =
          static_cast<std::uint16_t>(std::lround(255.0 * t));
    }
  }
  return image;
}

}  // namespace haptex::tactile
