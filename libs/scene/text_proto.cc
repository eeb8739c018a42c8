#include "libs/scene/text_proto.h"

#include <google/protobuf/io/tokenizer.h>
#include <google/protobuf/io/zero_copy_stream_impl_lite.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstring>

namespace haptex::scene {
namespace {

std::string Describe(const std::string& file, const std::vector<TextIssue>& issues) {
  std::string text;
  for (const TextIssue& issue : issues) {
    if (!text.empty()) text += "\n";
    text += file + ":" + std::to_string(issue.line) + ":" + std::to_string(issue.column) + ": " + issue.message;
  }
  return text;
}

class CollectIssues : public google::protobuf::io::ErrorCollector {
 public:
  explicit CollectIssues(std::vector<TextIssue>* issues) : issues_(issues) {}
  void AddError(int line, google::protobuf::io::ColumnNumber column, const std::string& message) override {
    issues_->push_back({line + 1, column + 1, message});
  }
  void AddWarning(int line, google::protobuf::io::ColumnNumber column, const std::string& message) override {
    issues_->push_back({line + 1, column + 1, "warning: " + message});
  }

 private:
  std::vector<TextIssue>* issues_;
};

const google::protobuf::FieldDescriptor* FieldOf(const google::protobuf::Message& parent, std::string_view field) {
  const auto* descriptor = parent.GetDescriptor()->FindFieldByName(std::string(field));
  if (descriptor == nullptr) {
    throw std::logic_error("no field '" + std::string(field) + "' in " + parent.GetDescriptor()->full_name());
  }
  return descriptor;
}

}  // namespace

TextProtoError::TextProtoError(std::string file, std::vector<TextIssue> issues)
    : std::runtime_error(Describe(file, issues)), file_(std::move(file)), issues_(std::move(issues)) {}

ParsedText ParseTextProto(std::string_view text, const std::string& file, google::protobuf::Message* message) {
  ParsedText parsed;
  parsed.locations = std::make_unique<google::protobuf::TextFormat::ParseInfoTree>();
  std::vector<TextIssue> issues;
  CollectIssues collector(&issues);
  google::protobuf::TextFormat::Parser parser;
  parser.RecordErrorsTo(&collector);
  parser.WriteLocationsTo(parsed.locations.get());
  google::protobuf::io::ArrayInputStream input(text.data(), static_cast<int>(text.size()));
  const bool ok = parser.Parse(&input, message);
  // Warnings alone do not refuse a file, but errors do.
  if (!ok) {
    if (issues.empty()) issues.push_back({1, 1, "cannot parse " + message->GetTypeName()});
    throw TextProtoError(file, std::move(issues));
  }
  return parsed;
}

std::string ReadTextFile(const std::string& path, std::size_t max_bytes) {
  // O_NONBLOCK: opening a FIFO must not wait for a writer; it is refused below like any non-file
  const int fd = open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) throw TextProtoError(path, {{1, 1, std::string("cannot open the file: ") + std::strerror(errno)}});
  const auto fail = [&](const std::string& what) {
    close(fd);
    throw TextProtoError(path, {{1, 1, what}});
  };
  struct stat info {};
  if (fstat(fd, &info) != 0) fail(std::string("cannot read the file: ") + std::strerror(errno));
  if (!S_ISREG(info.st_mode)) fail("not a regular file (a device, pipe, socket or folder): refused");
  const auto too_large = [&](std::uint64_t bytes) {
    fail("the file has " + std::to_string(bytes) + " bytes, over the " + std::to_string(max_bytes) +
         " bytes a scene, fabric or key file may have");
  };
  if (static_cast<std::uint64_t>(info.st_size) > max_bytes) too_large(static_cast<std::uint64_t>(info.st_size));
  std::string text;
  text.resize(max_bytes + 1);  // one more: a file that grew since fstat is still caught
  std::size_t got = 0;
  while (got < text.size()) {
    const ssize_t n = read(fd, text.data() + got, text.size() - got);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) fail(std::string("cannot read the file: ") + std::strerror(errno));
    if (n == 0) break;
    got += static_cast<std::size_t>(n);
  }
  if (got > max_bytes) too_large(got);
  close(fd);
  text.resize(got);
  return text;
}

ParsedText ParseTextProtoFile(const std::string& path, google::protobuf::Message* message) {
  return ParseTextProto(ReadTextFile(path), path, message);
}

FieldLocator FieldLocator::Nested(const google::protobuf::Message& parent, std::string_view field, int index) const {
  const TextIssue here = At(parent, field, index, "");
  const google::protobuf::TextFormat::ParseInfoTree* nested =
      tree_ ? tree_->GetTreeForNested(FieldOf(parent, field), index) : nullptr;
  return FieldLocator(nested, here);
}

TextIssue FieldLocator::At(const google::protobuf::Message& parent, std::string_view field, int index,
                           std::string message) const {
  TextIssue issue = fallback_;
  if (tree_ != nullptr) {
    const auto location = tree_->GetLocation(FieldOf(parent, field), index);
    if (location.line >= 0) {
      issue.line = location.line + 1;
      issue.column = location.column + 1;
    }
  }
  issue.message = std::move(message);
  return issue;
}

TextIssue FieldLocator::Here(std::string message) const {
  TextIssue issue = fallback_;
  issue.message = std::move(message);
  return issue;
}

}  // namespace haptex::scene
