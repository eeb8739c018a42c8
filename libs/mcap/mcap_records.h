#pragma once
// The parts of an MCAP file (https://mcap.dev/spec) that haptex writes and reads: the magic, the
// record opcodes, and schemas, channels and messages as plain values.

#include <cstdint>
#include <map>
#include <string>
#include <string_view>

namespace haptex::mcap {

// 0x89 "MCAP" major version '0' "\r\n", at both ends of the file
inline constexpr std::string_view kMagic{"\x89MCAP0\r\n", 8};

enum class Opcode : std::uint8_t {
  kHeader = 0x01,
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kMessageIndex = 0x07,
  kChunkIndex = 0x08,
  kAttachment = 0x09,
  kAttachmentIndex = 0x0A,
  kStatistics = 0x0B,
  kMetadata = 0x0C,
  kMetadataIndex = 0x0D,
  kSummaryOffset = 0x0E,
  kDataEnd = 0x0F,
};

// opcode (1) + content length (8)
inline constexpr std::size_t kRecordPrefixBytes = 9;
// summary_start (8) + summary_offset_start (8) + summary_crc (4)
inline constexpr std::size_t kFooterContentBytes = 20;

struct Schema {
  std::uint16_t id = 0;  // never 0 (0 means "no schema" on a channel)
  std::string name;      // e.g. "haptex.v1.ClothFrame"
  std::string encoding;  // e.g. "protobuf"
  std::string data;      // e.g. a serialized FileDescriptorSet

  bool operator==(const Schema&) const = default;
};

struct Channel {
  std::uint16_t id = 0;
  std::uint16_t schema_id = 0;
  std::string topic;             // e.g. "/global_sim/cloth_frame"
  std::string message_encoding;  // e.g. "protobuf"
  std::map<std::string, std::string> metadata;

  bool operator==(const Channel&) const = default;
};

struct Message {
  std::uint16_t channel_id = 0;
  std::uint32_t sequence = 0;
  std::uint64_t log_time = 0;      // [ns]
  std::uint64_t publish_time = 0;  // [ns]
  std::string data;

  bool operator==(const Message&) const = default;
};

}  // namespace haptex::mcap
