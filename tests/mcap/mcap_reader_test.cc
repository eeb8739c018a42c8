// Hostile files: missing, empty, not MCAP, cut at every byte, every byte flipped, lengths that
// point past the end. Each is a McapError saying what is wrong; nothing crashes or reads past the end.
#include "libs/mcap/mcap_reader.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include "libs/mcap/mcap_writer.h"

namespace haptex::mcap {
namespace {

using ::testing::HasSubstr;

std::string SmallFile(bool crcs = true) {
  WriterOptions options;
  options.chunk_size = 60;
  options.crcs = crcs;
  std::ostringstream out;
  McapWriter w(out, options);
  const auto s = w.AddSchema("test.S", "protobuf", "descriptor");
  const auto a = w.AddChannel(s, "/a/s", "protobuf", {{"key", "value"}});
  const auto b = w.AddChannel(s, "/b/s", "protobuf");
  w.AddMessage({a, 1, 10, 10, "first"});
  w.AddMessage({b, 1, 20, 20, "second"});
  w.AddMessage({a, 2, 30, 30, "third"});
  w.Finish();
  return out.str();
}

std::string ErrorOf(const std::string& bytes) {
  try {
    ReadMcap(bytes);
  } catch (const McapError& e) {
    return e.what();
  }
  return "";
}

TEST(McapReaderTest, TheSmallFileReads) {
  const McapFile f = ReadMcap(SmallFile());
  EXPECT_EQ(f.messages.size(), 3u);
  EXPECT_GE(f.chunks, 2u);
}

TEST(McapReaderTest, AMissingFileIsAClearError) {
  try {
    ReadMcapFile(::testing::TempDir() + "/no_such_file.mcap");
    FAIL() << "no error";
  } catch (const McapError& e) {
    EXPECT_THAT(e.what(), HasSubstr("cannot read"));
    EXPECT_THAT(e.what(), HasSubstr("no_such_file.mcap"));
  }
}

TEST(McapReaderTest, AnEmptyOrForeignFileIsNotMcap) {
  EXPECT_THAT(ErrorOf(""), HasSubstr("not an MCAP file"));
  EXPECT_THAT(ErrorOf("hello, world"), HasSubstr("not an MCAP file"));
  // a length-delimited protobuf recording, as services write them
  EXPECT_THAT(ErrorOf(std::string("\x05\x08\x01\x10\x02\x18", 6)), HasSubstr("not an MCAP file"));
  std::string wrong_version = SmallFile();
  wrong_version[5] = '1';
  EXPECT_THAT(ErrorOf(wrong_version), HasSubstr("not an MCAP file"));
}

TEST(McapReaderTest, AFileCutAtEveryByteIsAnErrorNamingAnOffset) {
  const std::string file = SmallFile();
  for (std::size_t size = 0; size < file.size(); ++size) {
    const std::string error = ErrorOf(file.substr(0, size));
    EXPECT_THAT(error, HasSubstr("MCAP: ")) << "cut to " << size << " bytes read without an error";
    if (size >= 8) {
      EXPECT_THAT(error, HasSubstr("at byte")) << error;
    }
  }
}

TEST(McapReaderTest, AFileWithSomethingAppendedIsAnError) {
  EXPECT_THAT(ErrorOf(SmallFile() + "x"), HasSubstr("does not end with the MCAP magic"));
}

// Every byte flipped, with and without CRCs (without them the damage reaches the record parsers):
// each is read or refused with a McapError, never anything else.
TEST(McapReaderTest, EveryFlippedByteIsReadOrRefusedCleanly) {
  for (bool crcs : {true, false}) {
    const std::string file = SmallFile(crcs);
    for (std::size_t at = 0; at < file.size(); ++at) {
      for (std::uint8_t mask : {0x01, 0x80, 0xFF}) {
        std::string damaged = file;
        damaged[at] = static_cast<char>(damaged[at] ^ mask);
        try {
          ReadMcap(damaged);
          EXPECT_FALSE(crcs && at >= 8 && at < file.size() - 8 - 29)
              << "a flipped byte at " << at << " passed the CRCs";
        } catch (const McapError&) {
        } catch (const std::exception& e) {
          ADD_FAILURE() << "byte " << at << " ^ " << int(mask) << ": not a McapError: " << e.what();
        }
      }
    }
  }
}

// Every 8-byte record length (and every 4-byte field length inside the records) set to huge values.
TEST(McapReaderTest, LengthsPastTheEndAreRefused) {
  const std::string file = SmallFile(false);
  int refused = 0;
  for (std::size_t at = 8; at + 8 <= file.size() - 8; ++at) {
    for (std::uint64_t huge : {0xFFFFFFFFFFFFFFFFull, 0x7FFFFFFFFFFFFFFFull, 0xFFFFFFFFull, 0x100000000ull}) {
      std::string damaged = file;
      for (int i = 0; i < 8; ++i) damaged[at + i] = static_cast<char>((huge >> (8 * i)) & 0xFF);
      try {
        ReadMcap(damaged);
      } catch (const McapError&) {
        ++refused;
      }
    }
  }
  EXPECT_GT(refused, 0);
  std::string header_too_long = file;
  header_too_long[9] = '\x7F';  // the Header's content length
  EXPECT_THAT(ErrorOf(header_too_long), HasSubstr("bytes long, only"));
}

TEST(McapReaderTest, ACorruptedChunkFailsItsCrc) {
  std::string file = SmallFile();
  const auto at = file.find("second");
  ASSERT_NE(at, std::string::npos);
  file[at] = 'S';
  EXPECT_THAT(ErrorOf(file), HasSubstr("CRC"));
}

TEST(McapReaderTest, AMessageOnAnUnknownChannelIsRefused) {
  WriterOptions options;
  options.crcs = false;
  std::ostringstream out;
  McapWriter w(out, options);
  const auto c = w.AddChannel(0, "/a", "json");
  w.AddMessage({c, 0, 1, 1, "{}"});
  w.Finish();
  std::string file = out.str();
  // the message's channel_id, after the Channel record in the chunk: change 1 to 9
  const auto at = file.find("{}");
  ASSERT_NE(at, std::string::npos);
  const std::size_t channel_id_at = at - 22;
  ASSERT_EQ(file[channel_id_at], '\x01');
  file[channel_id_at] = '\x09';
  EXPECT_THAT(ErrorOf(file), HasSubstr("channel 9, which no earlier Channel defines"));
}

TEST(McapReaderTest, ReadsAFileFromDisk) {
  const std::string path = ::testing::TempDir() + "/mcap_reader_test.mcap";
  std::ofstream(path, std::ios::binary) << SmallFile();
  EXPECT_EQ(ReadMcapFile(path).messages.size(), 3u);
  std::ofstream(path, std::ios::binary | std::ios::trunc) << SmallFile().substr(0, 100);
  try {
    ReadMcapFile(path);
    FAIL() << "no error";
  } catch (const McapError& e) {
    EXPECT_THAT(e.what(), HasSubstr(path));
  }
}

}  // namespace
}  // namespace haptex::mcap
