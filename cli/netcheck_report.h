#pragma once
// What `haptex netcheck probe` measures about a link, and its verdict for haptic use.

#include <cstdint>
#include <string>
#include <vector>

#include "libs/device/device_bridge.h"

namespace haptex::cli {

/// Verdict thresholds (docs/netcheck.md explains them; docs/remote.md has the measurements).
struct LinkVerdictLimits {
  double good_p99_us = 1000.0;  // a 1 kHz contact loop closes across the link as on one machine
  double good_loss = 0.001;
  /// The haptic link may cross: the bridge renders models up to device::DeviceBridgeConfig's
  /// max_model_age_s old and resumes after a slow spell below recover_fraction of it, so a p99
  /// under that never trips it.
  double usable_p99_us =
      1e6 * device::DeviceBridgeConfig{}.recover_fraction * device::DeviceBridgeConfig{}.max_model_age_s;
  double usable_loss = 0.10;  // the pinch held within 2 % at 10 % loss each way
  /// Only the global link may cross (remote_global): measured to a 200 ms round trip with 10 % loss
  /// each way, passive throughout, a pressing finger's force growing with the delay (docs/remote.md).
  double global_only_p99_us = 200e3;
  double global_only_loss = 0.10;
};

struct NetcheckReport {
  std::string target;
  double rate_hz = 0;
  double seconds = 0;
  std::uint64_t datagram_bytes = 0;
  std::uint64_t sent = 0;
  std::uint64_t send_failures = 0;
  std::uint64_t send_overruns = 0;  // probe cycles the sender could not keep
  std::uint64_t received = 0;       // distinct probes answered
  std::uint64_t lost = 0;
  std::uint64_t duplicates = 0;
  std::uint64_t reordered = 0;  // replies arriving after a later probe's reply
  std::uint64_t rejected = 0;   // datagrams the probe dropped (bad MAC, ...)
  double loss_fraction = 0;
  double rtt_min_us = 0, rtt_mean_us = 0, rtt_p50_us = 0, rtt_p99_us = 0, rtt_p999_us = 0, rtt_max_us = 0;
  double jitter_us = 0;  // mean |rtt(k) - rtt(k-1)| over consecutive answered probes
  std::string verdict;   // "good", "usable", "poor" or "unreachable"
  std::string advice;
};

/// Collects replies by probe sequence (1..capacity). Written by one receiver thread, read after.
class ProbeRecorder {
 public:
  explicit ProbeRecorder(std::size_t capacity);
  /// Records a reply; ignores sequences outside 1..capacity (counted as rejected).
  void OnReply(std::uint64_t probe_sequence, std::int64_t rtt_ns);
  void OnRejected(std::uint64_t count) { rejected_ += count; }
  /// Fills the counting and timing fields of *report for `sent` probes, and the verdict.
  void Summarise(std::uint64_t sent, const LinkVerdictLimits& limits, NetcheckReport* report) const;

 private:
  std::vector<std::int64_t> rtt_ns_;  // -1: no reply
  std::uint64_t duplicates_ = 0;
  std::uint64_t reordered_ = 0;
  std::uint64_t rejected_ = 0;
  std::uint64_t highest_ = 0;
};

/// Sets verdict and advice from the report's rtt_p99_us, loss_fraction and received.
void ClassifyLink(const LinkVerdictLimits& limits, NetcheckReport* report);

std::string ReportToJson(const NetcheckReport& report);
std::string ReportToText(const NetcheckReport& report);

}  // namespace haptex::cli
