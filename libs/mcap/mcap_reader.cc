#include "libs/mcap/mcap_reader.h"

#include <algorithm>
#include <fstream>
#include <iterator>
#include <set>

#include "libs/mcap/crc32.h"
#include "libs/mcap/mcap_bytes.h"

namespace haptex::mcap {
namespace {

// magic, an empty Header record, a Footer record, magic
constexpr std::size_t kMinimumFileBytes =
    2 * kMagic.size() + kRecordPrefixBytes + 8 + kRecordPrefixBytes + kFooterContentBytes;

std::string Hex(std::uint8_t v) {
  constexpr char kDigits[] = "0123456789abcdef";
  return std::string("0x") + kDigits[v >> 4] + kDigits[v & 0xF];
}

struct Record {
  Opcode op;
  std::uint64_t offset;      // of the opcode, in the file
  std::string_view content;  // after the length
};

// Walks <opcode><uint64 length><content> records over [begin, end) of the file.
class RecordWalker {
 public:
  RecordWalker(std::string_view file, std::uint64_t begin, std::uint64_t end, std::string_view where)
      : file_(file), at_(begin), end_(end), where_(where) {}

  bool Done() const { return at_ >= end_; }
  std::uint64_t at() const { return at_; }

  Record Next() {
    if (end_ - at_ < kRecordPrefixBytes) {
      throw McapError(std::string(where_) + ": a record starts but its opcode and length are cut short", at_);
    }
    ByteReader prefix(file_.substr(at_, kRecordPrefixBytes), at_, where_);
    const std::uint8_t op = prefix.U8();
    const std::uint64_t length = prefix.U64();
    if (op == 0) throw McapError(std::string(where_) + ": opcode 0x00 is not a record", at_);
    if (length > end_ - at_ - kRecordPrefixBytes) {
      throw McapError(std::string(where_) + ": record " + Hex(op) + " says it is " + std::to_string(length) +
                          " bytes long, only " + std::to_string(end_ - at_ - kRecordPrefixBytes) + " are left",
                      at_);
    }
    Record r{static_cast<Opcode>(op), at_, file_.substr(at_ + kRecordPrefixBytes, length)};
    at_ += kRecordPrefixBytes + length;
    return r;
  }

 private:
  std::string_view file_;
  std::uint64_t at_, end_;
  std::string_view where_;
};

std::uint64_t ContentOffset(const Record& r) { return r.offset + kRecordPrefixBytes; }

Schema ParseSchema(const Record& r) {
  ByteReader in(r.content, ContentOffset(r), "Schema");
  Schema s;
  s.id = in.U16();
  s.name = in.String("name");
  s.encoding = in.String("encoding");
  s.data = in.String("data");
  return s;
}

Channel ParseChannel(const Record& r) {
  ByteReader in(r.content, ContentOffset(r), "Channel");
  Channel c;
  c.id = in.U16();
  c.schema_id = in.U16();
  c.topic = in.String("topic");
  c.message_encoding = in.String("message_encoding");
  const std::uint64_t map_offset = in.offset() + 4;
  ByteReader map(in.String("metadata"), map_offset, "Channel metadata");
  while (map.remaining() > 0) {
    std::string key(map.String("key"));
    c.metadata[std::move(key)] = std::string(map.String("value"));
  }
  return c;
}

Message ParseMessage(const Record& r) {
  ByteReader in(r.content, ContentOffset(r), "Message");
  Message m;
  m.channel_id = in.U16();
  m.sequence = in.U32();
  m.log_time = in.U64();
  m.publish_time = in.U64();
  m.data = in.Rest();
  return m;
}

Statistics ParseStatistics(const Record& r) {
  ByteReader in(r.content, ContentOffset(r), "Statistics");
  Statistics s;
  s.message_count = in.U64();
  s.schema_count = in.U16();
  s.channel_count = in.U32();
  in.U32();  // attachments
  in.U32();  // metadata
  s.chunk_count = in.U32();
  s.message_start_time = in.U64();
  s.message_end_time = in.U64();
  const std::uint64_t map_offset = in.offset() + 4;
  ByteReader map(in.String("channel_message_counts"), map_offset, "Statistics channel_message_counts");
  while (map.remaining() > 0) {
    const std::uint16_t id = map.U16();
    s.channel_message_counts[id] = map.U64();
  }
  return s;
}

class Reader {
 public:
  explicit Reader(std::string_view file) : file_(file) {}

