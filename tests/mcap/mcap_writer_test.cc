// The writer's files read back as written, and are laid out as the MCAP specification says
// (https://mcap.dev/spec): checked here byte by byte, independently of the reader.
#include "libs/mcap/mcap_writer.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "libs/mcap/crc32.h"
#include "libs/mcap/mcap_reader.h"

namespace haptex::mcap {
namespace {

std::uint64_t Le(const std::string& b, std::size_t at, int bytes) {
  std::uint64_t v = 0;
  for (int i = 0; i < bytes; ++i) v |= static_cast<std::uint64_t>(static_cast<std::uint8_t>(b.at(at + i))) << (8 * i);
  return v;
}

struct RawRecord {
  std::uint8_t op;
  std::size_t offset;
  std::size_t length;  // content
};

// every top-level record between the leading magic and the trailing one
std::vector<RawRecord> Records(const std::string& file) {
  std::vector<RawRecord> out;
  std::size_t at = 8;
  while (at < file.size() - 8) {
    const RawRecord r{static_cast<std::uint8_t>(file.at(at)), at, static_cast<std::size_t>(Le(file, at + 1, 8))};
    out.push_back(r);
    at += 9 + r.length;
  }
  EXPECT_EQ(at, file.size() - 8);
  return out;
}

Message Msg(std::uint16_t channel, std::uint64_t t, std::string data, std::uint32_t sequence = 0) {
  return {channel, sequence, t, t + 1, std::move(data)};
}

// three channels on two schemas, 60 messages, small chunks
std::string ThreeChannelFile(std::size_t chunk_size, bool crcs = true) {
  std::ostringstream out;
  McapWriter w(out, {.profile = "", .library = "haptex", .chunk_size = chunk_size, .crcs = crcs});
  const auto a = w.AddSchema("test.A", "protobuf", std::string("schema\0A", 8));
  const auto b = w.AddSchema("test.B", "protobuf", "schema B");
  const auto c1 = w.AddChannel(a, "/one/a", "protobuf", {{"k", "v"}});
  const auto c2 = w.AddChannel(a, "/two/a", "protobuf");
  const auto c3 = w.AddChannel(b, "/one/b", "protobuf");
  for (int i = 0; i < 20; ++i) {
    w.AddMessage(Msg(c1, 1000 + 10 * i, "one-a " + std::to_string(i), i));
    w.AddMessage(Msg(c2, 1005 + 10 * i, std::string(i, '\0'), i));
    if (i % 2 == 0) w.AddMessage(Msg(c3, 1003 + 10 * i, "one-b " + std::to_string(i), i));
  }
  w.AddMessage(Msg(c1, 500, "early"));  // out of order: readers sort by log time
  w.Finish();
  return out.str();
}

TEST(McapWriterTest, RoundTripsSchemasChannelsAndMessagesInLogTimeOrder) {
  const McapFile f = ReadMcap(ThreeChannelFile(200));
  EXPECT_EQ(f.profile, "");
  EXPECT_EQ(f.library, "haptex");
  ASSERT_EQ(f.schemas.size(), 2u);
  EXPECT_EQ(f.schemas[0], (Schema{1, "test.A", "protobuf", std::string("schema\0A", 8)}));
  EXPECT_EQ(f.schemas[1], (Schema{2, "test.B", "protobuf", "schema B"}));
  ASSERT_EQ(f.channels.size(), 3u);
  EXPECT_EQ(f.channels[0], (Channel{1, 1, "/one/a", "protobuf", {{"k", "v"}}}));
  EXPECT_EQ(f.channels[2].topic, "/one/b");
  EXPECT_EQ(f.channels[2].schema_id, 2);

  ASSERT_EQ(f.messages.size(), 51u);
  EXPECT_EQ(f.messages.front(), Msg(1, 500, "early"));
  for (std::size_t i = 1; i < f.messages.size(); ++i) EXPECT_LE(f.messages[i - 1].log_time, f.messages[i].log_time);
  EXPECT_EQ(f.messages[1], Msg(1, 1000, "one-a 0", 0));
  EXPECT_EQ(f.messages[2], Msg(3, 1003, "one-b 0", 0));
  EXPECT_EQ(f.messages[3], Msg(2, 1005, "", 0));
  EXPECT_EQ(f.messages.back(), Msg(2, 1195, std::string(19, '\0'), 19));
}

TEST(McapWriterTest, ChunksSplitBySizeAndTheSummaryCountsThem) {
  const std::string small = ThreeChannelFile(200);
  const McapFile f = ReadMcap(small);
  EXPECT_GT(f.chunks, 5u);
  EXPECT_TRUE(f.has_summary);
  EXPECT_EQ(f.chunk_indexes, f.chunks);
  ASSERT_TRUE(f.statistics.has_value());
  EXPECT_EQ(f.statistics->message_count, 51u);
  EXPECT_EQ(f.statistics->schema_count, 2);
  EXPECT_EQ(f.statistics->channel_count, 3u);
  EXPECT_EQ(f.statistics->chunk_count, f.chunks);
  EXPECT_EQ(f.statistics->message_start_time, 500u);
  EXPECT_EQ(f.statistics->message_end_time, 1195u);
  EXPECT_EQ(f.statistics->channel_message_counts, (std::map<std::uint16_t, std::uint64_t>{{1, 21}, {2, 20}, {3, 10}}));

  // one big chunk holds the same
  const McapFile one = ReadMcap(ThreeChannelFile(1 << 20));
  EXPECT_EQ(one.chunks, 1u);
  EXPECT_EQ(one.messages, f.messages);
}

// The layout itself: magic, Header, Chunks each followed by Message Indexes, Data End with the CRC of
// all before it, Schemas, Channels, Statistics, Chunk Indexes, Summary Offsets, Footer, magic.
TEST(McapWriterTest, LaysOutTheFileAsTheSpecificationSays) {
  const std::string file = ThreeChannelFile(200);
  ASSERT_EQ(file.substr(0, 8), std::string("\x89MCAP0\r\n", 8));
  ASSERT_EQ(file.substr(file.size() - 8), std::string("\x89MCAP0\r\n", 8));
  const auto records = Records(file);
  ASSERT_GE(records.size(), 4u);
  EXPECT_EQ(records.front().op, 0x01);
  // Header: profile "" and library "haptex"
  EXPECT_EQ(Le(file, records[0].offset + 9, 4), 0u);
  EXPECT_EQ(Le(file, records[0].offset + 13, 4), 6u);
  EXPECT_EQ(file.substr(records[0].offset + 17, 6), "haptex");

  std::size_t i = 1;
  std::vector<std::size_t> chunk_offsets;
  while (records[i].op == 0x06) {
    const RawRecord& chunk = records[i];
    chunk_offsets.push_back(chunk.offset);
    const std::size_t c = chunk.offset + 9;
    const std::uint64_t uncompressed_size = Le(file, c + 16, 8);
    const std::uint32_t crc = static_cast<std::uint32_t>(Le(file, c + 24, 4));
    EXPECT_EQ(Le(file, c + 28, 4), 0u) << "compression is \"\"";
    EXPECT_EQ(Le(file, c + 32, 8), uncompressed_size);
    EXPECT_EQ(Crc32Of(file.substr(c + 40, uncompressed_size)), crc);
    ++i;
    ASSERT_EQ(records[i].op, 0x07) << "a Message Index follows every chunk";
    while (records[i].op == 0x07) ++i;
  }
  EXPECT_GT(chunk_offsets.size(), 5u);
  ASSERT_EQ(records[i].op, 0x0F);
  EXPECT_EQ(Le(file, records[i].offset + 9, 4), Crc32Of(file.substr(0, records[i].offset)));
  const std::size_t summary_start = records[i].offset + 9 + records[i].length;
  ++i;
  std::vector<std::uint8_t> summary_ops;
  std::vector<std::size_t> chunk_index_targets;
  for (; records[i].op != 0x0E; ++i) {
    summary_ops.push_back(records[i].op);
    if (records[i].op == 0x08) chunk_index_targets.push_back(Le(file, records[i].offset + 9 + 16, 8));
  }
  std::vector<std::uint8_t> expected{0x03, 0x03, 0x04, 0x04, 0x04, 0x0B};
  expected.insert(expected.end(), chunk_offsets.size(), 0x08);
  EXPECT_EQ(summary_ops, expected);
  EXPECT_EQ(chunk_index_targets, chunk_offsets);
  const std::size_t summary_offset_start = records[i].offset;
  // one Summary Offset per group, each pointing at records of its opcode
  std::vector<std::uint8_t> groups;
  for (; records[i].op == 0x0E; ++i) {
    const std::size_t c = records[i].offset + 9;
    groups.push_back(static_cast<std::uint8_t>(file[c]));
    EXPECT_EQ(static_cast<std::uint8_t>(file.at(Le(file, c + 1, 8))), groups.back());
  }
  EXPECT_EQ(groups, (std::vector<std::uint8_t>{0x03, 0x04, 0x0B, 0x08}));
  ASSERT_EQ(records[i].op, 0x02);
  ASSERT_EQ(i + 1, records.size());
  const std::size_t footer = records[i].offset;
  EXPECT_EQ(Le(file, footer + 9, 8), summary_start);
  EXPECT_EQ(Le(file, footer + 17, 8), summary_offset_start);
  EXPECT_EQ(Le(file, footer + 25, 4), Crc32Of(file.substr(summary_start, footer + 25 - summary_start)));
}

TEST(McapWriterTest, AFileWithoutMessagesIsValid) {
  std::ostringstream out;
  McapWriter w(out);
  w.Finish();
  const McapFile f = ReadMcap(out.str());
  EXPECT_TRUE(f.messages.empty());
  EXPECT_EQ(f.chunks, 0u);
  ASSERT_TRUE(f.statistics.has_value());
  EXPECT_EQ(f.statistics->message_count, 0u);
}

TEST(McapWriterTest, WritesEachChunkAsItClosesAndRefusesAFailedStream) {
  std::ostringstream out;
  McapWriter w(out, {.profile = "", .library = "haptex", .chunk_size = 100, .crcs = true});
  const auto c = w.AddChannel(0, "/a", "json");
  w.AddMessage(Msg(c, 1, std::string(200, 'x')));
  EXPECT_GT(out.str().size(), 200u);  // the chunk is in the stream before Finish()
  w.Finish();
  EXPECT_EQ(ReadMcap(out.str()).messages.size(), 1u);

  std::ofstream bad(::testing::TempDir() + "/no_such_folder/x.mcap");
  McapWriter failing(bad);
  EXPECT_THROW(failing.Finish(), McapError);
}

TEST(McapWriterTest, WithoutCrcsWritesZeroes) {
  const McapFile f = ReadMcap(ThreeChannelFile(200, false));
  EXPECT_EQ(f.messages.size(), 51u);
}

TEST(McapWriterTest, RefusesUnknownChannelsAndSchemas) {
  std::ostringstream out;
  McapWriter w(out);
  EXPECT_THROW(w.AddChannel(1, "/x", "protobuf"), McapError);
  const auto c = w.AddChannel(0, "/no_schema", "json");
  EXPECT_THROW(w.AddMessage(Msg(c + 1, 0, "")), McapError);
  w.AddMessage(Msg(c, 0, "{}"));
  w.Finish();
  EXPECT_THROW(w.AddMessage(Msg(c, 0, "")), McapError);
}

}  // namespace
}  // namespace haptex::mcap
