#pragma once
// The field encodings of MCAP records: little-endian integers, and uint32-length-prefixed strings,
// maps and arrays. The reader checks every length against what is left and throws McapError with
// the file offset instead of reading past the end.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace haptex::mcap {

/// Appends fields to a byte string.
class ByteWriter {
 public:
  explicit ByteWriter(std::string* out) : out_(out) {}

  void U8(std::uint8_t v) { out_->push_back(static_cast<char>(v)); }
  void U16(std::uint16_t v) { Little(v, 2); }
  void U32(std::uint32_t v) { Little(v, 4); }
  void U64(std::uint64_t v) { Little(v, 8); }
  void Raw(std::string_view bytes) { out_->append(bytes); }
  /// uint32 length, then the bytes (String, and Bytes with a uint32 prefix). Throws McapError when
  /// longer than a uint32 can say.
  void String(std::string_view text);

 private:
  void Little(std::uint64_t v, int bytes) {
    for (int i = 0; i < bytes; ++i) out_->push_back(static_cast<char>((v >> (8 * i)) & 0xFFu));
  }
  std::string* out_;
};

/// Reads fields from a span of the file; `base` is the span's offset in the file (for errors).
class ByteReader {
 public:
  ByteReader(std::string_view bytes, std::uint64_t base, std::string_view what)
      : bytes_(bytes), base_(base), what_(what) {}

  std::uint8_t U8() { return static_cast<std::uint8_t>(Little(1)); }
  std::uint16_t U16() { return static_cast<std::uint16_t>(Little(2)); }
  std::uint32_t U32() { return static_cast<std::uint32_t>(Little(4)); }
  std::uint64_t U64() { return Little(8); }
  /// `n` bytes; throws when fewer are left.
  std::string_view Take(std::uint64_t n, std::string_view field);
  /// A uint32 length, then that many bytes.
  std::string_view String(std::string_view field) { return Take(U32(), field); }
  /// A uint64 length, then that many bytes.
  std::string_view Bytes64(std::string_view field) { return Take(U64(), field); }
  /// Everything left.
  std::string_view Rest() { return Take(remaining(), "rest"); }

  std::size_t remaining() const { return bytes_.size() - at_; }
  std::uint64_t offset() const { return base_ + at_; }  // in the file

 private:
  std::uint64_t Little(int bytes);
  std::string_view bytes_;
  std::uint64_t base_;
  std::string_view what_;  // the record being read, for errors
  std::size_t at_ = 0;
};

}  // namespace haptex::mcap
