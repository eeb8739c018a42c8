#pragma once
// Writes an MCAP file to a stream: magic, Header, then messages grouped into uncompressed Chunks
// (each followed by its Message Index records), Data End with the data section's CRC, a Summary
// (Schemas, Channels, Statistics with per-channel counts, Chunk Indexes), Summary Offsets, Footer
// and magic (https://mcap.dev/spec). A schema and channel are written into the chunk of their
// channel's first message, and again in the summary, so both streaming and indexed readers find them.

#include <cstddef>
#include <cstdint>
#include <map>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "libs/mcap/crc32.h"
#include "libs/mcap/mcap_records.h"

namespace haptex::mcap {

struct WriterOptions {
  std::string profile;             // "" : no well-known profile
  std::string library = "haptex";  // the Header's writer name
  // A chunk is closed once its records reach this size [bytes]; a message is never split.
  std::size_t chunk_size = 1 << 20;
  // false writes 0 for every CRC ("not available", as the spec allows); for tests of readers
  bool crcs = true;
};

class McapWriter {
 public:
  /// Writes to `out` as it goes: a chunk at a time, the summary at Finish(). Keeps only the open
  /// chunk and the index entries in memory.
  explicit McapWriter(std::ostream& out, WriterOptions options = {});

  /// Returns the new schema's id (from 1). Throws McapError past 65535 schemas.
  std::uint16_t AddSchema(std::string name, std::string encoding, std::string data);
  /// `schema_id` 0: no schema. Returns the new channel's id (from 1). Throws McapError for an
  /// unknown schema id or past 65535 channels.
  std::uint16_t AddChannel(std::uint16_t schema_id, std::string topic, std::string message_encoding,
                           std::map<std::string, std::string> metadata = {});
  /// Throws McapError for an unknown channel, or after Finish().
  void AddMessage(const Message& message);

  /// Closes the data section and writes the summary and footer. The writer takes nothing more after
  /// this. Throws McapError when the stream has failed.
  void Finish();

 private:
  struct ChunkIndex {
    std::uint64_t start_time = 0, end_time = 0;
    std::uint64_t chunk_offset = 0, chunk_length = 0;
    std::map<std::uint16_t, std::uint64_t> message_index_offsets;
    std::uint64_t message_index_length = 0;
    std::uint64_t records_size = 0;
  };

  void CloseChunk();
  void Flush();                                                      // out_ to the stream
  std::uint64_t Position() const { return flushed_ + out_.size(); }  // in the file

  std::ostream* sink_;
  WriterOptions options_;
  std::string out_;            // written but not yet flushed
  std::uint64_t flushed_ = 0;  // bytes given to the stream
  Crc32 data_crc_;             // of the data section so far
  bool data_ended_ = false;
  std::vector<Schema> schemas_;
  std::vector<Channel> channels_;
  std::vector<bool> schema_written_, channel_written_;  // into the data section, by id - 1
  std::map<std::uint16_t, std::uint64_t> channel_counts_;
  std::uint64_t message_count_ = 0;
  std::uint64_t start_time_ = 0, end_time_ = 0;  // over all messages

  // the open chunk: its records, times, and per channel (log_time, offset in the records)
  std::string chunk_;
  std::uint64_t chunk_start_time_ = 0, chunk_end_time_ = 0;
  bool chunk_has_messages_ = false;
  std::map<std::uint16_t, std::vector<std::pair<std::uint64_t, std::uint64_t>>> chunk_index_;
  std::vector<ChunkIndex> chunk_indexes_;
  bool finished_ = false;
};

}  // namespace haptex::mcap
