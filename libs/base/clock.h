#pragma once
// The one clock every loop, latency measurement and time stamp in a process uses: steady_clock,
// which is CLOCK_MONOTONIC on Linux (comparable across processes on one machine). Not for the pure
// cores (libs/textile, contact, tactile, device): time comes into them as `dt`.

#include <chrono>
#include <cstdint>

namespace haptex::base {

/// Now on CLOCK_MONOTONIC [ns].
inline std::int64_t SteadyNowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

}  // namespace haptex::base
