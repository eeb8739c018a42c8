#include "libs/scene/field_checks.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>

namespace haptex::scene {
namespace {

using google::protobuf::FieldDescriptor;
using google::protobuf::Message;
using google::protobuf::Reflection;

std::string Number(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

void CheckNumber(const Message& m, const FieldDescriptor& f, int index, double value, const std::string& path,
                 const FieldLocator& where, std::vector<TextIssue>* issues) {
  if (std::isfinite(value)) return;
  issues->push_back(where.At(m, f.name(), index, path + " must be a finite number, got " + Number(value)));
}

void CheckEnum(const Message& m, const FieldDescriptor& f, int index, int value, const std::string& path,
               const FieldLocator& where, std::vector<TextIssue>* issues) {
  if (f.enum_type()->FindValueByNumber(value) != nullptr) return;
  std::string known;
  for (int i = 0; i < f.enum_type()->value_count(); ++i) {
    if (f.enum_type()->value(i)->number() == 0) continue;  // UNSPECIFIED: not a choice to offer
    known += (known.empty() ? "" : ", ") + f.enum_type()->value(i)->name();
  }
  issues->push_back(where.At(
      m, f.name(), index,
      path + ": " + std::to_string(value) + " is not a value of " + f.enum_type()->name() + " (" + known + ")"));
}

void CheckString(const Message& m, const FieldDescriptor& f, int index, const std::string& value,
                 const std::string& path, std::size_t max_bytes, const FieldLocator& where,
                 std::vector<TextIssue>* issues) {
  std::string problem;
  if (value.size() > max_bytes) {
    problem = " has " + std::to_string(value.size()) + " bytes, at most " + std::to_string(max_bytes);
  } else if (!IsValidUtf8(value)) {
    problem = " is not valid UTF-8";
  } else if (!IsWellFormedText(value)) {
    problem = " holds a control character (only tab and newline may appear)";
  }
  if (!problem.empty()) issues->push_back(where.At(m, f.name(), index, path + problem));
}

void CheckMessage(const Message& m, const std::string& prefix, const FieldLocator& where,
                  std::vector<TextIssue>* issues, const std::map<std::string, std::size_t>& max_bytes) {
  const Reflection& r = *m.GetReflection();
  std::vector<const FieldDescriptor*> fields;
  r.ListFields(m, &fields);
  for (const FieldDescriptor* f : fields) {
    const std::string path = prefix + f->name();
    const int count = f->is_repeated() ? r.FieldSize(m, f) : 1;
    for (int i = 0; i < count; ++i) {
      const int index = f->is_repeated() ? i : -1;
      const std::string item = f->is_repeated() ? path + "[" + std::to_string(i) + "]" : path;
      switch (f->cpp_type()) {
        case FieldDescriptor::CPPTYPE_DOUBLE:
          CheckNumber(m, *f, index, f->is_repeated() ? r.GetRepeatedDouble(m, f, i) : r.GetDouble(m, f), item, where,
                      issues);
          break;
        case FieldDescriptor::CPPTYPE_FLOAT:
          CheckNumber(m, *f, index, f->is_repeated() ? r.GetRepeatedFloat(m, f, i) : r.GetFloat(m, f), item, where,
                      issues);
          break;
        case FieldDescriptor::CPPTYPE_ENUM:
          CheckEnum(m, *f, index, f->is_repeated() ? r.GetRepeatedEnumValue(m, f, i) : r.GetEnumValue(m, f), item,
                    where, issues);
          break;
        case FieldDescriptor::CPPTYPE_STRING:
          if (f->type() == FieldDescriptor::TYPE_STRING) {
            const auto bound = max_bytes.find(std::string(f->full_name()));
            CheckString(m, *f, index, f->is_repeated() ? r.GetRepeatedString(m, f, i) : r.GetString(m, f), item,
                        bound == max_bytes.end() ? kMaxStringBytes : std::min(bound->second, kMaxStringBytes), where,
                        issues);
          }
          break;
        case FieldDescriptor::CPPTYPE_MESSAGE:
          CheckMessage(f->is_repeated() ? r.GetRepeatedMessage(m, f, i) : r.GetMessage(m, f), item + ".",
                       where.Nested(m, f->name(), index), issues, max_bytes);
          break;
        default:
          break;  // integers and booleans: every value is a number; ranges are the loaders' rules
      }
    }
  }
}

}  // namespace

void CheckEveryField(const Message& message, const FieldLocator& where, std::vector<TextIssue>* issues,
                     const std::map<std::string, std::size_t>& max_bytes) {
  CheckMessage(message, "", where, issues, max_bytes);
}

bool IsWellFormedText(std::string_view text) {
  if (text.size() > kMaxStringBytes || !IsValidUtf8(text)) return false;
  return std::none_of(text.begin(), text.end(), [](char c) {
    const auto u = static_cast<unsigned char>(c);
    return (u < 0x20 && c != '\t' && c != '\n') || u == 0x7f;
  });
}

void SortByLocation(std::vector<TextIssue>* issues) {
  std::stable_sort(issues->begin(), issues->end(), [](const TextIssue& a, const TextIssue& b) {
    return a.line != b.line ? a.line < b.line : a.column < b.column;
  });
}

bool IsValidUtf8(std::string_view text) {
  std::size_t i = 0;
  while (i < text.size()) {
    const auto c = static_cast<unsigned char>(text[i]);
    std::size_t length = 0;
    std::uint32_t code = 0;
    if (c < 0x80) {
      ++i;
      continue;
    } else if ((c & 0xE0) == 0xC0) {
      length = 2;
      code = c & 0x1F;
    } else if ((c & 0xF0) == 0xE0) {
      length = 3;
      code = c & 0x0F;
    } else if ((c & 0xF8) == 0xF0) {
      length = 4;
      code = c & 0x07;
    } else {
      return false;
    }
    if (i + length > text.size()) return false;
    for (std::size_t k = 1; k < length; ++k) {
      const auto next = static_cast<unsigned char>(text[i + k]);
      if ((next & 0xC0) != 0x80) return false;
      code = (code << 6) | (next & 0x3F);
    }
    const std::uint32_t smallest[] = {0, 0, 0x80, 0x800, 0x10000};
    if (code < smallest[length] || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF)) return false;
    i += length;
  }
  return true;
}

bool IsPlainName(std::string_view text, std::size_t max_bytes) {
  if (text.empty() || text.size() > max_bytes || text.front() == '.') return false;
  for (const char c : text) {
    const bool ok =
        (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-' || c == '.';
    if (!ok) return false;
  }
  return true;
}

}  // namespace haptex::scene
