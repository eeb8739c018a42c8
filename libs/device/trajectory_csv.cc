#include "libs/device/trajectory_csv.h"

#include <array>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace haptex::device {
namespace {

[[noreturn]] void Fail(std::size_t line, const std::string& what) {
  throw std::invalid_argument("line " + std::to_string(line) + ": " + what);
}

std::string_view Trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

double ParseNumber(std::string_view field, std::size_t line, std::size_t column) {
  field = Trim(field);
  double value = 0.0;
  const char* end = field.data() + field.size();
  const auto [ptr, ec] = std::from_chars(field.data(), end, value);
  if (field.empty() || ec != std::errc() || ptr != end) {
    Fail(line, "field " + std::to_string(column + 1) + " is not a number: '" + std::string(field) + "'");
  }
  if (!std::isfinite(value)) {
    Fail(line, "field " + std::to_string(column + 1) + " is not finite: '" + std::string(field) + "'");
  }
  return value;
}

}  // namespace

std::vector<TrajectorySample> ParseTrajectoryCsv(std::string_view text) {
  std::vector<TrajectorySample> samples;
  bool header_seen = false;
  std::size_t line_number = 0;
  while (!text.empty()) {
    const std::size_t eol = text.find('\n');
    std::string_view line = Trim(text.substr(0, eol));
    text = eol == std::string_view::npos ? std::string_view{} : text.substr(eol + 1);
    ++line_number;
    if (line.empty() || line.front() == '#') continue;

    if (!header_seen) {
      if (line != kTrajectoryCsvHeader) {
        Fail(line_number,
             "expected header '" + std::string(kTrajectoryCsvHeader) + "', got '" + std::string(line) + "'");
      }
      header_seen = true;
      continue;
    }

    std::array<double, 7> v{};
    std::size_t fields = 0;
    std::string_view rest = line;
    while (true) {
      const std::size_t comma = rest.find(',');
      const std::string_view field = rest.substr(0, comma);
      if (fields < v.size()) v[fields] = ParseNumber(field, line_number, fields);
      ++fields;
      if (comma == std::string_view::npos) break;
      rest = rest.substr(comma + 1);
    }
    if (fields != v.size()) {
      Fail(line_number, "expected 7 fields, got " + std::to_string(fields));
    }
    TrajectorySample s;
    s.t_s = v[0];
    s.thumb_D_m = {v[1], v[2], v[3]};
    s.index_D_m = {v[4], v[5], v[6]};
    if (!samples.empty() && !(s.t_s > samples.back().t_s)) {
      Fail(line_number, "t_s must increase strictly (" + std::to_string(s.t_s) + " after " +
                            std::to_string(samples.back().t_s) + ")");
    }
    samples.push_back(s);
  }
  if (!header_seen) throw std::invalid_argument("trajectory CSV is empty (no header)");
  if (samples.size() < 2) {
    throw std::invalid_argument("trajectory CSV needs at least 2 samples, got " + std::to_string(samples.size()));
  }
  return samples;
}

std::vector<TrajectorySample> LoadTrajectoryCsv(const std::string& path) {
  // a device (/dev/zero) or a runaway file would be read until memory runs out
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error)) {
    throw std::invalid_argument(path + ": the trajectory CSV must be a regular file");
  }
  if (std::filesystem::file_size(path, error) > kMaxTrajectoryCsvBytes || error) {
    throw std::invalid_argument(path + ": the trajectory CSV has more than " +
                                std::to_string(kMaxTrajectoryCsvBytes >> 20) + " MB");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::invalid_argument(path + ": cannot open trajectory CSV");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  try {
    return ParseTrajectoryCsv(buffer.str());
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(path + ": " + e.what());
  }
}

}  // namespace haptex::device
