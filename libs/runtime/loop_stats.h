#pragma once
// What a periodic loop measures about itself: ticks, overruns, period and compute time.

#include <cstdint>
#include <string>

#include "haptex/v1/health.pb.h"
#include "libs/runtime/latency_histogram.h"

namespace haptex::runtime {

struct LoopStats {
  std::string name;
  double target_rate_hz = 0.0;
  std::uint64_t ticks = 0;
  std::uint64_t overruns = 0;  // cycles skipped because a tick started a period or more late
  LatencyHistogram period;     // start-to-start time between ticks
  LatencyHistogram compute;    // time inside the tick

  /// Writes the statistics into a Health LoopStats message (no allocation once the name is set).
  void FillProto(v1::LoopStats* out) const;
};

}  // namespace haptex::runtime
