#pragma once
// Builds a service's Health message from its loops, counters and latencies. Register everything
// at start-up; Build() then reuses the message and does not allocate.

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "haptex/v1/health.pb.h"
#include "libs/runtime/latency_histogram.h"
#include "libs/runtime/loop_stats.h"

namespace haptex::runtime {

/// One latency distribution as Health reports it.
struct LatencySummary {
  std::uint64_t samples = 0;
  double p50_us = 0, p99_us = 0, max_us = 0;
};

class HealthReporter final {
 public:
  using CounterId = std::size_t;
  /// Called at every Build; must not allocate.
  using LatencySource = std::function<LatencySummary()>;

  explicit HealthReporter(std::string service);

  /// The loop's statistics are read at every Build; the pointer must outlive the reporter.
  void AddLoop(const LoopStats* loop);
  void AddLatency(std::string name, const LatencyHistogram* histogram);
  /// A latency kept elsewhere (e.g. a core's own tracker).
  void AddLatency(std::string name, LatencySource source);
  CounterId AddCounter(std::string name);
  /// One counter per reason 1..N-1 of an enum whose 0 means "none" (drop reasons, frame errors),
  /// each named `prefix` + name_of(reason); element 0 is unused.
  template <class Reason, std::size_t N, class NameOf>
  std::array<CounterId, N> AddCounterPerReason(std::string_view prefix, NameOf name_of) {
    std::array<CounterId, N> ids{};
    for (std::size_t r = 1; r < N; ++r) {
      ids[r] = AddCounter(std::string(prefix) + std::string(name_of(static_cast<Reason>(r))));
    }
    return ids;
  }

  void SetCounter(CounterId id, std::uint64_t value) { counter_values_[id] = value; }
  void SetState(v1::Health::State state) { state_ = state; }
  /// Keeps the message's capacity when the text fits (ReserveLastError beforehand lets a loop set it
  /// without allocating).
  void SetLastError(std::string_view text) { health_.mutable_last_error()->assign(text.data(), text.size()); }
  void ReserveLastError(std::size_t bytes) { health_.mutable_last_error()->reserve(bytes); }
  /// The resumes after a cut the device bridge reports; sized by the service once, written in place.
  google::protobuf::RepeatedPtrField<v1::ForceResume>* mutable_resumes() { return health_.mutable_resumes(); }

  const v1::Health& Build(double uptime_s);

 private:
  std::vector<const LoopStats*> loops_;
  std::vector<LatencySource> latencies_;
  std::vector<std::uint64_t> counter_values_;
  v1::Health::State state_ = v1::Health::STATE_STARTING;
  v1::Health health_;
};

}  // namespace haptex::runtime
