#pragma once
// Grey images in and out of the tactile pre-processing: PGM (P2/P5) reading, PGM and minimal
// PNG writing, and conversion between images and height fields.

#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "libs/tactile/height_map.h"

namespace haptex::tactile {

/// A grey image, row-major from the top-left pixel; values in 0..max_value.
struct GreyImage {
  int width = 0;
  int height = 0;
  int max_value = 255;  ///< 1..65535
  std::vector<std::uint16_t> pixels;
};

/// Reads a binary (P5) or plain (P2) PGM, 8 or 16 bits, with comments.
/// @throws std::runtime_error with the reason on malformed or truncated data.
GreyImage ReadPgm(std::istream& in);
GreyImage ReadPgmFile(const std::string& path);

/// Writes a binary PGM (P5); 16-bit samples (big-endian) when max_value > 255.
void WritePgm(const GreyImage& image, std::ostream& out);
void WritePgmFile(const GreyImage& image, const std::string& path);

/// Writes an 8-bit grey PNG (zlib stored blocks, no compression).
/// @throws std::invalid_argument if max_value > 255.
void WritePng(const GreyImage& image, std::ostream& out);
void WritePngFile(const GreyImage& image, const std::string& path);

/// Height map from an image: black = 0, white = relief_um; x to the right, y downwards.
HeightMap HeightMapFromGreyImage(const GreyImage& image, double pixel_size_m, double relief_um);

/// 8-bit image of `values` (index (x, y), x to the right), min -> 0 and max -> 255.
GreyImage GreyImageFromArray(const Eigen::ArrayXXd& values);

}  // namespace haptex::tactile
