#include "launch/impair_option.h"

#include <charconv>
#include <set>
#include <stdexcept>
#include <vector>

#include "launch/service_table.h"
#include "libs/scene/scene_network.h"

namespace haptex::launch {
namespace {

namespace pb = google::protobuf;

std::vector<std::string_view> Split(std::string_view text, char separator) {
  std::vector<std::string_view> parts;
  std::size_t start = 0;
  for (;;) {
    const std::size_t at = text.find(separator, start);
    parts.push_back(text.substr(start, at == std::string_view::npos ? at : at - start));
    if (at == std::string_view::npos) return parts;
    start = at + 1;
  }
}

[[noreturn]] void Refuse(std::string_view text, const std::string& what) {
  throw std::invalid_argument("--impair '" + std::string(text) + "': " + what);
}

std::string KnownServices() {
  std::string names;
  for (const ServiceSpec& spec : ServiceTable()) names += (names.empty() ? "" : ", ") + std::string(spec.name);
  return names;
}

// The fields a key may name: the link's values (not its ends or its directions' groups).
bool IsValueField(const pb::FieldDescriptor* field) {
  if (field == nullptr) return false;
  if (field->cpp_type() == pb::FieldDescriptor::CPPTYPE_MESSAGE) {
    return field->message_type() == v1::BurstLoss::descriptor();
  }
  return field->cpp_type() == pb::FieldDescriptor::CPPTYPE_DOUBLE ||
         field->cpp_type() == pb::FieldDescriptor::CPPTYPE_UINT64 ||
         field->cpp_type() == pb::FieldDescriptor::CPPTYPE_STRING;
}

std::string KnownKeys() {
  std::string keys;
  const pb::Descriptor* link = v1::LinkImpairment::descriptor();
  for (int i = 0; i < link->field_count(); ++i) {
    if (IsValueField(link->field(i))) keys += (keys.empty() ? "" : ", ") + link->field(i)->name();
  }
  return keys + "; forward.KEY or back.KEY for one direction";
}

double ParseDouble(std::string_view text, std::string_view key, std::string_view value) {
  double number = 0.0;
  const auto [end, error] = std::from_chars(value.data(), value.data() + value.size(), number);
  if (value.empty() || error != std::errc() || end != value.data() + value.size()) {
    Refuse(text, std::string(key) + ": '" + std::string(value) + "' is not a number");
  }
  return number;  // NaN and infinity are refused by the link checks, in their words
}

std::uint64_t ParseSeed(std::string_view text, std::string_view key, std::string_view value) {
  std::uint64_t seed = 0;
  const auto [end, error] = std::from_chars(value.data(), value.data() + value.size(), seed);
  if (value.empty() || error != std::errc() || end != value.data() + value.size()) {
    Refuse(text, std::string(key) + ": '" + std::string(value) + "' is not a whole number from 0 to 2^64 - 1");
  }
  return seed;
}

void SetBurst(std::string_view text, std::string_view key, std::string_view value, v1::BurstLoss* burst) {
  const std::vector<std::string_view> parts = Split(value, '/');
  if (parts.size() < 2 || parts.size() > 4) {
    Refuse(text, std::string(key) + ": expected P/R[/LOSS_BAD[/LOSS_GOOD]], got '" + std::string(value) + "'");
  }
  burst->set_p(ParseDouble(text, key, parts[0]));
  burst->set_r(ParseDouble(text, key, parts[1]));
  if (parts.size() > 2) burst->set_loss_bad(ParseDouble(text, key, parts[2]));
  if (parts.size() > 3) burst->set_loss_good(ParseDouble(text, key, parts[3]));
}

void SetKey(std::string_view text, std::string_view key, std::string_view value, v1::LinkImpairment* link) {
  pb::Message* message = link;
  std::string_view name = key;
  const std::size_t dot = key.find('.');
  if (dot != std::string_view::npos) {
    const std::string_view direction = key.substr(0, dot);
    if (direction == "forward") {
      message = link->mutable_forward();
    } else if (direction == "back") {
      message = link->mutable_back();
    } else {
      Refuse(text, "unknown key '" + std::string(key) + "' (keys: " + KnownKeys() + ")");
    }
    name = key.substr(dot + 1);
  }
  const pb::FieldDescriptor* field = message->GetDescriptor()->FindFieldByName(std::string(name));
  if (!IsValueField(field)) Refuse(text, "unknown key '" + std::string(key) + "' (keys: " + KnownKeys() + ")");
  if (value.empty()) Refuse(text, std::string(key) + " needs a value");
  const pb::Reflection* reflection = message->GetReflection();
  switch (field->cpp_type()) {
    case pb::FieldDescriptor::CPPTYPE_DOUBLE:
      reflection->SetDouble(message, field, ParseDouble(text, key, value));
      break;
    case pb::FieldDescriptor::CPPTYPE_UINT64:
      reflection->SetUInt64(message, field, ParseSeed(text, key, value));
      break;
    case pb::FieldDescriptor::CPPTYPE_STRING:
      reflection->SetString(message, field, std::string(value));
      break;
    default:
      SetBurst(text, key, value, static_cast<v1::BurstLoss*>(reflection->MutableMessage(message, field)));
      break;
  }
}

std::string BurstText(const v1::BurstLoss& burst) {
  std::string text = ExactNumber(burst.p()) + "/" + ExactNumber(burst.r());
  if (burst.has_loss_bad() || burst.loss_good() != 0.0) {
    text += "/" + ExactNumber(burst.has_loss_bad() ? burst.loss_bad() : 1.0);
    if (burst.loss_good() != 0.0) text += "/" + ExactNumber(burst.loss_good());
  }
  return text;
}

// Every value field `message` sets, in field order, as KEY=VALUE with `prefix` before the key.
void AppendValues(const pb::Message& message, const std::string& prefix, std::string* out) {
  std::vector<const pb::FieldDescriptor*> fields;
  message.GetReflection()->ListFields(message, &fields);
  const pb::Reflection* reflection = message.GetReflection();
  for (const pb::FieldDescriptor* field : fields) {
    if (!IsValueField(field)) continue;
    std::string value;
    switch (field->cpp_type()) {
      case pb::FieldDescriptor::CPPTYPE_DOUBLE:
        value = ExactNumber(reflection->GetDouble(message, field));
        break;
      case pb::FieldDescriptor::CPPTYPE_UINT64:
        value = std::to_string(reflection->GetUInt64(message, field));
        break;
      case pb::FieldDescriptor::CPPTYPE_STRING:
        value = reflection->GetString(message, field);
        break;
      default:
        value = BurstText(static_cast<const v1::BurstLoss&>(reflection->GetMessage(message, field)));
        break;
    }
    *out += (out->empty() ? "" : ",") + prefix + field->name() + "=" + value;
  }
}

}  // namespace

v1::LinkImpairment ParseImpairOption(std::string_view text) {
  const std::size_t colon = text.find(':');
  const std::string_view ends = text.substr(0, colon);
  const std::vector<std::string_view> services = Split(ends, '-');
  if (services.size() != 2 || services[0].empty() || services[1].empty()) {
    Refuse(text, "expected SERVICE-SERVICE[:KEY=VALUE,...], e.g. device_bridge-local_contact:rtt_ms=100,loss=0.05");
  }
  v1::LinkImpairment link;
  for (int i = 0; i < 2; ++i) {
    const ServiceSpec* spec = FindSpec(services[i]);
    if (spec == nullptr) {
      Refuse(text, "unknown service '" + std::string(services[i]) + "' (services: " + KnownServices() + ")");
    }
    if (i == 0) {
      link.set_a(spec->kind);
    } else {
      link.set_b(spec->kind);
    }
  }
  if (colon != std::string_view::npos && colon + 1 < text.size()) {
    std::set<std::string_view> seen;
    for (const std::string_view item : Split(text.substr(colon + 1), ',')) {
      const std::size_t equals = item.find('=');
      if (item.empty() || equals == std::string_view::npos || equals == 0) {
        Refuse(text, "expected KEY=VALUE, got '" + std::string(item) + "'");
      }
      const std::string_view key = item.substr(0, equals);
      if (!seen.insert(key).second) Refuse(text, std::string(key) + " is given twice");
      SetKey(text, key, item.substr(equals + 1), &link);
    }
  }
  const std::vector<scene::LinkIssue> issues = scene::CheckLinkValues(link);
  if (!issues.empty()) {
    std::string what;
    for (const scene::LinkIssue& issue : issues) what += (what.empty() ? "" : "; ") + issue.message;
    Refuse(text, what);
  }
  return link;
}

std::string ImpairmentText(const v1::LinkImpairment& link) {
  std::string text;
  AppendValues(link, "", &text);
  if (link.has_forward()) AppendValues(link.forward(), "forward.", &text);
  if (link.has_back()) AppendValues(link.back(), "back.", &text);
  return text;
}

std::string ExactNumber(double value) {
  char text[32];
  const auto [end, error] = std::to_chars(text, text + sizeof(text), value);
  return error == std::errc() ? std::string(text, end) : std::string("nan");
}

}  // namespace haptex::launch
