#pragma once
// Reading a run's summary.json in tests: parsed by protobuf's JSON parser (a reader independent
// of launch/json_writer), with lookups that fail the test, not crash it, on a missing key.

#include <google/protobuf/struct.pb.h>
#include <google/protobuf/util/json_util.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <iostream>
#include <string>

namespace haptex::testing {

inline google::protobuf::Struct ParseJson(const std::string& text) {
  google::protobuf::Struct json;
  const auto status = google::protobuf::util::JsonStringToMessage(text, &json);
  EXPECT_TRUE(status.ok()) << status.message();
  return json;
}

inline const google::protobuf::Value& At(const google::protobuf::Struct& object, const std::string& key) {
  static const google::protobuf::Value kNone;
  const auto it = object.fields().find(key);
  EXPECT_NE(it, object.fields().end()) << key;
  return it == object.fields().end() ? kNone : it->second;
}

inline double Number(const google::protobuf::Struct& object, const std::string& key) {
  return At(object, key).number_value();
}

inline const google::protobuf::Struct& Object(const google::protobuf::Struct& object, const std::string& key) {
  return At(object, key).struct_value();
}

/// The entry of `services` named `name` (empty when there is none, with a failure).
inline google::protobuf::Struct ServiceSummary(const google::protobuf::Struct& summary, const std::string& name) {
  for (const auto& s : At(summary, "services").list_value().values()) {
    const auto& fields = s.struct_value().fields();
    const auto it = fields.find("name");
    if (it != fields.end() && it->second.string_value() == name) return s.struct_value();
  }
  ADD_FAILURE() << "no service " << name << " in summary.json";
  return {};
}

/// Whatever paused the host during a run: every resume after a cut the bridge reported (its
/// summary.json entry `bridge`) gave at most max(1.1 x held, held + 0.3 N) (docs/stalls.md), or
/// ended the contact. Returns how many resumes the bound held down.
inline int ExpectResumesWithinTheirBound(const google::protobuf::Struct& bridge) {
  int limited = 0;
  if (!bridge.fields().count("resumes")) return limited;  // no cut finished its resume
  for (const auto& v : bridge.fields().at("resumes").list_value().values()) {
    const google::protobuf::Struct& r = v.struct_value();
    const double held_N = Number(r, "held_n"), peak_N = Number(r, "peak_n");
    std::cout << "[measured] resume after " << At(r, "cause").string_value() << ": held " << held_N << " N, peak "
              << peak_N << " N" << (At(r, "ended").bool_value() ? " (contact ended)" : "") << "\n";
    if (!At(r, "ended").bool_value()) {
      EXPECT_LE(peak_N, std::max(1.1 * held_N, held_N + 0.3) + 1e-6);
    }
    if (At(r, "limited").bool_value()) ++limited;
  }
  return limited;
}

}  // namespace haptex::testing
