#pragma once
// Protobuf text-format files with errors that point at file:line:column, for scenes and fabrics.

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

/// Reads and parses a file; a missing or unreadable file is a TextProtoError at 1:1.
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
