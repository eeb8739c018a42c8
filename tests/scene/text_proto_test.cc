#include "libs/scene/text_proto.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "haptex/v1/scene.pb.h"

namespace haptex::scene {
namespace {

TextProtoError ParseError(const std::string& text) {
  v1::Scene scene;
  try {
    ParseTextProto(text, "s.textproto", &scene);
  } catch (const TextProtoError& e) {
    return e;
  }
  ADD_FAILURE() << "parsed: " << text;
  return TextProtoError("", {});
}

TEST(TextProtoTest, UnknownFieldIsLocated) {
  const TextProtoError e = ParseError("name: \"x\"\ncloth {\n  widht_m: 0.2\n}\n");
  ASSERT_EQ(e.issues().size(), 1u);
  EXPECT_EQ(e.issues()[0].line, 3);
  // protobuf points just past the unknown name; either way the column lies on that name
  EXPECT_GE(e.issues()[0].column, 3);
  EXPECT_LE(e.issues()[0].column, 10);
  EXPECT_NE(std::string(e.what()).find("s.textproto:3:"), std::string::npos) << e.what();
  EXPECT_NE(std::string(e.what()).find("widht_m"), std::string::npos);
}

TEST(TextProtoTest, SyntaxAndTypeErrorsAreLocated) {
  EXPECT_EQ(ParseError("cloth { width_m: 0.2\n").issues()[0].line, 2);  // unclosed brace at EOF
  const TextProtoError bad_enum = ParseError("\n\ncloth { mounting: HANGING }");
  EXPECT_EQ(bad_enum.issues()[0].line, 3);
  EXPECT_NE(std::string(bad_enum.what()).find("HANGING"), std::string::npos);
  EXPECT_EQ(ParseError("duration_s: \"long\"").issues()[0].line, 1);
}

TEST(TextProtoTest, MissingFileIsAnError) {
  v1::Scene scene;
  try {
    ParseTextProtoFile("/nonexistent/scene.textproto", &scene);
    FAIL();
  } catch (const TextProtoError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/scene.textproto:1:1: cannot open"), std::string::npos);
  }
}

// A scene path of /dev/zero read until memory ran out: the size and kind are checked before reading.
TEST(TextProtoTest, FilesAreCappedBeforeTheyAreRead) {
  const auto refused = [](const std::string& path) -> std::string {
    try {
      ReadTextFile(path);
    } catch (const TextProtoError& e) {
      EXPECT_EQ(e.issues().size(), 1u);
      EXPECT_EQ(e.issues()[0].line, 1);
      return e.issues()[0].message;
    }
    ADD_FAILURE() << "read " << path;
    return "";
  };
  EXPECT_NE(refused("/dev/zero").find("not a regular file"), std::string::npos);
  EXPECT_NE(refused("/dev/urandom").find("not a regular file"), std::string::npos);
  const std::string dir = ::testing::TempDir() + "/haptex_text_proto_caps_" + std::to_string(getpid());
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  EXPECT_NE(refused(dir).find("not a regular file"), std::string::npos);
  const std::string fifo = dir + "/fifo";
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_NE(refused(fifo).find("not a regular file"), std::string::npos) << "and opening it did not wait";
  const std::string big = dir + "/big.textproto";
  std::ofstream(big) << std::string(kMaxTextFileBytes + 1, '#');
  EXPECT_NE(refused(big).find("the file has 1048577 bytes, over the 1048576"), std::string::npos);
  const std::string full = dir + "/full.textproto";
  std::ofstream(full) << std::string(kMaxTextFileBytes, '#');
  EXPECT_EQ(ReadTextFile(full).size(), kMaxTextFileBytes);
  EXPECT_NE(refused(full + ".missing").find("cannot open"), std::string::npos);
  EXPECT_THROW(ReadTextFile(full, 100), TextProtoError);
  std::filesystem::remove_all(dir);
}

TEST(TextProtoTest, LocatorFindsNestedAndRepeatedFields) {
  v1::Scene scene;
  const ParsedText parsed =
      ParseTextProto("name: \"x\"\nfingers { finger: FINGER_THUMB }\nfingers {\n  radius_m: 0.5\n}\n", "s", &scene);
  const FieldLocator root(parsed.locations.get(), {1, 1, ""});
  const FieldLocator second = root.Nested(scene, "fingers", 1);
  const TextIssue at_radius = second.At(scene.fingers(1), "radius_m", -1, "too big");
  EXPECT_EQ(at_radius.line, 4);
  EXPECT_EQ(at_radius.column, 3);
  // A field that was left out is located at its parent.
  const TextIssue missing = second.At(scene.fingers(1), "finger", -1, "missing");
  EXPECT_EQ(missing.line, 3);
}

}  // namespace
}  // namespace haptex::scene
