#include "libs/scene/text_proto.h"

#include <google/protobuf/io/tokenizer.h>
#include <google/protobuf/io/zero_copy_stream_impl_lite.h>

#include <fstream>
#include <sstream>

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

ParsedText ParseTextProtoFile(const std::string& path, google::protobuf::Message* message) {
  std::ifstream in(path);
  if (!in) throw TextProtoError(path, {{1, 1, "cannot open the file"}});
  std::stringstream buffer;
  buffer << in.rdbuf();
  return ParseTextProto(buffer.str(), path, message);
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