  McapFile Read() {
    CheckMagicAndFooter();
    RecordWalker data(file_, kMagic.size(), footer_offset_, "data section");
    const Record header = data.Next();
    if (header.op != Opcode::kHeader) {
      throw McapError("the first record is " + Hex(static_cast<std::uint8_t>(header.op)) + ", not a Header",
                      header.offset);
    }
    ByteReader h(header.content, ContentOffset(header), "Header");
    out_.profile = h.String("profile");
    out_.library = h.String("library");

    bool data_end = false;
    while (!data.Done()) {
      const Record r = data.Next();
      if (r.op == Opcode::kDataEnd) {
        CheckDataEnd(r);
        data_end = true;
        break;
      }
      DataRecord(r, "the data section");
    }
    if (!data_end) throw McapError("no Data End record before the Footer (file cut short?)", data.at());
    ReadSummary(data.at());
    CheckSummaryAgrees();

    std::stable_sort(out_.messages.begin(), out_.messages.end(),
                     [](const Message& a, const Message& b) { return a.log_time < b.log_time; });
    return std::move(out_);
  }

 private:
  void CheckMagicAndFooter() {
    if (file_.size() < kMagic.size() || file_.substr(0, kMagic.size()) != kMagic) {
      throw McapError("not an MCAP file: it does not start with the MCAP magic", 0);
    }
    if (file_.size() < kMinimumFileBytes) {
      throw McapError("cut short: " + std::to_string(file_.size()) + " bytes, an MCAP file has at least " +
                          std::to_string(kMinimumFileBytes),
                      file_.size());
    }
    const std::uint64_t tail = file_.size() - kMagic.size();
    if (file_.substr(tail) != kMagic) {
      throw McapError("cut short or damaged: the file does not end with the MCAP magic", tail);
    }
    footer_offset_ = tail - kRecordPrefixBytes - kFooterContentBytes;
    ByteReader footer(file_.substr(footer_offset_, kRecordPrefixBytes + kFooterContentBytes), footer_offset_, "Footer");
    const std::uint8_t op = footer.U8();
    const std::uint64_t length = footer.U64();
    if (op != static_cast<std::uint8_t>(Opcode::kFooter) || length != kFooterContentBytes) {
      throw McapError("no Footer record before the closing magic", footer_offset_);
    }
    summary_start_ = footer.U64();
    summary_offset_start_ = footer.U64();
    summary_crc_ = footer.U32();
  }

  void DataRecord(const Record& r, std::string_view where) {
    switch (r.op) {
      case Opcode::kSchema:
        AddSchema(ParseSchema(r), r.offset);
        break;
      case Opcode::kChannel:
        AddChannel(ParseChannel(r), r.offset);
        break;
      case Opcode::kMessage: {
        Message m = ParseMessage(r);
        if (channel_at_.count(m.channel_id) == 0) {
          throw McapError("a message on channel " + std::to_string(m.channel_id) + ", which no earlier Channel defines",
                          r.offset);
        }
        out_.messages.push_back(std::move(m));
        break;
      }
      case Opcode::kChunk:
        if (where != "the data section") throw McapError("a Chunk inside a Chunk", r.offset);
        ReadChunk(r);
        break;
      case Opcode::kHeader:
      case Opcode::kFooter:
      case Opcode::kDataEnd:
      case Opcode::kStatistics:
      case Opcode::kChunkIndex:
      case Opcode::kSummaryOffset:
        throw McapError("record " + Hex(static_cast<std::uint8_t>(r.op)) + " does not belong in " + std::string(where),
                        r.offset);
      default:
        break;  // message indexes, attachments, metadata, and records of later versions: not needed here
    }
  }

