#pragma once
// Protobuf text-format files with errors that point at file:line:column, for scenes and fabrics.

#include <cstddef>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <google/protobuf/message.h>
#include <google/protobuf/text_format.h>

namespace haptex::scene {

/// One problem in a text file; line and column are 1-based.
struct TextIssue {
  int line = 1;
  int column = 1;
  std::string message;
};

/// A file that cannot be used; what() lists every issue as "file:line:column: message".
class TextProtoError : public std::runtime_error {
 public:
  TextProtoError(std::string file, std::vector<TextIssue> issues);
  const std::string& file() const { return file_; }
  const std::vector<TextIssue>& issues() const { return issues_; }

 private:
  std::string file_;
  std::vector<TextIssue> issues_;
};

/// A parsed message and where each of its fields was written.
struct ParsedText {
  std::unique_ptr<google::protobuf::TextFormat::ParseInfoTree> locations;
};

/// Parses `text` into *message; throws TextProtoError (named `file`) on syntax errors, unknown
/// fields or bad values. The returned tree locates fields for later semantic errors.
ParsedText ParseTextProto(std::string_view text, const std::string& file, google::protobuf::Message* message);

/// The largest scene, fabric or key file read: a scene is a few kB, and the cap refuses a device
/// such as /dev/zero, or a runaway file, before anything is read.
inline constexpr std::size_t kMaxTextFileBytes = std::size_t{1} << 20;

/// The whole of a regular file of at most `max_bytes`. A missing or unreadable file, anything but a
/// regular file (a device, pipe, socket or folder) and a larger file are a TextProtoError at 1:1
/// that says which, before more than max_bytes + 1 bytes are read.
std::string ReadTextFile(const std::string& path, std::size_t max_bytes = kMaxTextFileBytes);

/// Reads (ReadTextFile) and parses a file; a file that cannot be read is a TextProtoError at 1:1.
ParsedText ParseTextProtoFile(const std::string& path, google::protobuf::Message* message);

/// Finds where fields were written, for semantic errors. A field that was left out is located at
/// its nearest written ancestor.
class FieldLocator {
 public:
  FieldLocator(const google::protobuf::TextFormat::ParseInfoTree* tree, TextIssue fallback)
      : tree_(tree), fallback_(std::move(fallback)) {}

  /// The locator of a nested message field (index for repeated fields, -1 otherwise).
  FieldLocator Nested(const google::protobuf::Message& parent, std::string_view field, int index = -1) const;
  /// An issue at the given field of `parent`.
  TextIssue At(const google::protobuf::Message& parent, std::string_view field, int index, std::string message) const;
  TextIssue Here(std::string message) const;

 private:
  const google::protobuf::TextFormat::ParseInfoTree* tree_;
  TextIssue fallback_;
};

}  // namespace haptex::scene
