#pragma once
// The one clock every loop and latency measurement in a process uses (CLOCK_MONOTONIC).

#include <chrono>
#include <cstdint>

namespace haptex::runtime {

inline std::int64_t SteadyNowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

}  // namespace haptex::runtime
