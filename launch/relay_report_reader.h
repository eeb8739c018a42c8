#pragma once
// What a relay achieved, read back from the JSON report `haptex relay --json` writes when it stops
// (docs/relay.md, "The report"), for summary.json's network section.

#include <cstdint>
#include <map>
#include <string>

namespace haptex::launch {

struct RelayDirectionResult {
  std::uint64_t received = 0;
  std::uint64_t forwarded = 0;
  std::uint64_t duplicated = 0;
  std::uint64_t held_back = 0;
  std::uint64_t reordered = 0;
  std::uint64_t dropped_total = 0;
  std::map<std::string, std::uint64_t> dropped;  // by cause: loss, burst_loss, queue_overflow, ...
  std::uint64_t in_flight = 0;
  // achieved delay from the kernel's receive stamp to the send; NaN when nothing was sent
  double delay_p50_ms = 0.0;
  double delay_p99_ms = 0.0;
  double delay_max_ms = 0.0;
  double delay_mean_ms = 0.0;
};

struct RelayResult {
  double duration_s = 0.0;
  RelayDirectionResult forward;  // the link's a -> b
  RelayDirectionResult back;     // b -> a
};

/// Parses a report's text. Throws std::runtime_error when it is not JSON or lacks a field.
RelayResult ParseRelayReport(const std::string& json);
/// Reads and parses the report at `path`; a missing file is a std::runtime_error too.
RelayResult ReadRelayReport(const std::string& path);

}  // namespace haptex::launch
