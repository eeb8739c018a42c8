#include "libs/mcap/mcap_writer.h"

#include <algorithm>
#include <limits>
#include <utility>

#include "libs/mcap/crc32.h"
#include "libs/mcap/mcap_bytes.h"
#include "libs/mcap/mcap_error.h"

namespace haptex::mcap {
namespace {

// <opcode><uint64 content length><content>
void AppendRecord(std::string* out, Opcode op, std::string_view content) {
  ByteWriter w(out);
  w.U8(static_cast<std::uint8_t>(op));
  w.U64(content.size());
  w.Raw(content);
}

std::string SchemaContent(const Schema& s) {
  std::string c;
  ByteWriter w(&c);
  w.U16(s.id);
  w.String(s.name);
  w.String(s.encoding);
  w.String(s.data);
  return c;
}

std::string ChannelContent(const Channel& ch) {
  std::string map;
  ByteWriter m(&map);
  for (const auto& [key, value] : ch.metadata) {
    m.String(key);
    m.String(value);
  }
  std::string c;
  ByteWriter w(&c);
  w.U16(ch.id);
  w.U16(ch.schema_id);
  w.String(ch.topic);
  w.String(ch.message_encoding);
  w.String(map);
  return c;
}

// the byte offset and length of a group of summary records with one opcode
struct Group {
  Opcode op;
  std::uint64_t start = 0, length = 0;
};

}  // namespace

McapWriter::McapWriter(std::ostream& out, WriterOptions options) : sink_(&out), options_(std::move(options)) {
  out_.append(kMagic);
  std::string header;
  ByteWriter w(&header);
  w.String(options_.profile);
  w.String(options_.library);
  AppendRecord(&out_, Opcode::kHeader, header);
  Flush();
}

void McapWriter::Flush() {
  if (!data_ended_) data_crc_.Update(out_);
  sink_->write(out_.data(), static_cast<std::streamsize>(out_.size()));
  flushed_ += out_.size();
  out_.clear();
}

std::uint16_t McapWriter::AddSchema(std::string name, std::string encoding, std::string data) {
  if (schemas_.size() >= std::numeric_limits<std::uint16_t>::max()) throw McapError("more than 65535 schemas");
  const auto id = static_cast<std::uint16_t>(schemas_.size() + 1);
  schemas_.push_back({id, std::move(name), std::move(encoding), std::move(data)});
  schema_written_.push_back(false);
  return id;
}

std::uint16_t McapWriter::AddChannel(std::uint16_t schema_id, std::string topic, std::string message_encoding,
                                     std::map<std::string, std::string> metadata) {
  if (schema_id > schemas_.size()) throw McapError("channel " + topic + ": no schema " + std::to_string(schema_id));
  if (channels_.size() >= std::numeric_limits<std::uint16_t>::max()) throw McapError("more than 65535 channels");
  const auto id = static_cast<std::uint16_t>(channels_.size() + 1);
  channels_.push_back({id, schema_id, std::move(topic), std::move(message_encoding), std::move(metadata)});
  channel_written_.push_back(false);
  return id;
}

void McapWriter::AddMessage(const Message& message) {
  if (finished_) throw McapError("message after Finish()");
  if (message.channel_id == 0 || message.channel_id > channels_.size()) {
    throw McapError("message on unknown channel " + std::to_string(message.channel_id));
  }
  // a channel (and its schema) is written before its first message
  const Channel& channel = channels_[message.channel_id - 1];
  if (!channel_written_[channel.id - 1]) {
    if (channel.schema_id != 0 && !schema_written_[channel.schema_id - 1]) {
      AppendRecord(&chunk_, Opcode::kSchema, SchemaContent(schemas_[channel.schema_id - 1]));
      schema_written_[channel.schema_id - 1] = true;
    }
    AppendRecord(&chunk_, Opcode::kChannel, ChannelContent(channel));
    channel_written_[channel.id - 1] = true;
  }

  chunk_index_[message.channel_id].emplace_back(message.log_time, chunk_.size());
  std::string content;
  ByteWriter w(&content);
  w.U16(message.channel_id);
  w.U32(message.sequence);
  w.U64(message.log_time);
  w.U64(message.publish_time);
  w.Raw(message.data);
  AppendRecord(&chunk_, Opcode::kMessage, content);

  chunk_start_time_ = chunk_has_messages_ ? std::min(chunk_start_time_, message.log_time) : message.log_time;
  chunk_end_time_ = chunk_has_messages_ ? std::max(chunk_end_time_, message.log_time) : message.log_time;
  start_time_ = message_count_ > 0 ? std::min(start_time_, message.log_time) : message.log_time;
  end_time_ = message_count_ > 0 ? std::max(end_time_, message.log_time) : message.log_time;
  chunk_has_messages_ = true;
  ++message_count_;
  ++channel_counts_[message.channel_id];
  if (chunk_.size() >= options_.chunk_size) CloseChunk();
}

void McapWriter::CloseChunk() {
  if (chunk_.empty()) return;
  ChunkIndex index;
  index.start_time = chunk_has_messages_ ? chunk_start_time_ : 0;
  index.end_time = chunk_has_messages_ ? chunk_end_time_ : 0;
  index.chunk_offset = Position();
  index.records_size = chunk_.size();

  std::string content;
  ByteWriter w(&content);
  w.U64(index.start_time);
  w.U64(index.end_time);
  w.U64(chunk_.size());  // uncompressed_size
  w.U32(options_.crcs ? Crc32Of(chunk_) : 0);
  w.String("");  // compression: none
  w.U64(chunk_.size());
  w.Raw(chunk_);
  AppendRecord(&out_, Opcode::kChunk, content);
  index.chunk_length = Position() - index.chunk_offset;

  // one Message Index per channel in the chunk, by channel id
  const std::uint64_t indexes_start = Position();
  for (const auto& [channel_id, entries] : chunk_index_) {
    index.message_index_offsets[channel_id] = Position();
    std::string array;
    ByteWriter a(&array);
    for (const auto& [log_time, offset] : entries) {
      a.U64(log_time);
      a.U64(offset);
    }
    std::string record;
    ByteWriter r(&record);
    r.U16(channel_id);
    r.String(array);
    AppendRecord(&out_, Opcode::kMessageIndex, record);
  }
  index.message_index_length = Position() - indexes_start;
  chunk_indexes_.push_back(std::move(index));

  chunk_.clear();
  chunk_index_.clear();
  chunk_has_messages_ = false;
  Flush();
}

void McapWriter::Finish() {
  if (finished_) throw McapError("Finish() twice");
  finished_ = true;
  CloseChunk();

  // Data End: the CRC of everything before it, from the leading magic on
  {
    Flush();
    std::string content;
    ByteWriter(&content).U32(options_.crcs ? data_crc_.value() : 0);
    AppendRecord(&out_, Opcode::kDataEnd, content);
    data_ended_ = true;
    Flush();
  }

  // Summary, grouped by opcode
  const std::uint64_t summary_start = Position();
  std::vector<Group> groups;
  auto begin_group = [&](Opcode op) { groups.push_back({op, Position(), 0}); };
  auto end_group = [&] { groups.back().length = Position() - groups.back().start; };
  if (!schemas_.empty()) {
    begin_group(Opcode::kSchema);
    for (const Schema& s : schemas_) AppendRecord(&out_, Opcode::kSchema, SchemaContent(s));
    end_group();
  }
  if (!channels_.empty()) {
    begin_group(Opcode::kChannel);
    for (const Channel& c : channels_) AppendRecord(&out_, Opcode::kChannel, ChannelContent(c));
    end_group();
  }
  {
    begin_group(Opcode::kStatistics);
    std::string counts;
    ByteWriter m(&counts);
    for (const auto& [channel_id, count] : channel_counts_) {
      m.U16(channel_id);
      m.U64(count);
    }
    std::string content;
    ByteWriter w(&content);
    w.U64(message_count_);
    w.U16(static_cast<std::uint16_t>(schemas_.size()));
    w.U32(static_cast<std::uint32_t>(channels_.size()));
    w.U32(0);  // attachments
    w.U32(0);  // metadata
    w.U32(static_cast<std::uint32_t>(chunk_indexes_.size()));
    w.U64(message_count_ > 0 ? start_time_ : 0);
    w.U64(message_count_ > 0 ? end_time_ : 0);
    w.String(counts);
    AppendRecord(&out_, Opcode::kStatistics, content);
    end_group();
  }
  if (!chunk_indexes_.empty()) {
    begin_group(Opcode::kChunkIndex);
    for (const ChunkIndex& c : chunk_indexes_) {
      std::string offsets;
      ByteWriter m(&offsets);
      for (const auto& [channel_id, offset] : c.message_index_offsets) {
        m.U16(channel_id);
        m.U64(offset);
      }
      std::string content;
      ByteWriter w(&content);
      w.U64(c.start_time);
      w.U64(c.end_time);
      w.U64(c.chunk_offset);
      w.U64(c.chunk_length);
      w.String(offsets);
      w.U64(c.message_index_length);
      w.String("");           // compression
      w.U64(c.records_size);  // compressed_size
      w.U64(c.records_size);  // uncompressed_size
      AppendRecord(&out_, Opcode::kChunkIndex, content);
    }
    end_group();
  }

  // Summary Offsets: where each group is
  const std::uint64_t summary_offset_start = Position();
  for (const Group& g : groups) {
    std::string content;
    ByteWriter w(&content);
    w.U8(static_cast<std::uint8_t>(g.op));
    w.U64(g.start);
    w.U64(g.length);
    AppendRecord(&out_, Opcode::kSummaryOffset, content);
  }

  // Footer: its CRC covers the summary, the offsets and the footer up to the CRC field
  ByteWriter w(&out_);
  w.U8(static_cast<std::uint8_t>(Opcode::kFooter));
  w.U64(kFooterContentBytes);
  w.U64(summary_start);
  w.U64(summary_offset_start);
  w.U32(options_.crcs ? Crc32Of(out_) : 0);  // out_ holds the file from summary_start on
  w.Raw(kMagic);
  Flush();
  sink_->flush();
  if (!*sink_) throw McapError("the output stream failed");
}

}  // namespace haptex::mcap
