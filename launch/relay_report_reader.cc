#include "launch/relay_report_reader.h"

#include <google/protobuf/struct.pb.h>
#include <google/protobuf/util/json_util.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace haptex::launch {
namespace {

namespace pb = google::protobuf;

// protobuf's JSON reader into a Struct is the JSON parser at hand; its numbers are doubles, exact
// for counts up to 2^53.
const pb::Value& Member(const pb::Struct& object, const std::string& key, const std::string& where) {
  const auto it = object.fields().find(key);
  if (it == object.fields().end()) throw std::runtime_error("relay report: no " + where + key);
  return it->second;
}

const pb::Struct& Object(const pb::Struct& object, const std::string& key, const std::string& where) {
  const pb::Value& value = Member(object, key, where);
  if (!value.has_struct_value()) throw std::runtime_error("relay report: " + where + key + " is not an object");
  return value.struct_value();
}

// JSON has no NaN: the relay writes null for a delay it has no sample of.
double Number(const pb::Struct& object, const std::string& key, const std::string& where) {
  const pb::Value& value = Member(object, key, where);
  if (value.has_null_value()) return std::numeric_limits<double>::quiet_NaN();
  if (value.kind_case() != pb::Value::kNumberValue) {
    throw std::runtime_error("relay report: " + where + key + " is not a number");
  }
  return value.number_value();
}

std::uint64_t Count(const pb::Struct& object, const std::string& key, const std::string& where) {
  const double value = Number(object, key, where);
  if (!(value >= 0.0) || value != std::floor(value)) {
    throw std::runtime_error("relay report: " + where + key + " is not a count");
  }
  return static_cast<std::uint64_t>(value);
}

RelayDirectionResult Direction(const pb::Struct& report, const std::string& name) {
  const pb::Struct& d = Object(report, name, "");
  const std::string where = name + ".";
  RelayDirectionResult r;
  r.received = Count(d, "received", where);
  r.forwarded = Count(d, "forwarded", where);
  r.duplicated = Count(d, "duplicated", where);
  r.held_back = Count(d, "held_back", where);
  r.reordered = Count(d, "reordered", where);
  r.dropped_total = Count(d, "dropped_total", where);
  r.in_flight = Count(d, "in_flight", where);
  for (const auto& [cause, value] : Object(d, "dropped", where).fields()) {
    r.dropped[cause] = Count(Object(d, "dropped", where), cause, where + "dropped.");
  }
  const pb::Struct& delay = Object(d, "delay_ms", where);
  r.delay_p50_ms = Number(delay, "p50", where + "delay_ms.");
  r.delay_p99_ms = Number(delay, "p99", where + "delay_ms.");
  r.delay_max_ms = Number(delay, "max", where + "delay_ms.");
  r.delay_mean_ms = Number(delay, "mean", where + "delay_ms.");
  return r;
}

}  // namespace

RelayResult ParseRelayReport(const std::string& json) {
  pb::Struct report;
  const auto status = pb::util::JsonStringToMessage(json, &report);
  if (!status.ok()) throw std::runtime_error("relay report is not JSON: " + std::string(status.message()));
  RelayResult result;
  result.duration_s = Number(report, "duration_s", "");
  result.forward = Direction(report, "forward");
  result.back = Direction(report, "back");
  return result;
}

RelayResult ReadRelayReport(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("no relay report " + path);
  std::stringstream text;
  text << in.rdbuf();
  try {
    return ParseRelayReport(text.str());
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(std::string(e.what()) + " [" + path + "]");
  }
}

}  // namespace haptex::launch