  void ReadChunk(const Record& r) {
    ByteReader in(r.content, ContentOffset(r), "Chunk");
    in.U64();  // message_start_time
    in.U64();  // message_end_time
    const std::uint64_t uncompressed_size = in.U64();
    const std::uint32_t crc = in.U32();
    const std::string compression(in.String("compression"));
    const std::uint64_t records_offset = in.offset() + 8;
    const std::string_view records = in.Bytes64("records");
    if (!compression.empty()) {
      throw McapError("a Chunk compressed with \"" + compression + "\" (only uncompressed chunks are read)", r.offset);
    }
    if (records.size() != uncompressed_size) {
      throw McapError("a Chunk says " + std::to_string(uncompressed_size) + " uncompressed bytes but holds " +
                          std::to_string(records.size()),
                      r.offset);
    }
    if (crc != 0 && Crc32Of(records) != crc) throw McapError("a Chunk's records fail their CRC", r.offset);
    chunk_offsets_.insert(r.offset);
    ++out_.chunks;
    // records' offsets inside the file, so errors point at the byte
    RecordWalker walker(file_, records_offset, records_offset + records.size(), "chunk");
    while (!walker.Done()) DataRecord(walker.Next(), "a Chunk");
  }

  void CheckDataEnd(const Record& r) {
    ByteReader in(r.content, ContentOffset(r), "Data End");
    const std::uint32_t crc = in.U32();
    if (crc != 0 && Crc32Of(file_.substr(0, r.offset)) != crc) {
      throw McapError("the data section fails its CRC (Data End)", r.offset);
    }
  }

  void ReadSummary(std::uint64_t after_data_end) {
    if (summary_start_ != 0 && summary_start_ != after_data_end) {
      throw McapError("the Footer puts the summary at byte " + std::to_string(summary_start_) +
                          ", the data section ends at byte " + std::to_string(after_data_end),
                      footer_offset_);
    }
    if (summary_offset_start_ != 0 &&
        (summary_offset_start_ < after_data_end || summary_offset_start_ > footer_offset_)) {
      throw McapError("the Footer's summary offset start is outside the summary", footer_offset_);
    }
    if (summary_crc_ != 0 && summary_start_ != 0) {
      const std::string_view covered =
          file_.substr(summary_start_, footer_offset_ + kRecordPrefixBytes + 16 - summary_start_);
      if (Crc32Of(covered) != summary_crc_) throw McapError("the summary fails its CRC (Footer)", footer_offset_);
    }
    RecordWalker walker(file_, after_data_end, footer_offset_, "summary");
    while (!walker.Done()) {
      const Record r = walker.Next();
      out_.has_summary = true;
      switch (r.op) {
        case Opcode::kSchema: {
          Schema s = ParseSchema(r);
          if (s.id == 0) break;
          if (schema_at_.count(s.id) == 0) AddSchema(s, r.offset);
          if (!(out_.schemas[schema_at_[s.id]] == s)) {
            throw McapError("the summary's Schema " + std::to_string(s.id) + " differs from the data section's",
                            r.offset);
          }
          break;
        }
        case Opcode::kChannel: {
          Channel c = ParseChannel(r);
          if (channel_at_.count(c.id) == 0) AddChannel(Channel(c), r.offset);
          if (!(out_.channels[channel_at_[c.id]] == c)) {
            throw McapError("the summary's Channel " + std::to_string(c.id) + " differs from the data section's",
                            r.offset);
          }
          break;
        }
        case Opcode::kStatistics:
          if (out_.statistics) throw McapError("a second Statistics record", r.offset);
          out_.statistics = ParseStatistics(r);
          break;
        case Opcode::kChunkIndex: {
          ByteReader in(r.content, ContentOffset(r), "Chunk Index");
          in.U64();
          in.U64();
          const std::uint64_t chunk_offset = in.U64();
          if (chunk_offsets_.count(chunk_offset) == 0) {
            throw McapError("a Chunk Index points at byte " + std::to_string(chunk_offset) + ", where no Chunk starts",
                            r.offset);
          }
          ++out_.chunk_indexes;
          break;
        }
        case Opcode::kSummaryOffset: {
          ByteReader in(r.content, ContentOffset(r), "Summary Offset");
          in.U8();
          const std::uint64_t start = in.U64();
          const std::uint64_t length = in.U64();
          if (start < after_data_end || start > footer_offset_ || length > footer_offset_ - start) {
            throw McapError("a Summary Offset points outside the summary", r.offset);
          }
          break;
        }
        case Opcode::kHeader:
        case Opcode::kFooter:
        case Opcode::kMessage:
        case Opcode::kChunk:
        case Opcode::kMessageIndex:
        case Opcode::kDataEnd:
          throw McapError("record " + Hex(static_cast<std::uint8_t>(r.op)) + " does not belong in the summary",
                          r.offset);
        default:
          break;  // attachment and metadata indexes, later versions' records
      }
    }
  }

