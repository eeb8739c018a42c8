#include "launch/recording.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <stdexcept>

namespace haptex::launch {

Recording ReadRecording(const std::string& path) {
  std::error_code error;
  if (std::filesystem::exists(path, error) && !std::filesystem::is_regular_file(path, error)) {
    throw std::runtime_error("recording " + path + " is not a regular file");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read recording " + path);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  Recording recording;
  recording.path = path;
  std::size_t at = 0;
  while (at < bytes.size()) {
    // varint length
    std::uint64_t length = 0;
    int shift = 0;
    bool complete = false;
    while (at < bytes.size() && shift < 64) {
      const auto byte = static_cast<std::uint8_t>(bytes[at++]);
      length |= static_cast<std::uint64_t>(byte & 0x7f) << shift;
      shift += 7;
      if ((byte & 0x80) == 0) {
        complete = true;
        break;
      }
    }
    if (!complete || length > bytes.size() - at) {
      recording.truncated = true;
      break;
    }
    v1::Envelope envelope;
    if (envelope.ParseFromArray(bytes.data() + at, static_cast<int>(length))) {
      recording.envelopes.push_back(std::move(envelope));
    } else {
      ++recording.unparsable;
    }
    at += length;
  }
  return recording;
}

std::vector<Recording> ReadRecordings(const std::string& folder) {
  std::vector<std::string> paths;
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(folder, error)) {
    if (entry.path().extension() == ".pb" && entry.is_regular_file(error)) paths.push_back(entry.path().string());
  }
  std::sort(paths.begin(), paths.end());
  std::vector<Recording> recordings;
  for (const std::string& path : paths) recordings.push_back(ReadRecording(path));
  return recordings;
}

std::int64_t EarliestSendTimeNs(const std::vector<Recording>& recordings) {
  std::int64_t earliest = std::numeric_limits<std::int64_t>::max();
  for (const Recording& r : recordings) {
    for (const v1::Envelope& e : r.envelopes) earliest = std::min(earliest, e.send_time_ns());
  }
  return earliest == std::numeric_limits<std::int64_t>::max() ? 0 : earliest;
}

}  // namespace haptex::launch