  void CheckSummaryAgrees() {
    if (out_.chunk_indexes != 0 && out_.chunk_indexes != out_.chunks) {
      throw McapError("the summary indexes " + std::to_string(out_.chunk_indexes) + " chunks, the file has " +
                      std::to_string(out_.chunks));
    }
    if (!out_.statistics) return;
    const Statistics& s = *out_.statistics;
    if (s.message_count != out_.messages.size()) {
      throw McapError("the Statistics count " + std::to_string(s.message_count) + " messages, the file has " +
                      std::to_string(out_.messages.size()));
    }
    if (!s.channel_message_counts.empty()) {
      std::map<std::uint16_t, std::uint64_t> counted;
      for (const Message& m : out_.messages) ++counted[m.channel_id];
      for (auto& [id, n] : counted) {
        const auto it = s.channel_message_counts.find(id);
        const std::uint64_t said = it == s.channel_message_counts.end() ? 0 : it->second;
        if (said != n) {
          throw McapError("the Statistics count " + std::to_string(said) + " messages on channel " +
                          std::to_string(id) + ", the file has " + std::to_string(n));
        }
      }
    }
  }

  void AddSchema(Schema s, std::uint64_t offset) {
    if (s.id == 0) return;  // invalid; readers ignore it
    const auto it = schema_at_.find(s.id);
    if (it != schema_at_.end()) {
      if (!(out_.schemas[it->second] == s)) {
        throw McapError("two different Schema records with id " + std::to_string(s.id), offset);
      }
      return;
    }
    schema_at_[s.id] = out_.schemas.size();
    out_.schemas.push_back(std::move(s));
  }

  void AddChannel(Channel c, std::uint64_t offset) {
    if (c.schema_id != 0 && schema_at_.count(c.schema_id) == 0) {
      throw McapError(
          "Channel " + c.topic + " names schema " + std::to_string(c.schema_id) + ", which no earlier Schema defines",
          offset);
    }
    const auto it = channel_at_.find(c.id);
    if (it != channel_at_.end()) {
      if (!(out_.channels[it->second] == c)) {
        throw McapError("two different Channel records with id " + std::to_string(c.id), offset);
      }
      return;
    }
    channel_at_[c.id] = out_.channels.size();
    out_.channels.push_back(std::move(c));
  }

  std::string_view file_;
  McapFile out_;
  std::uint64_t footer_offset_ = 0;
  std::uint64_t summary_start_ = 0, summary_offset_start_ = 0;
  std::uint32_t summary_crc_ = 0;
  std::map<std::uint16_t, std::size_t> schema_at_, channel_at_;  // id -> index in out_
  std::set<std::uint64_t> chunk_offsets_;
};

}  // namespace

const Channel* McapFile::FindChannel(std::uint16_t id) const {
  for (const Channel& c : channels) {
    if (c.id == id) return &c;
  }
  return nullptr;
}

const Schema* McapFile::FindSchema(std::uint16_t id) const {
  for (const Schema& s : schemas) {
    if (s.id == id) return &s;
  }
  return nullptr;
}

McapFile ReadMcap(std::string_view bytes) { return Reader(bytes).Read(); }

McapFile ReadMcapFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw McapError("cannot read " + path + " (missing or unreadable)");
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw McapError("cannot read " + path);
  try {
    return ReadMcap(bytes);
  } catch (const McapError& e) {
    throw e.In(path);
  }
}

}  // namespace haptex::mcap
